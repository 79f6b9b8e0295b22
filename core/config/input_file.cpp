#include "core/config/input_file.h"

#include "core/util/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

namespace gibench {
namespace {

// Offset of the first byte of `text` that does not belong to a well-formed UTF-8 sequence
// (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF).
std::optional<std::size_t> firstInvalidUtf8(const std::string& text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = byte(i);
        std::size_t length;
        unsigned lowest, highest;  // range of the second byte
        if (c < 0x80) {
            ++i;
            continue;
        } else if (c >= 0xC2 && c <= 0xDF) {
            length = 2, lowest = 0x80, highest = 0xBF;
        } else if (c >= 0xE0 && c <= 0xEF) {
            length = 3, lowest = c == 0xE0 ? 0xA0 : 0x80, highest = c == 0xED ? 0x9F : 0xBF;
        } else if (c >= 0xF0 && c <= 0xF4) {
            length = 4, lowest = c == 0xF0 ? 0x90 : 0x80, highest = c == 0xF4 ? 0x8F : 0xBF;
        } else {
            return i;
        }
        if (i + length > text.size() || byte(i + 1) < lowest || byte(i + 1) > highest) return i;
        for (std::size_t k = 2; k < length; ++k)
            if ((byte(i + k) & 0xC0) != 0x80) return i;
        i += length;
    }
    return std::nullopt;
}

std::string hexByte(unsigned char c) {
    char text[8];
    std::snprintf(text, sizeof text, "0x%02x", c);
    return text;
}

// `text` with every byte outside printable ASCII as \xNN, so the message prints as it reads.
std::string visible(const std::string& text) {
    std::string out;
    for (unsigned char c : text) out += c >= 0x20 && c < 0x7f ? std::string(1, char(c)) : "\\x" + hexByte(c).substr(2);
    return out;
}

}  // namespace

std::string readInputFile(const std::filesystem::path& file, const std::string& prefix) {
    std::error_code error;
    // Opening a directory succeeds on Linux and reads as empty, which would pass for an empty file.
    if (std::filesystem::is_directory(file, error)) throw InputError(prefix + "is a directory, not a file");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(prefix + std::strerror(errno));
    std::stringstream buffer;
    buffer << in.rdbuf();
    return buffer.str();
}

void checkUtf8Text(const std::string& text, const std::string& what) {
    if (const auto offset = firstInvalidUtf8(text))
        throw InputError(what + " \"" + visible(text) + "\": expected UTF-8 (results record it in JSON), got byte " +
                         hexByte(static_cast<unsigned char>(text[*offset])) + " at offset " + std::to_string(*offset));
}

void checkUtf8Path(const std::filesystem::path& file) {
    const std::string name = file.string();
    if (const auto offset = firstInvalidUtf8(name))
        throw InputError(visible(name) + ": expected a file name in UTF-8 (results record it in JSON), got byte " +
                         hexByte(static_cast<unsigned char>(name[*offset])) + " at offset " + std::to_string(*offset));
}

}  // namespace gibench
