#include "experiments/child_process.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace gibench {

namespace {

// A wait status as a shell's $?.
int exitCodeOf(int status) { return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0); }

// Reads both pipes until both are closed: reading one to its end first would deadlock on a child
// blocked writing a full other pipe.
void drain(int outFd, int errFd, CapturedRun& captured) {
    pollfd fds[2] = {{outFd, POLLIN, 0}, {errFd, POLLIN, 0}};
    std::string* sinks[2] = {&captured.out, &captured.err};
    int open = 2;
    while (open > 0) {
        if (poll(fds, 2, -1) < 0) {
            if (errno == EINTR) continue;
            break;
        }
        for (int i = 0; i < 2; ++i) {
            if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            char buffer[4096];
            const ssize_t n = read(fds[i].fd, buffer, sizeof buffer);
            if (n > 0) {
                sinks[i]->append(buffer, std::size_t(n));
            } else if (n == 0 || errno != EINTR) {
                close(fds[i].fd);
                fds[i].fd = -1;
                --open;
            }
        }
    }
    for (const pollfd& f : fds)
        if (f.fd >= 0) close(f.fd);
}

}  // namespace

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
    return {pid, exitCodeOf(status)};
}

std::optional<CapturedRun> runAndCapture(const std::vector<std::string>& argv) {
    int outPipe[2], errPipe[2];
    if (pipe2(outPipe, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    if (pipe2(errPipe, O_CLOEXEC) != 0) {
        const int error = errno;
        close(outPipe[0]);
        close(outPipe[1]);
        throw std::runtime_error(std::string("pipe: ") + std::strerror(error));
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, outPipe[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, errPipe[1], STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(outPipe[1]);
    close(errPipe[1]);
    if (spawned != 0) {
        close(outPipe[0]);
        close(errPipe[0]);
        if (spawned == ENOENT || spawned == EACCES) return std::nullopt;
        throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(spawned));
    }
    CapturedRun captured;
    drain(outPipe[0], errPipe[0], captured);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    captured.exitCode = exitCodeOf(status);
    return captured;
}

}  // namespace gibench
