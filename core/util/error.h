#pragma once
// Errors in what a user gives gibench: a config, a scene, an image.

#include <stdexcept>
#include <string>

namespace gibench {

// Bad user input. what() is complete and self-contained: "FILE: /json/pointer: what was expected,
// got what" (or "FILE:LINE: ..." for text formats); several problems are separate lines.
// `gibench` prints each line as "error: LINE" and exits with code 2.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace gibench
