#include "core/util/progress.h"

#include <cstdio>
#include <unistd.h>

namespace gibench {

Progress::Progress(std::string label, uint64_t total, bool enabled)
    : m_label(std::move(label)),
      m_total(total > 0 ? total : 1),
      m_enabled(enabled),
      m_terminal(isatty(fileno(stderr)) != 0),
      m_start(std::chrono::steady_clock::now()),
      m_lastDraw(m_start) {}

Progress::~Progress() { finish(); }

void Progress::advance(uint64_t units) {
    if (!m_enabled) return;
    const uint64_t done = m_done.fetch_add(units) + units;
    const auto now = std::chrono::steady_clock::now();
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return;  // another thread is drawing; skipping one update is fine
    const int decile = int(10 * done / m_total);
    const bool due = m_terminal ? now - m_lastDraw > std::chrono::milliseconds(200) : decile > m_lastDecile;
    if (!due) return;
    m_lastDraw = now;
    m_lastDecile = decile;
    draw(done, false);
}

void Progress::finish() {
    if (!m_enabled || m_finished) return;
    std::lock_guard lock(m_mutex);
    m_finished = true;
    draw(m_done.load(), true);
}

void Progress::draw(uint64_t done, bool final) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    const double fraction = double(done) / double(m_total);
    char line[256];
    if (final) {
        std::snprintf(line, sizeof line, "%s: done in %.1f s", m_label.c_str(), elapsed);
    } else {
        const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
        std::snprintf(line, sizeof line, "%s: %5.1f %%  elapsed %.1f s  ETA %.1f s", m_label.c_str(), 100.0 * fraction, elapsed, eta);
    }
    if (m_terminal)
        std::fprintf(stderr, "\r%-78s%s", line, final ? "\n" : "");
    else
        std::fprintf(stderr, "%s\n", line);
    std::fflush(stderr);
}

}  // namespace gibench
