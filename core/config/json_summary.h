#pragma once
// A bad JSON value as error messages quote it: bounded in length and in the work it takes, so a
// value nested 100,000 deep or holding a million numbers cannot overflow the stack (dump() recurses)
// or flood the terminal.

#include <nlohmann/json.hpp>

#include <string>

namespace gibench {

// The value's dump() when it nests at most kSummaryDepth levels, cut to kSummaryLength characters
// with "..." after; otherwise its kind and size, e.g. "an array of 1 value nested more than 4 levels
// deep". Never recurses.
std::string summarize(const nlohmann::json& value);

inline constexpr int kSummaryDepth = 4;
inline constexpr std::size_t kSummaryLength = 120;

}  // namespace gibench
