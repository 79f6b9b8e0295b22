#include "core/util/pixel_read.h"

#include <cstddef>
#include <vector>

namespace gibench {

bool readPixels(OIIO::ImageInput& in, int channels, OIIO::TypeDesc type, void* out) {
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.tile_width > 0)
        return in.read_tiles(0, 0, spec.x, spec.x + spec.width, spec.y, spec.y + spec.height, spec.z, spec.z + 1, 0, channels, type, out);

    const std::size_t nativePixel = spec.pixel_bytes(0, channels, true);
    const std::size_t width = std::size_t(spec.width), height = std::size_t(spec.height);
    std::vector<std::byte> native(width * height * nativePixel);
    if (!in.read_native_scanlines(0, 0, spec.y, spec.y + spec.height, spec.z, 0, channels, native.data())) return false;
    // Channel by channel, since a file may store each in its own format (OpenEXR: half colour,
    // float depth).
    const OIIO::stride_t outPixel = OIIO::stride_t(channels * type.size());
    std::size_t offset = 0;
    for (int c = 0; c < channels; ++c) {
        const OIIO::TypeDesc format = spec.channelformat(c);
        if (!OIIO::convert_image(1, spec.width, spec.height, 1, native.data() + offset, format, OIIO::stride_t(nativePixel),
                                 OIIO::stride_t(width * nativePixel), OIIO::AutoStride, static_cast<std::byte*>(out) + c * type.size(), type,
                                 outPixel, outPixel * OIIO::stride_t(width), OIIO::AutoStride))
            return false;
        offset += format.size();
    }
    return true;
}

}  // namespace gibench
