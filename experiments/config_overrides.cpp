#include "experiments/config_overrides.h"

#include "core/config/input_file.h"
#include "core/util/error.h"

#include <algorithm>

namespace gibench {

namespace {

constexpr std::size_t kMaxNameLength = 64;

bool validName(const std::string& name) {
    return !name.empty() && name.size() <= kMaxNameLength && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    });
}

[[noreturn]] void refuse(const std::string& text, const std::string& why) {
    throw InputError("--set \"" + text + "\": " + why);
}

}  // namespace

std::string ConfigOverride::pointer() const {
    Json::json_pointer p;
    for (const std::string& name : path) p /= name;
    return p.to_string();
}

ConfigOverride parseConfigOverride(const std::string& text) {
    checkUtf8Text(text, "--set");
    const std::size_t equals = text.find('=');
    if (equals == std::string::npos) refuse(text, "expected KEY=VALUE, e.g. method.spp=64");
    ConfigOverride o{text, {}, Json(), "on the command line: --set " + text};
    const std::string key = text.substr(0, equals), value = text.substr(equals + 1);
    for (std::size_t start = 0;;) {
        const std::size_t dot = key.find('.', start);
        const std::string name = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        if (!validName(name))
            refuse(text, "expected a key of dot-separated names of 1 to 64 letters, digits, '_' or '-' before '=', got \"" + key + "\"");
        o.path.push_back(name);
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    if (value.empty()) refuse(text, "expected a value after '=' (JSON, or text taken as a string)");
    o.value = Json::parse(value, nullptr, false);
    if (o.value.is_discarded()) o.value = value;
    return o;
}

void applyConfigOverrides(Json& config, const std::vector<ConfigOverride>& overrides) {
    for (const ConfigOverride& o : overrides) {
        Json* node = &config;
        for (std::size_t i = 0; i + 1 < o.path.size(); ++i) {
            Json& next = (*node)[o.path[i]];
            if (next.is_null()) next = Json::object();
            if (!next.is_object())
                refuse(o.text, "\"" + o.path[i] + "\" holds " + next.dump() + ", not an object whose key \"" + o.path[i + 1] + "\" could be set");
            node = &next;
        }
        (*node)[o.path.back()] = o.value;
    }
}

std::string withOverrideOrigins(const std::string& message, const std::vector<ConfigOverride>& overrides) {
    std::string out = message;
    for (const ConfigOverride& o : overrides) {
        const std::string pointer = o.pointer();
        // Messages name a key as "FILE: /pointer: ", so the pointer is whole between ": " and ":",
        // or ends in "/" before a key inside the overridden object.
        if (message.find(": " + pointer + ":") != std::string::npos || message.find(": " + pointer + "/") != std::string::npos)
            out += "\n" + pointer + " was set " + o.source;
    }
    return out;
}

}  // namespace gibench
