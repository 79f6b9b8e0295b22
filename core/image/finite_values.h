#pragma once
// Non-finite values (NaN, ±inf) in an image: where the first one is and how many there are, so that
// an image gibench is given can be refused before any number is computed from it.

#include "core/image/image.h"

#include <cstddef>
#include <filesystem>
#include <string>

namespace gibench {

struct NonfiniteValues {
    std::size_t count = 0;  // over the checked channels of every pixel
    // The first in scan order (rows from the top, pixels from the left, then channels); valid when count > 0.
    int x = 0, y = 0, channel = 0;
    float value = 0.0f;
};

// The non-finite values among the first `channels` channels of `image` (all of them when
// `channels` is larger than the image's).
NonfiniteValues findNonfinite(const Image& image, int channels);

// The name of a layer's channel as a file holds it: "R" for the "total" layer, "direct.G" otherwise
// (the naming of writeExr and readLayeredImage).
std::string fileChannelName(const Layer& layer, int channel);

// Throws InputError "FILE: channel C: expected finite values, got nan at pixel (X, Y) (x from the
// left, y from the top); N values are not finite" when the first `channels` channels of `layer`
// hold a NaN or an infinity.
void requireFinite(const std::filesystem::path& file, const Layer& layer, int channels);

}  // namespace gibench
