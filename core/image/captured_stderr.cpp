#include "core/image/captured_stderr.h"

#include <cstdio>
#include <iostream>
#include <unistd.h>

namespace gibench {

CapturedStderr::CapturedStderr() {
    std::fflush(stderr);
    std::cerr.flush();
    FILE* file = std::tmpfile();
    if (!file) return;
    m_capture = dup(fileno(file));
    std::fclose(file);  // the temporary file lives on through m_capture and is deleted with it
    if (m_capture < 0) return;
    m_saved = dup(STDERR_FILENO);
    if (m_saved < 0 || dup2(m_capture, STDERR_FILENO) < 0) {
        if (m_saved >= 0) close(m_saved);
        m_saved = -1;
    }
}

CapturedStderr::~CapturedStderr() {
    if (m_saved >= 0) {
        std::fflush(stderr);
        std::cerr.flush();
        dup2(m_saved, STDERR_FILENO);
        close(m_saved);
    }
    if (m_capture >= 0) close(m_capture);
}

std::string CapturedStderr::text() const {
    if (m_saved < 0) return "";
    std::fflush(stderr);
    std::cerr.flush();
    std::string out;
    char buffer[512];
    for (off_t offset = 0;;) {
        const ssize_t n = pread(m_capture, buffer, sizeof buffer, offset);
        if (n <= 0) break;
        out.append(buffer, std::size_t(n));
        offset += n;
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
}

}  // namespace gibench
