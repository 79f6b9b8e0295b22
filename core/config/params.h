#pragma once
// Typed, validated access to one JSON object of a config or scene file.
//
// Every plugin declares a ParamTable (name, type, default, meaning, range); `Params` reads values
// only through that table, remembers which keys were read, and finish() reports every key nobody
// read. The same table feeds `gibench methods` and the resolved configuration in the manifest, so
// the documentation of a parameter is never a second copy.

#include "core/util/math.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace gibench {

using Json = nlohmann::json;

enum class ParamType {
    Bool,
    Int,
    Float,
    String,
    Color,  // a number (grey) or an array of 3 numbers, each within the range
    Vec3,   // an array of 3 numbers
    Json,   // any JSON value; the reader validates it
};

struct ParamSpec {
    std::string name;
    ParamType type;
    Json defaultValue;  // null: the key is required
    std::string meaning;
    double min = -std::numeric_limits<double>::infinity();  // inclusive, for Int, Float, Color
    double max = std::numeric_limits<double>::infinity();
    std::vector<std::string> choices = {};  // allowed values of a String; empty: any
    bool optional = false;  // with a null default: the key may be left out, meaning "none" (readers check has())
};

// `spec` as a key that may be left out without a default (ParamSpec::optional).
inline ParamSpec optionalKey(ParamSpec spec) {
    spec.optional = true;
    return spec;
}

using ParamTable = std::vector<ParamSpec>;

// `first` followed by `second`, for a plugin whose keys come from several parts (a pipeline and
// its store). A key in both is a programming error: std::logic_error naming it and `context`.
ParamTable joinTables(ParamTable first, const ParamTable& second, const std::string& context);

// The names of a string key that selects an enum value, written once: the table row lists
// choiceNames(choices) and Params::getEnum() maps the value read back through the same list.
template <typename E>
using EnumChoices = std::vector<std::pair<std::string, E>>;

template <typename E>
std::vector<std::string> choiceNames(const EnumChoices<E>& choices) {
    std::vector<std::string> names;
    for (const auto& choice : choices) names.push_back(choice.first);
    return names;
}

// The table as JSON rows {name, type, default, meaning, range?, choices?} for `gibench methods`.
Json describeTable(const ParamTable& table);
std::string typeName(ParamType type);

// Reads a JSON file; a syntax error becomes an InputError "FILE:LINE:COLUMN: ...". The file name
// must be UTF-8 (checkUtf8Path) and arrays and objects may nest at most kMaxJsonDepth levels:
// nlohmann::json copies and dumps values recursively, so a deeper file would overflow the stack.
Json loadJsonFile(const std::filesystem::path& file);
inline constexpr int kMaxJsonDepth = 100;

// Whether the double `x` survives the cast to float as a finite number. Smaller magnitudes are
// allowed (they round to 0 or a subnormal); a reader for which 0 is invalid checks the float.
bool fitsFloat(double x);
// `v` as a float when it is a number that fitsFloat().
std::optional<float> asFloat(const Json& v);
// What a message adds after "got X" when X is a number that does not fit a float.
inline constexpr const char* kFloatLimit = "too large for a float, whose magnitude is at most 3.4e38";

class Params {
public:
    // `block` must be an object (else InputError). `pointer` is its JSON pointer in `file`;
    // `context` names the reader in messages, e.g. "method \"mamba\"". `table` may be null for a
    // block whose keys are read by getJson()/discriminator() only.
    Params(Json block, std::string file, std::string pointer, std::string context, const ParamTable* table);

    // The same block read with another table (after a discriminator chose it); keys already read
    // stay read.
    Params withTable(const ParamTable& table, std::string context) const;

    bool has(const std::string& name) const;

    // Typed reads. The spec must be in the table (a programming error otherwise); a missing
    // optional key yields the table's default.
    bool getBool(const std::string& name);
    long long getInt(const std::string& name);
    float getFloat(const std::string& name);
    std::string getString(const std::string& name);
    Color getColor(const std::string& name);
    vec3 getVec3(const std::string& name);
    // A Vec3 key kept in double, for world positions far from the origin (scene_loader.h rebases
    // them); its numbers must still fit a float.
    glm::dvec3 getDVec3(const std::string& name);
    Json getJson(const std::string& name);
    // A String key whose row lists choiceNames(choices).
    template <typename E>
    E getEnum(const std::string& name, const EnumChoices<E>& choices) {
        const std::string value = getString(name);
        for (const auto& [choice, e] : choices)
            if (choice == value) return e;
        fail(name, "expected one of the choices its table row lists, got \"" + value + "\" (the row and the enum disagree)");
    }

    // A required string key outside any table that selects the table to use ("type", "name").
    std::string discriminator(const std::string& name, const std::vector<std::string>& choices);

    // A nested object, read with its own table; marks `name` read here.
    Params child(const std::string& name, const ParamTable* table, std::string context);
    // Elements of an array of objects under `name` (empty when absent); marks `name` read.
    std::vector<Params> children(const std::string& name, std::string context);

    // Throws one InputError listing every key never read, with the known keys.
    void finish() const;

    // Table defaults overlaid with the given values: what the run actually used.
    Json resolved() const;

    // "FILE: /pointer/name: " prefix for an error about key `name` ("" for the block itself).
    std::string where(const std::string& name = "") const;
    [[noreturn]] void fail(const std::string& name, const std::string& message) const;

    const std::string& file() const { return m_file; }
    const std::string& pointer() const { return m_pointer; }
    const Json& json() const { return m_block; }
    // Folder relative paths in this file are resolved against.
    std::filesystem::path baseDir() const;

private:
    const ParamSpec& spec(const std::string& name) const;
    // The value given for `name`, or its default; marks it read. Null when absent without default.
    const Json& value(const std::string& name);
    std::string childPointer(const std::string& name) const;

    Json m_block;
    std::string m_file;
    std::string m_pointer;
    std::string m_context;
    const ParamTable* m_table = nullptr;
    std::shared_ptr<std::set<std::string>> m_read;  // shared with withTable() copies
};

}  // namespace gibench
