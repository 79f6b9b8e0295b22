#include "core/util/exr_header_check.h"

#include "core/util/error.h"
#include "core/util/image_limits.h"
#include "core/util/text_format.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <optional>
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

int32_t littleEndianInt(const unsigned char* b) {
    return int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24);
}

// Scanlines a compressed block holds, by the "compression" attribute's value (the OpenEXR file
// layout's table); the library sizes its decompression buffers to a whole block's rows.
std::optional<int> linesPerBlock(unsigned char compression) {
    switch (compression) {
    case 0: case 1: case 2: return 1;   // none, RLE, ZIPS
    case 3: case 5: return 16;          // ZIP, PXR24
    case 4: case 6: case 7: case 8: return 32;  // PIZ, B44, B44A, DWAA
    case 9: return 256;                 // DWAB
    default: return std::nullopt;       // unknown: the library refuses it
    }
}

// What one part's header declares about its pixels; unset where the attribute is missing.
struct PartLayout {
    std::optional<double> width, height;
    std::optional<int> channels;
    std::optional<int> linesPerBlock;
    std::optional<double> tileWidth, tileHeight;

    // The values the library decodes at once at most: the image, or a whole tile or block of
    // scanlines when that is larger than the image.
    std::optional<double> valuesToDecode() const {
        if (!width || !height || !channels) return std::nullopt;
        const double rows = std::max(*height, tileHeight ? *tileHeight : double(linesPerBlock.value_or(1)));
        const double columns = std::max(*width, tileWidth.value_or(0.0));
        return columns * rows * double(*channels);
    }

    void read(const std::string& attribute, const std::string& value) {
        const auto* b = reinterpret_cast<const unsigned char*>(value.data());
        if (attribute == "dataWindow" && value.size() == 16) {
            width = double(littleEndianInt(b + 8)) - double(littleEndianInt(b)) + 1.0;
            height = double(littleEndianInt(b + 12)) - double(littleEndianInt(b + 4)) + 1.0;
        } else if (attribute == "channels") {
            // Entries of a NUL-terminated name and 16 bytes, ended by an empty name.
            int count = 0;
            for (std::size_t at = 0; at < value.size() && value[at] != '\0'; ++count) {
                const std::size_t end = value.find('\0', at);
                if (end == std::string::npos) break;
                at = end + 1 + 16;
            }
            channels = count;
        } else if (attribute == "compression" && value.size() == 1) {
            linesPerBlock = gibench::linesPerBlock(b[0]);
        } else if (attribute == "tiles" && value.size() == 9) {
            tileWidth = double(uint32_t(littleEndianInt(b)));
            tileHeight = double(uint32_t(littleEndianInt(b + 4)));
        }
    }
};

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

    // Reads an attribute's value: its size is checked against the bytes left, so this reads no
    // more than the file holds.
    std::string value(const std::string& attribute) {
        unsigned char b[4];
        if (!m_in.read(reinterpret_cast<char*>(b), 4)) fail("the header ends inside the size of attribute \"" + attribute + "\"");
        const int32_t size = littleEndianInt(b);
        const std::uintmax_t position = std::uintmax_t(m_in.tellg());
        if (size < 0 || std::uintmax_t(size) > m_fileSize - position)
            fail("attribute \"" + attribute + "\" claims " + std::to_string(size) + " bytes, but " + std::to_string(m_fileSize - position) +
                 " remain in the file");
        std::string bytes(std::size_t(size), '\0');
        m_in.read(bytes.data(), size);
        return bytes;
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
    const uint32_t version = uint32_t(littleEndianInt(start + 4));
    HeaderReader header(in, fileSize, file);
    const bool multipart = (version & kMultipartFlag) != 0;
    for (int part = 0;; ++part) {
        int attributes = 0;
        PartLayout layout;
        for (std::string attribute = header.name("name"); !attribute.empty(); attribute = header.name("name"), ++attributes) {
            header.name("type");
            layout.read(attribute, header.value(attribute));
        }
        // A multi-part file's headers end with an empty one.
        if (multipart && attributes == 0) return;
        const std::string whichHeader = "the header" + (multipart ? " of part " + std::to_string(part) : std::string());
        // dataWindow is required. Without it the walk has read the header differently from the
        // library, which, for a "chlist" one byte longer than its declared size, reads on to the
        // real dataWindow (found by tests/fuzz/fuzz_image): the size check below must not be
        // skipped.
        if (!layout.width) header.fail(whichHeader + " has no dataWindow attribute of 16 bytes");
        // OpenEXR allocates its block buffers when it opens the file, before the caller sees a
        // size: 1.5 to 2 GiB for a 597-byte file claiming 16777218 x 1 pixels.
        if (const auto values = layout.valuesToDecode(); values && *values > kMaxImageValues)
            throw InputError(file.string() + ": cannot read image: " + whichHeader + " claims " + formatCount(*layout.width) + "x" +
                             formatCount(*layout.height) + " pixels of " + std::to_string(*layout.channels) + " channels, " +
                             formatCount(*values) + " values to decode, more than the " + formatCount(kMaxImageValues) + " gibench reads");
        if (!multipart) return;
    }
}

}  // namespace gibench
