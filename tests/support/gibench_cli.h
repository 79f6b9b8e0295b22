#pragma once
// The `gibench` executable as a user runs it, for the tests of what it prints and exits with.

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace gibench::test {

struct Outcome {
    int exitCode;        // -1: killed by a signal
    std::string output;  // stdout and stderr together
};

// Runs `gibench ARGUMENTS` through the shell (the arguments are shell words) and waits for it.
inline Outcome gibench(const std::string& arguments) {
    FILE* pipe = popen((std::string(GIBENCH_EXE) + " " + arguments + " 2>&1").c_str(), "r");
    std::string output;
    std::array<char, 512> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe)) output += buffer.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace gibench::test
