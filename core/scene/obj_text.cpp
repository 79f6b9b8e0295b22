#include "core/scene/obj_text.h"

#include "core/config/params.h"
#include "core/util/error.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <vector>

namespace gibench {
namespace {

// The tokens of one line as tinyobjloader splits them: lines end at \n, \r\n or \r; tokens are
// separated by spaces and tabs. Views into the text, since OBJ files run to millions of lines.
struct Line {
    std::size_t number;  // from 1
    std::vector<std::string_view> tokens;
};

template <typename F>
void forEachLine(const std::string& text, const F& visit) {
    Line line{1, {}};
    std::size_t tokenStart = std::string::npos;
    for (std::size_t i = 0; i <= text.size(); ++i) {
        const char c = i < text.size() ? text[i] : '\n';
        const bool lineEnd = c == '\n' || c == '\r', separator = lineEnd || c == ' ' || c == '\t';
        if (separator && tokenStart != std::string::npos) {
            line.tokens.emplace_back(text.data() + tokenStart, i - tokenStart);
            tokenStart = std::string::npos;
        } else if (!separator && tokenStart == std::string::npos) {
            tokenStart = i;
        }
        if (!lineEnd) continue;
        if (!line.tokens.empty()) visit(line);
        if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
        line.tokens.clear();
        ++line.number;
    }
}

// Throws when `text` holds a byte no text file has.
void checkIsText(const std::string& text, const std::filesystem::path& file, const std::string& where, const std::string& format) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        const bool control = (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') || c == 0x7f;
        if (!control) continue;
        char byte[8];
        std::snprintf(byte, sizeof byte, "0x%02x", c);
        throw InputError(where + "invalid " + format + " \"" + file.string() + "\": not a text " + format + " file (byte " + byte +
                         " at offset " + std::to_string(i) + ")");
    }
}

// Digits with an optional sign, point and exponent: what tinyobjloader reads as a number (it
// reads "nan", "inf" and hexadecimal as 0, so strtod alone would accept too much).
bool isDecimal(std::string_view s) {
    std::size_t i = 0, digits = 0;
    auto run = [&] {
        std::size_t n = 0;
        while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++n;
        return n;
    };
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    digits += run();
    if (i < s.size() && s[i] == '.') ++i, digits += run();
    if (digits == 0) return false;
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        if (run() == 0) return false;
    }
    return i == s.size();
}

class TextChecker {
public:
    TextChecker(const std::filesystem::path& file, const std::string& where) : m_file(file), m_where(where) {}

    [[noreturn]] void fail(std::size_t line, std::string_view keyword, const std::string& message) const {
        throw InputError(m_where + m_file.string() + ":" + std::to_string(line) + ": " + std::string(keyword) + ": " + message);
    }
    [[noreturn]] void fail(const Line& line, const std::string& message) const { fail(line.number, line.tokens[0], message); }

    // Tokens 1 .. count of `line` (at least `required` of them present) are numbers a float holds.
    void checkNumbers(const Line& line, std::size_t required, std::size_t count) const {
        if (line.tokens.size() - 1 < required)
            fail(line, "expected " + std::to_string(required) + " numbers, got " + std::to_string(line.tokens.size() - 1));
        for (std::size_t i = 1; i <= count && i < line.tokens.size(); ++i) {
            const std::string token(line.tokens[i]);
            if (!isDecimal(token)) fail(line, "expected a number, got \"" + token + "\"");
            if (!fitsFloat(std::strtod(token.c_str(), nullptr)))
                fail(line, "expected a number, got \"" + token + "\" (" + kFloatLimit + ")");
        }
    }

private:
    std::filesystem::path m_file;
    std::string m_where;
};

// A face index past the v, vt or vn lines read so far, checked against the whole file at its end.
struct IndexAhead {
    std::size_t line;
    long long index;
};

}  // namespace

std::filesystem::path mtlPath(const std::filesystem::path& folder, const std::string& name) {
    return (folder / name).lexically_normal();
}

void checkObjText(const std::string& text, const std::filesystem::path& file, const std::string& where) {
    checkIsText(text, file, where, "OBJ");
    const TextChecker checker(file, where);
    const std::array<const char*, 3> kinds = {"v", "vt", "vn"};  // the order of a face corner's indices
    std::array<long long, 3> counts = {0, 0, 0};
    std::array<std::vector<IndexAhead>, 3> ahead;
    forEachLine(text, [&](const Line& line) {
        const std::string_view keyword = line.tokens[0];
        if (keyword == "v") {
            checker.checkNumbers(line, 3, 3);
            ++counts[0];
        } else if (keyword == "vt") {
            checker.checkNumbers(line, 1, 2);
            ++counts[1];
        } else if (keyword == "vn") {
            checker.checkNumbers(line, 3, 3);
            ++counts[2];
        } else if (keyword == "mtllib") {
            for (std::size_t i = 1; i < line.tokens.size(); ++i) {
                const std::filesystem::path mtl = mtlPath(file.parent_path(), std::string(line.tokens[i]));
                std::string extension = mtl.extension().string();
                for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
                if (extension != ".mtl") checker.fail(line, "expected an .mtl file, got \"" + mtl.string() + "\"");
            }
        } else if (keyword == "f") {
            for (std::size_t i = 1; i < line.tokens.size(); ++i) {
                const std::string corner(line.tokens[i]);
                std::size_t start = 0;
                for (std::size_t kind = 0; kind < 3 && start <= corner.size(); ++kind) {
                    const std::size_t end = std::min(corner.find('/', start), corner.size());
                    const std::string part = corner.substr(start, end - start);
                    start = end + 1;
                    if (part.empty()) continue;  // v//vn
                    char* stop = nullptr;
                    const long long index = std::strtoll(part.c_str(), &stop, 10);
                    if (stop == part.c_str() || *stop != '\0')
                        checker.fail(line, "expected vertex indices such as 1, 1/2 or 1/2/3, got \"" + corner + "\"");
                    // Index 0 is left to tinyobjloader, whose message says it is not allowed.
                    // Compared without negating: -LLONG_MIN does not exist (fuzz_obj found it).
                    if (index < 0 && index < -static_cast<long long>(counts[kind]))
                        checker.fail(line, "index " + std::to_string(index) + " of \"" + corner + "\" is out of range (" +
                                               std::to_string(counts[kind]) + " \"" + kinds[kind] + "\" lines before it)");
                    if (index > counts[kind]) ahead[kind].push_back({line.number, index});
                }
            }
        }
    });
    for (std::size_t kind = 0; kind < 3; ++kind)
        for (const IndexAhead& use : ahead[kind])
            if (use.index > counts[kind])
                checker.fail(use.line, "f", "index " + std::to_string(use.index) + " is out of range (" + std::to_string(counts[kind]) +
                                                " \"" + kinds[kind] + "\" lines in the file)");
}

void checkMtlText(const std::string& text, const std::filesystem::path& file, const std::string& where) {
    checkIsText(text, file, where, "MTL");
    const TextChecker checker(file, where);
    forEachLine(text, [&](const Line& line) {
        if (line.tokens[0] == "Kd" || line.tokens[0] == "Ke") checker.checkNumbers(line, 3, 3);
    });
}

}  // namespace gibench
