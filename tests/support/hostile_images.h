#pragma once
// Image files made to break readers, shared by the tests of every layer that reads images.

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace gibench::test {

// A PNG of 68 bytes whose header claims 100000 × 100000 RGB pixels (and one tiny IDAT chunk, so
// that libpng reads the header without complaint).
inline const std::string kHugeHeaderPng(
    "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x02\x00\x00\x00\x27\x30\x9c"
    "\x9f\x00\x00\x00\x0b\x49\x44\x41\x54\x78\x9c\x63\x60\x80\x01\x00\x00\x0a\x00\x01\x7f\x80\x74\x5e\x00\x00\x00\x00\x49\x45\x4e\x44"
    "\xae\x42\x60\x82",
    68);

// An OpenEXR file written as 2 x 2 RGB half pixels compressed "zip", whose data window is then
// patched to claim `width` x `height` (the pixel data stays that of 2 x 2): the form of a 597-byte
// input of tests/fuzz/fuzz_image that claimed 16777218 x 1 pixels. `scratch` is where the file is
// written first.
inline std::string exrClaiming(const std::filesystem::path& scratch, int width, int height) {
    OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::HALF);
    spec.attribute("compression", "zip");
    const float pixels[12] = {};
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out || !out->open(scratch.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels) || !out->close())
        throw std::runtime_error("cannot write " + scratch.string());
    std::ifstream in(scratch, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key("dataWindow\0box2i\0", 17);
    const std::size_t at = bytes.find(key);
    if (at == std::string::npos) throw std::runtime_error("no dataWindow in " + scratch.string());
    const int32_t window[4] = {0, 0, width - 1, height - 1};  // xMin, yMin, xMax, yMax; little-endian like the file
    std::memcpy(&bytes[at + key.size() + 4], window, sizeof window);
    return bytes;
}

}  // namespace gibench::test
