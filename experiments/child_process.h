#pragma once
// Child processes of gibench: the local sweep runs each point as `gibench sweep FILE --index I`,
// so that a run that crashes or leaks cannot take the others down, and a SIGKILL of the sweep
// stops its runs too: a child dies with its parent (PR_SET_PDEATHSIG) rather than racing a
// resumed sweep for the same run folder. The Slurm backend runs the cluster's commands (sbatch,
// squeue) and reads their replies.

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gibench {

// This program's executable, for starting more of itself.
std::filesystem::path currentExecutable();

// Starts argv[0] with the arguments (no shell), its stdout and stderr appended to `log`;
// std::runtime_error when the log cannot be opened or the process cannot be created. A program
// that cannot be executed exits 127 in the child, like a shell's.
pid_t spawnChild(const std::vector<std::string>& argv, const std::filesystem::path& log);

struct ChildExit {
    pid_t pid = 0;   // 0: no child has ended yet (a poll)
    int exitCode = 0;  // a child killed by a signal: 128 + its number, like a shell's $?
};

// Runs argv[0] (looked up on PATH) with this process's environment, waits for it and returns
// what it wrote; nullopt when it is not installed (cannot be found or executed).
struct CapturedRun {
    int exitCode = 0;  // killed by a signal: 128 + its number
    std::string out, err;
};
std::optional<CapturedRun> runAndCapture(const std::vector<std::string>& argv);

// The next child to end: waits for one, or with `poll` returns {0, 0} at once when none has.
ChildExit waitForChild(bool poll);

}  // namespace gibench
