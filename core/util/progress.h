#pragma once
// A progress line with an ETA on stderr: redrawn in place on a terminal, a line every ~10 %
// otherwise (logs, CI). Thread-safe.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace gibench {

class Progress {
public:
    // `enabled` false makes every call a no-op (tests, library use).
    Progress(std::string label, uint64_t total, bool enabled);
    ~Progress();
    void advance(uint64_t units = 1);
    void finish();

private:
    void draw(uint64_t done, bool final);

    std::string m_label;
    uint64_t m_total;
    bool m_enabled;
    bool m_terminal;
    std::atomic<uint64_t> m_done{0};
    std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_lastDraw;
    int m_lastDecile = -1;
    bool m_finished = false;
};

}  // namespace gibench
