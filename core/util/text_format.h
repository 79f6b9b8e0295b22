#pragma once
// Numbers as user-facing messages show them.

#include <iomanip>
#include <sstream>
#include <string>

namespace gibench {

// A length or size, to 6 significant digits.
inline std::string formatNumber(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

// A whole count, every digit (counts too large for any integer type included).
inline std::string formatCount(double x) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(0) << x;
    return out.str();
}

}  // namespace gibench
