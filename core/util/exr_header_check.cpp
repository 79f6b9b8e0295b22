#include "core/util/exr_header_check.h"

#include "core/util/error.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

namespace gibench {

namespace {

// OpenEXR layout (openexr.com, "The OpenEXR File Layout"): magic, a 4-byte version field whose
// bit 12 marks a multi-part file, then headers. A header is a sequence of attributes — name and
// type as NUL-terminated strings, a little-endian int32 size, then that many bytes — ended by an
// empty name; a multi-part file's headers are ended by one more empty header.
constexpr unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr uint32_t kMultipartFlag = 1u << 12;
constexpr std::size_t kMaxNameLength = 255;  // with the "long names" flag; 31 without

class HeaderReader {
public:
    HeaderReader(std::ifstream& in, std::uintmax_t fileSize, const std::filesystem::path& file)
        : m_in(in), m_fileSize(fileSize), m_file(file) {}

    // Reads one NUL-terminated string; empty at a header's end.
    std::string name(const char* what) {
        std::string s;
        for (;;) {
            const int c = m_in.get();
            if (c == std::char_traits<char>::eof()) fail("the header ends inside an attribute " + std::string(what));
            if (c == 0) return s;
            if (s.size() == kMaxNameLength) fail("an attribute " + std::string(what) + " is longer than 255 bytes");
            s.push_back(char(c));
        }
    }

    void skipValue(const std::string& attribute) {
        unsigned char b[4];
        if (!m_in.read(reinterpret_cast<char*>(b), 4)) fail("the header ends inside the size of attribute \"" + attribute + "\"");
        const int32_t size = int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24);
        const std::uintmax_t position = std::uintmax_t(m_in.tellg());
        if (size < 0 || std::uintmax_t(size) > m_fileSize - position)
            fail("attribute \"" + attribute + "\" claims " + std::to_string(size) + " bytes, but " + std::to_string(m_fileSize - position) +
                 " remain in the file");
        m_in.seekg(size, std::ios::cur);
    }

    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(m_file.string() + ": cannot read image: not a valid OpenEXR file: " + reason);
    }

private:
    std::ifstream& m_in;
    std::uintmax_t m_fileSize;
    const std::filesystem::path& m_file;
};

}  // namespace

void checkExrHeader(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char start[8];
    if (!in || !in.read(reinterpret_cast<char*>(start), 8) || !std::equal(kMagic, kMagic + 4, start)) return;
    std::error_code error;
    const std::uintmax_t fileSize = std::filesystem::file_size(file, error);
    if (error) return;
    const uint32_t version = uint32_t(start[4]) | uint32_t(start[5]) << 8 | uint32_t(start[6]) << 16 | uint32_t(start[7]) << 24;
    HeaderReader header(in, fileSize, file);
    const bool multipart = (version & kMultipartFlag) != 0;
    for (;;) {
        int attributes = 0;
        for (std::string attribute = header.name("name"); !attribute.empty(); attribute = header.name("name"), ++attributes) {
            header.name("type");
            header.skipValue(attribute);
        }
        // A single-part file has one header; a multi-part file ends with an empty one.
        if (!multipart || attributes == 0) return;
    }
}

}  // namespace gibench
