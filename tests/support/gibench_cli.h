#pragma once
// The `gibench` executable as a user runs it, for the tests of what it prints and exits with.

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace gibench::test {

struct Outcome {
    int exitCode;        // -1: killed by a signal
    std::string output;  // stdout and stderr together
};

// Runs `gibench ARGUMENTS` through the shell (the arguments are shell words), `redirection`
// appended, and returns its exit code and stdout.
inline Outcome runThroughShell(const std::string& arguments, const std::string& redirection) {
    FILE* pipe = popen((std::string(GIBENCH_EXE) + " " + arguments + " " + redirection).c_str(), "r");
    std::string output;
    std::array<char, 512> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe)) output += buffer.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// stdout and stderr together.
inline Outcome gibench(const std::string& arguments) { return runThroughShell(arguments, "2>&1"); }

// stdout and stderr apart, for what a script reading stdout gets; stderr passes through
// `stderrFile`.
struct SeparateOutcome {
    int exitCode;  // -1: killed by a signal
    std::string out, err;
};
inline SeparateOutcome gibenchSeparately(const std::string& arguments, const std::filesystem::path& stderrFile) {
    const Outcome outcome = runThroughShell(arguments, "2>'" + stderrFile.string() + "'");
    std::ostringstream err;
    err << std::ifstream(stderrFile).rdbuf();
    return {outcome.exitCode, outcome.output, err.str()};
}

}  // namespace gibench::test
