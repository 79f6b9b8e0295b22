#pragma once
// Reading an open image's pixels with allocations bounded by the image's size. OpenImageIO's
// read_image and read_scanlines convert through a buffer of at least 64 rows (256 by default,
// its "read_chunk"), allocated whatever the image's height: a 597-byte OpenEXR file claiming
// 16777218 x 1 pixels made them ask for 25.8 GB (found by tests/fuzz/fuzz_image).

#include <OpenImageIO/imageio.h>

namespace gibench {

// Reads channels [0, channels) of every pixel of the first subimage of `in` as `type` into `out`
// (width x height x channels values, rows from the top); false with the error in in.geterror().
// Scanline images are read in their file's formats into a buffer of the image's size and
// converted here; tiled images tile by tile, by the library.
bool readPixels(OIIO::ImageInput& in, int channels, OIIO::TypeDesc type, void* out);

// The values reading an image of this header takes at most: its pixels, or whole tiles when a
// tile is larger than the image, since the library decodes a tile at a time.
inline double valuesToRead(const OIIO::ImageSpec& spec) {
    const double width = spec.tile_width > spec.width ? spec.tile_width : spec.width;
    const double height = spec.tile_height > spec.height ? spec.tile_height : spec.height;
    return width * height * double(spec.nchannels);
}

}  // namespace gibench
