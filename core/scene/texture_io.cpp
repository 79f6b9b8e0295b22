#include "core/scene/texture_io.h"

#include "core/util/error.h"
#include "core/util/exr_header_check.h"
#include "core/util/image_limits.h"
#include "core/util/pixel_read.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

namespace gibench {
namespace {

[[noreturn]] void cannotRead(const std::filesystem::path& file, const std::string& reason) {
    throw InputError("cannot read image \"" + file.string() + "\": " + reason);
}

// OpenImageIO says only "Could not open file" for a missing file, and "Not a PNG file" for a
// folder named a.png; the system says why.
void checkReadable(const std::filesystem::path& file) {
    std::error_code error;
    if (std::filesystem::is_directory(file, error)) cannotRead(file, "is a directory, not a file");
    std::ifstream probe(file, std::ios::binary);
    if (!probe) cannotRead(file, std::strerror(errno));
}

}  // namespace

float srgbToLinear(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

Texture loadTexture(const std::filesystem::path& file) {
    checkReadable(file);
    // Colours as stored: dropping alpha must not leave them multiplied by it.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    checkExrHeader(file);
    auto input = OIIO::ImageInput::open(file.string(), &config);
    if (!input) cannotRead(file, OIIO::geterror());
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0 || spec.deep)
        cannotRead(file, "expected a flat 2D image, got " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             "x" + std::to_string(spec.depth) + " with " + std::to_string(spec.nchannels) + " channels");
    if (valuesToRead(spec) > kMaxImageValues)
        cannotRead(file, "the header claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " pixels of " +
                             std::to_string(spec.nchannels) + " channels, more than the " + std::to_string(int64_t(kMaxImageValues)) +
                             " values gibench reads");
    const bool isFloat = spec.format.basetype == OIIO::TypeDesc::FLOAT || spec.format.basetype == OIIO::TypeDesc::HALF ||
                         spec.format.basetype == OIIO::TypeDesc::DOUBLE;
    const bool srgb = !isFloat && !OIIO::Strutil::iequals(spec.get_string_attribute("oiio:ColorSpace"), "linear");
    const int channels = spec.nchannels >= 3 ? 3 : 1;
    const std::size_t count = std::size_t(spec.width) * std::size_t(spec.height);

    Texture texture;
    texture.width = spec.width;
    texture.height = spec.height;
    texture.texels.resize(count);
    auto store = [&](std::size_t i, const float* c) { texture.texels[i] = channels == 3 ? Color(c[0], c[1], c[2]) : Color(c[0]); };

    if (srgb && spec.format.basetype == OIIO::TypeDesc::UINT8) {
        // 8-bit files are most textures; a table spares a pow() per channel.
        std::array<float, 256> table;
        for (int v = 0; v < 256; ++v) table[v] = srgbToLinear(float(v) / 255.0f);
        std::vector<uint8_t> raw(count * channels);
        if (!readPixels(*input, channels, OIIO::TypeDesc::UINT8, raw.data())) cannotRead(file, input->geterror());
        for (std::size_t i = 0; i < count; ++i) {
            float c[3];
            for (int k = 0; k < channels; ++k) c[k] = table[raw[i * channels + k]];
            store(i, c);
        }
    } else {
        std::vector<float> raw(count * channels);
        if (!readPixels(*input, channels, OIIO::TypeDesc::FLOAT, raw.data())) cannotRead(file, input->geterror());
        if (srgb)
            for (float& v : raw) v = srgbToLinear(v);
        for (std::size_t i = 0; i < count; ++i) store(i, &raw[i * channels]);
    }
    return texture;
}

}  // namespace gibench
