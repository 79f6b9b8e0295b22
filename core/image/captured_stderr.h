#pragma once
// The C libraries under OpenImageIO (libpng, OpenEXR) print their own complaints to the process's
// standard error before OpenImageIO reports the failure. gibench's error already names the file
// and the reason; a stray "libpng error: ..." line before it is noise a user cannot place. While a
// CapturedStderr lives, everything written to file descriptor 2 goes to a temporary file instead.
//
// Not thread safe: file descriptor 2 belongs to the whole process, so only one thread may capture
// at a time, and other threads' messages in that time are captured too. gibench reads images
// before it starts worker threads.

#include <string>

namespace gibench {

class CapturedStderr {
public:
    CapturedStderr();
    ~CapturedStderr();  // restores standard error; what was captured is dropped
    CapturedStderr(const CapturedStderr&) = delete;
    CapturedStderr& operator=(const CapturedStderr&) = delete;

    // Everything written so far, trailing newlines removed.
    std::string text() const;

private:
    int m_saved = -1;    // the original standard error, -1 when capturing failed (then nothing is)
    int m_capture = -1;  // the temporary file
};

}  // namespace gibench
