#include "experiments/manifest.h"

#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <sys/utsname.h>
#include <thread>
#include <unistd.h>

namespace gibench {

static std::string commandOutput(const std::string& command) {
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
    if (!pipe) return "";
    std::string out;
    std::array<char, 256> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe.get())) out += buffer.data();
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}

Json gitInfo() {
    const std::string dir = GIBENCH_SOURCE_DIR;
    const std::string commit = commandOutput("git -C '" + dir + "' rev-parse HEAD 2>/dev/null");
    if (commit.empty()) return {{"commit", "unknown"}, {"dirty", nullptr}};
    const std::string status = commandOutput("git -C '" + dir + "' status --porcelain --untracked-files=no 2>/dev/null");
    return {{"commit", commit}, {"dirty", !status.empty()}};
}

Json machineInfo() {
    Json info;
    std::array<char, 256> host{};
    gethostname(host.data(), host.size() - 1);
    info["host"] = host.data();
    info["logical_cores"] = std::thread::hardware_concurrency();
    std::ifstream cpu("/proc/cpuinfo");
    for (std::string line; std::getline(cpu, line);)
        if (line.rfind("model name", 0) == 0) {
            info["cpu"] = line.substr(line.find(':') + 2);
            break;
        }
    std::ifstream mem("/proc/meminfo");
    for (std::string line; std::getline(mem, line);)
        if (line.rfind("MemTotal:", 0) == 0) {
            info["memory_gib"] = std::stod(line.substr(9)) / (1024.0 * 1024.0);
            break;
        }
    utsname u{};
    if (uname(&u) == 0) info["os"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
    return info;
}

std::string utcNow() {
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&now, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

}  // namespace gibench
