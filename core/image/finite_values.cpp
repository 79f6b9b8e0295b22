#include "core/image/finite_values.h"

#include "core/util/error.h"
#include "core/util/text_format.h"

#include <algorithm>
#include <cmath>

namespace gibench {

NonfiniteValues findNonfinite(const Image& image, int channels) {
    NonfiniteValues found;
    const int checked = std::min(channels, image.channels);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < checked; ++c) {
                const float v = image.at(x, y, c);
                if (std::isfinite(v)) continue;
                if (found.count == 0) {
                    found.x = x;
                    found.y = y;
                    found.channel = c;
                    found.value = v;
                }
                ++found.count;
            }
    return found;
}

std::string fileChannelName(const Layer& layer, int channel) {
    const std::string& name = layer.channelNames.at(std::size_t(channel));
    return layer.name == "total" ? name : layer.name + "." + name;
}

void requireFinite(const std::filesystem::path& file, const Layer& layer, int channels) {
    const NonfiniteValues found = findNonfinite(layer.image, channels);
    if (found.count == 0) return;
    throw InputError(file.string() + ": channel " + fileChannelName(layer, found.channel) + ": expected finite values, got " +
                     formatNumber(found.value) + " at pixel (" + std::to_string(found.x) + ", " + std::to_string(found.y) +
                     ") (x from the left, y from the top); " + std::to_string(found.count) + " values are not finite");
}

}  // namespace gibench
