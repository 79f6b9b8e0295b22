#pragma once
// What counts as a finding for every fuzz target (issue 8, "bad input never crashes"): bad input
// must end in an InputError or be accepted. Any other exception escaping is a finding, as is a
// crash or a sanitizer report, which libFuzzer catches itself. A finding aborts, so that libFuzzer
// saves the input that caused it.

#include "core/util/error.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace gibench {

[[noreturn]] inline void finding(const std::string& what) {
    std::fprintf(stderr, "finding: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

// Runs `readInput`; returns whether it accepted the input (false: it threw an InputError).
template <typename F>
bool acceptsOrRejectsCleanly(F&& readInput) {
    try {
        readInput();
        return true;
    } catch (const InputError&) {
        return false;
    } catch (const std::exception& e) {
        finding(std::string("an exception other than InputError escaped: ") + e.what());
    } catch (...) {
        finding("a non-std exception escaped");
    }
}

}  // namespace gibench
