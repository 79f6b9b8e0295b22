#include "experiments/child_process.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace gibench {

std::filesystem::path currentExecutable() { return std::filesystem::read_symlink("/proc/self/exe"); }

pid_t spawnChild(const std::vector<std::string>& argv, const std::filesystem::path& log) {
    const int out = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (out < 0) throw std::runtime_error(log.string() + ": cannot open for writing: " + std::strerror(errno));
    // Everything the child needs is made before fork: between fork and exec only async-signal-safe
    // calls are allowed, since other threads of this process may hold locks.
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent) _exit(137);  // the parent died before prctl took effect
        dup2(out, STDOUT_FILENO);
        dup2(out, STDERR_FILENO);
        execv(args[0], args.data());
        _exit(127);
    }
    const int forkError = errno;
    close(out);
    if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(forkError));
    return pid;
}

ChildExit waitForChild(bool poll) {
    int status = 0;
    pid_t pid;
    do {
        pid = waitpid(-1, &status, poll ? WNOHANG : 0);
    } while (pid < 0 && errno == EINTR);
    if (pid < 0) throw std::runtime_error(std::string("waiting for a run: ") + std::strerror(errno));
    if (pid == 0) return {};
    return {pid, WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)};
}

}  // namespace gibench
