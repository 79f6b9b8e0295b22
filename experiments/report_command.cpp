#include "experiments/report_command.h"

#include "core/util/error.h"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace gibench {

int runReport(const std::filesystem::path& resultsDir, const std::optional<std::filesystem::path>& out) {
    if (!std::filesystem::is_directory(resultsDir))
        throw InputError(resultsDir.string() + ": not a folder (expected a results root, an experiment folder or a run)");
    std::vector<std::string> args = {kAnalysisPython, std::string(GIBENCH_SOURCE_DIR) + "/analysis/report.py", resultsDir.string()};
    if (out) args.insert(args.end(), {"--out", out->string()});
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);

    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, kAnalysisPython, nullptr, nullptr, argv.data(), environ);
    if (spawned != 0) throw std::runtime_error(std::string("cannot start ") + kAnalysisPython + ": " + std::strerror(spawned));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error(std::string("waiting for ") + kAnalysisPython + ": " + std::strerror(errno));
    return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : WEXITSTATUS(status);
}

}  // namespace gibench
