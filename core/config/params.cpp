#include "core/config/params.h"

#include "core/config/input_file.h"
#include "core/config/json_summary.h"
#include "core/util/error.h"

#include <cfloat>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace gibench {
namespace {

std::string formatBound(double x) {
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    if (x == std::floor(x) && std::fabs(x) < 1e15) return std::to_string(static_cast<long long>(x));
    std::ostringstream out;
    out << x;
    return out.str();
}

// "an integer >= 1", "a number in [0, 1]", ... for messages.
std::string expectation(const std::string& what, const ParamSpec& s) {
    const bool lo = std::isfinite(s.min), hi = std::isfinite(s.max);
    if (lo && hi) return what + " in [" + formatBound(s.min) + ", " + formatBound(s.max) + "]";
    if (lo) return what + " >= " + formatBound(s.min);
    if (hi) return what + " <= " + formatBound(s.max);
    return what;
}

// "got X" for a message about a number, saying why when X is a number a float cannot hold.
std::string gotNumber(const Json& v) {
    const bool tooLarge = v.is_number() && std::isfinite(v.get<double>()) && !fitsFloat(v.get<double>());
    return "got " + summarize(v) + (tooLarge ? std::string(" (") + kFloatLimit + ")" : "");
}

// Line and column (from 1) of byte `offset` of `text`.
std::pair<std::size_t, std::size_t> lineAndColumn(const std::string& text, std::size_t offset) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return {line, column};
}

// Offset of the bracket that opens level kMaxJsonDepth + 1, if the text nests that deep. Brackets
// inside strings do not count; the parser reports any other syntax error afterwards.
std::optional<std::size_t> tooDeepAt(const std::string& text) {
    int depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth) return i;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return std::nullopt;
}

std::string quotedList(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "\"" : ", \"") + n + "\"";
    return out;
}

}  // namespace

std::string typeName(ParamType type) {
    switch (type) {
        case ParamType::Bool: return "bool";
        case ParamType::Int: return "int";
        case ParamType::Float: return "float";
        case ParamType::String: return "string";
        case ParamType::Color: return "color";
        case ParamType::Vec3: return "vec3";
        case ParamType::Json: return "json";
    }
    return "?";
}

ParamTable joinTables(ParamTable first, const ParamTable& second, const std::string& context) {
    for (const ParamSpec& spec : second) {
        for (const ParamSpec& taken : first)
            if (taken.name == spec.name)
                throw std::logic_error(context + ": two parameter tables declare key \"" + spec.name + "\"");
        first.push_back(spec);
    }
    return first;
}

Json describeTable(const ParamTable& table) {
    Json rows = Json::array();
    for (const auto& s : table) {
        Json row = {{"name", s.name}, {"type", typeName(s.type)}, {"default", s.defaultValue}, {"meaning", s.meaning}};
        if (std::isfinite(s.min) || std::isfinite(s.max))
            row["range"] = {std::isfinite(s.min) ? Json(s.min) : Json(nullptr), std::isfinite(s.max) ? Json(s.max) : Json(nullptr)};
        if (!s.choices.empty()) row["choices"] = s.choices;
        rows.push_back(row);
    }
    return rows;
}

bool fitsFloat(double x) { return std::isfinite(x) && std::fabs(x) <= double(FLT_MAX); }

std::optional<float> asFloat(const Json& v) {
    if (!v.is_number() || !fitsFloat(v.get<double>())) return std::nullopt;
    return static_cast<float>(v.get<double>());
}

Json loadJsonFile(const std::filesystem::path& file) {
    checkUtf8Path(file);
    const std::string text = readInputFile(file, file.string() + ": cannot open file: ");
    auto at = [&](std::size_t offset) {
        const auto [line, column] = lineAndColumn(text, offset);
        return file.string() + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
    };
    if (const auto offset = tooDeepAt(text))
        throw InputError(at(*offset) + "expected arrays and objects nested at most " + std::to_string(kMaxJsonDepth) +
                         " levels deep, got more");
    try {
        return Json::parse(text);
    } catch (const Json::parse_error& e) {
        // nlohmann reports a byte offset (of the byte after the error, from 1); users want a line and column.
        std::string why = e.what();
        if (auto pos = why.find("parse error"); pos != std::string::npos) why = why.substr(pos);
        throw InputError(at(e.byte > 0 ? e.byte - 1 : 0) + "invalid JSON: " + why);
    } catch (const Json::out_of_range& e) {
        // A number such as 1e400 ("number overflow parsing '1e400'"); nlohmann gives no offset, so
        // the number's first appearance stands for it.
        const std::string why = e.what();
        const auto open = why.find('\''), close = why.rfind('\'');
        const std::string number = open < close ? why.substr(open + 1, close - open - 1) : "";
        const std::size_t offset = number.empty() ? std::string::npos : text.find(number);
        throw InputError((offset == std::string::npos ? file.string() + ": " : at(offset)) +
                         "expected numbers within the range of a double, got " + (number.empty() ? why : number));
    }
}

Params::Params(Json block, std::string file, std::string pointer, std::string context, const ParamTable* table)
    : m_block(std::move(block)),
      m_file(std::move(file)),
      m_pointer(std::move(pointer)),
      m_context(std::move(context)),
      m_table(table),
      m_read(std::make_shared<std::set<std::string>>()) {
    if (!m_block.is_object())
        throw InputError(m_file + ": " + (m_pointer.empty() ? "/" : m_pointer) + ": expected an object for " + m_context +
                         ", got " + summarize(m_block));
}

Params Params::withTable(const ParamTable& table, std::string context) const {
    Params p = *this;
    p.m_table = &table;
    p.m_context = std::move(context);
    return p;
}

bool Params::has(const std::string& name) const { return m_block.contains(name); }

std::string Params::childPointer(const std::string& name) const {
    return (Json::json_pointer(m_pointer) / name).to_string();
}

std::string Params::where(const std::string& name) const {
    const std::string p = name.empty() ? m_pointer : childPointer(name);
    return m_file + ": " + (p.empty() ? "/" : p) + ": ";
}

void Params::fail(const std::string& name, const std::string& message) const { throw InputError(where(name) + message); }

std::filesystem::path Params::baseDir() const { return std::filesystem::path(m_file).parent_path(); }

const ParamSpec& Params::spec(const std::string& name) const {
    if (m_table)
        for (const auto& s : *m_table)
            if (s.name == name) return s;
    throw std::logic_error("parameter \"" + name + "\" is not in the table of " + m_context);
}

const Json& Params::value(const std::string& name) {
    static const Json null;
    const ParamSpec& s = spec(name);
    m_read->insert(name);
    if (auto it = m_block.find(name); it != m_block.end()) return *it;
    if (s.defaultValue.is_null() && !s.optional) fail("", "missing key \"" + name + "\" for " + m_context);
    return s.defaultValue;
}

bool Params::getBool(const std::string& name) {
    const Json& v = value(name);
    if (!v.is_boolean()) fail(name, "expected true or false, got " + summarize(v));
    return v.get<bool>();
}

long long Params::getInt(const std::string& name) {
    const Json& v = value(name);
    const ParamSpec& s = spec(name);
    const bool integral = v.is_number_integer() || (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>());
    const std::string expected = "expected " + expectation("an integer", s) + ", got " + summarize(v);
    if (!integral) fail(name, expected);
    const double x = v.get<double>();
    // A table without bounds still needs a long long to hold the value (2^63 is exact in double).
    if (x < s.min || x > s.max || x < -0x1p63 || x >= 0x1p63) fail(name, expected);
    return v.is_number_unsigned() ? static_cast<long long>(v.get<unsigned long long>()) : v.get<long long>();
}

float Params::getFloat(const std::string& name) {
    const Json& v = value(name);
    const ParamSpec& s = spec(name);
    const std::optional<float> x = asFloat(v);
    if (!x || v.get<double>() < s.min || v.get<double>() > s.max) fail(name, "expected " + expectation("a number", s) + ", " + gotNumber(v));
    return *x;
}

std::string Params::getString(const std::string& name) {
    const Json& v = value(name);
    const ParamSpec& s = spec(name);
    if (!v.is_string()) fail(name, "expected a string, got " + summarize(v));
    const std::string x = v.get<std::string>();
    if (!s.choices.empty() && std::find(s.choices.begin(), s.choices.end(), x) == s.choices.end())
        fail(name, "expected one of " + quotedList(s.choices) + ", got " + summarize(v));
    return x;
}

Color Params::getColor(const std::string& name) {
    const Json& v = value(name);
    const ParamSpec& s = spec(name);
    const std::string expected = "expected " + expectation("a number", s) + " or an array of 3 such numbers, got " + summarize(v);
    auto check = [&](const Json& x) {
        const std::optional<float> f = asFloat(x);
        if (!f || x.get<double>() < s.min || x.get<double>() > s.max)
            fail(name, expected + (x.is_number() && !f ? " (" + summarize(x) + " is " + kFloatLimit + ")" : ""));
        return *f;
    };
    if (v.is_number()) return Color(check(v));
    if (!v.is_array() || v.size() != 3) fail(name, expected);
    return Color(check(v[0]), check(v[1]), check(v[2]));
}

glm::dvec3 Params::getDVec3(const std::string& name) {
    const Json& v = value(name);
    const std::string expected = "expected an array of 3 numbers, got " + summarize(v);
    if (!v.is_array() || v.size() != 3) fail(name, expected);
    glm::dvec3 out;
    for (int i = 0; i < 3; ++i) {
        if (!asFloat(v[i])) fail(name, expected + (v[i].is_number() ? " (" + summarize(v[i]) + " is " + kFloatLimit + ")" : ""));
        out[i] = v[i].get<double>();
    }
    return out;
}

vec3 Params::getVec3(const std::string& name) { return vec3(getDVec3(name)); }

Json Params::getJson(const std::string& name) { return value(name); }

std::string Params::discriminator(const std::string& name, const std::vector<std::string>& choices) {
    m_read->insert(name);
    auto it = m_block.find(name);
    if (it == m_block.end()) fail("", "missing key \"" + name + "\" for " + m_context + " (one of " + quotedList(choices) + ")");
    if (!it->is_string() || std::find(choices.begin(), choices.end(), it->get<std::string>()) == choices.end())
        fail(name, "expected one of " + quotedList(choices) + ", got " + summarize(*it));
    return it->get<std::string>();
}

Params Params::child(const std::string& name, const ParamTable* table, std::string context) {
    m_read->insert(name);
    auto it = m_block.find(name);
    const Json block = it == m_block.end() ? Json::object() : *it;
    return Params(block, m_file, childPointer(name), std::move(context), table);
}

std::vector<Params> Params::children(const std::string& name, std::string context) {
    m_read->insert(name);
    std::vector<Params> out;
    auto it = m_block.find(name);
    if (it == m_block.end()) return out;
    if (!it->is_array()) fail(name, "expected an array of objects, got " + summarize(*it));
    const std::string base = childPointer(name);
    for (std::size_t i = 0; i < it->size(); ++i)
        out.emplace_back((*it)[i], m_file, base + "/" + std::to_string(i), context, nullptr);
    return out;
}

void Params::finish() const {
    std::string known;
    if (m_table)
        for (const auto& s : *m_table) known += (known.empty() ? "" : ", ") + s.name;
    std::string errors;
    for (const auto& [key, v] : m_block.items()) {
        if (m_read->count(key)) continue;
        if (!errors.empty()) errors += "\n";
        errors += where(key) + "unknown key for " + m_context + " (known: " + (known.empty() ? "none" : known) + ")";
    }
    if (!errors.empty()) throw InputError(errors);
}

Json Params::resolved() const {
    Json out = Json::object();
    if (m_table)
        for (const auto& s : *m_table) {
            auto it = m_block.find(s.name);
            if (it != m_block.end())
                out[s.name] = *it;
            else if (!s.defaultValue.is_null())
                out[s.name] = s.defaultValue;
        }
    return out;
}

}  // namespace gibench
