#pragma once
// Wall time per pipeline stage, per frame: what the error-vs-time curves are built from.

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace gibench {

class StageTimer {
public:
    // Adds `seconds` to `stage` in the current frame (stages keep their first-seen order).
    void add(const std::string& stage, double seconds) {
        for (auto& [name, total] : m_stages)
            if (name == stage) {
                total += seconds;
                return;
            }
        m_stages.emplace_back(stage, seconds);
    }
    const std::vector<std::pair<std::string, double>>& stages() const { return m_stages; }
    void clear() { m_stages.clear(); }

private:
    std::vector<std::pair<std::string, double>> m_stages;
};

// Times its own lifetime into one stage. Not thread-safe: stages are timed on the calling thread
// around parallel loops, not inside them.
class ScopedStage {
public:
    ScopedStage(StageTimer& timer, std::string stage)
        : m_timer(timer), m_stage(std::move(stage)), m_start(std::chrono::steady_clock::now()) {}
    ~ScopedStage() {
        m_timer.add(m_stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count());
    }
    ScopedStage(const ScopedStage&) = delete;
    ScopedStage& operator=(const ScopedStage&) = delete;

private:
    StageTimer& m_timer;
    std::string m_stage;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace gibench
