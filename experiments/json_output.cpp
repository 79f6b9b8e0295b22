#include "experiments/json_output.h"

#include "core/config/input_file.h"
#include "core/util/error.h"

#include <cmath>
#include <stdexcept>

namespace gibench {
namespace {

// RFC 6901: "~" and "/" in a key are escaped.
std::string pointerStep(const std::string& key) {
    std::string out = "/";
    for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
    return out;
}

void checkUtf8(const Json& value, const std::string& pointer, const std::string& source, const std::string& document) {
    // Every string from outside gibench that reaches its JSON is a file or folder name.
    auto check = [&](const std::string& text, const std::string& where) {
        try {
            checkUtf8Path(text);
        } catch (const InputError& e) {
            throw InputError(source + ": " + document + "'s " + (where.empty() ? "/" : where) + ": " + e.what());
        }
    };
    if (value.is_string()) {
        check(value.get_ref<const std::string&>(), pointer);
    } else if (value.is_object()) {
        for (const auto& [key, element] : value.items()) {
            check(key, pointer);
            checkUtf8(element, pointer + pointerStep(key), source, document);
        }
    } else if (value.is_array()) {
        for (std::size_t i = 0; i < value.size(); ++i) checkUtf8(value[i], pointer + "/" + std::to_string(i), source, document);
    }
}

void checkFinite(const Json& value, const std::string& pointer) {
    if (value.is_number_float() && !std::isfinite(value.get<double>()))
        throw std::logic_error("JSON output " + (pointer.empty() ? "/" : pointer) + " is " + std::to_string(value.get<double>()) +
                               ", which JSON cannot hold");
    if (value.is_object())
        for (const auto& [key, element] : value.items()) checkFinite(element, pointer + pointerStep(key));
    else if (value.is_array())
        for (std::size_t i = 0; i < value.size(); ++i) checkFinite(value[i], pointer + "/" + std::to_string(i));
}

}  // namespace

void requireUtf8(const Json& value, const std::string& source, const std::string& document) { checkUtf8(value, "", source, document); }

std::string dumpFinite(const Json& value, int indent) {
    checkFinite(value, "");
    return value.dump(indent);
}

}  // namespace gibench
