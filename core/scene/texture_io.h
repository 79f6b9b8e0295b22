#pragma once
// Image files as textures: albedo maps and environment maps, in linear RGB.

#include "core/scene/scene.h"

#include <filesystem>

namespace gibench {

// Reads the first image of `file` with OpenImageIO as linear RGB texels, rows from the top.
// Integer files (8- or 16-bit JPEG, PNG, ...) are decoded with the sRGB curve unless the file
// declares itself linear (OpenImageIO's "oiio:ColorSpace"); float files (EXR, HDR) are kept as
// they are. One channel is grey, copied to R, G and B; with two, the second (alpha) is dropped,
// as is every channel after the third.
// Throws InputError `cannot read image "<file>": <reason>`.
Texture loadTexture(const std::filesystem::path& file);

// The sRGB transfer curve (IEC 61966-2-1) from an encoded value in [0,1] to linear.
float srgbToLinear(float encoded);

}  // namespace gibench
