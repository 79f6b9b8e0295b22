#include "core/config/json_summary.h"

#include <cmath>
#include <utility>
#include <vector>

namespace gibench {
namespace {

// Whether `value` nests at most `levels` deep, walked with an explicit stack.
bool nestsAtMost(const nlohmann::json& value, int levels) {
    std::vector<std::pair<const nlohmann::json*, int>> pending = {{&value, 0}};
    while (!pending.empty()) {
        const auto [v, depth] = pending.back();
        pending.pop_back();
        if (!v->is_structured()) continue;
        if (depth >= levels) return false;
        for (const nlohmann::json& child : *v) pending.emplace_back(&child, depth + 1);
    }
    return true;
}

std::string counted(std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::string summarize(const nlohmann::json& value) {
    // dump() writes an infinite number (a literal such as 1e400) as null.
    if (value.is_number_float() && !std::isfinite(value.get<double>())) return "a number beyond the range of a double";
    if (!nestsAtMost(value, kSummaryDepth)) {
        const std::string size = value.is_array() ? "an array of " + counted(value.size(), "value", "values")
                                                  : "an object of " + counted(value.size(), "key", "keys");
        return size + " nested more than " + std::to_string(kSummaryDepth) + " levels deep";
    }
    // Invalid UTF-8 in a string (a file name, say) is replaced, so quoting it cannot throw.
    std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (text.size() > kSummaryLength) text = text.substr(0, kSummaryLength) + "...";
    return text;
}

}  // namespace gibench
