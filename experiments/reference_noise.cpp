#include "experiments/reference_noise.h"

#include "core/image/metrics.h"

namespace gibench {

Json referenceNoise(const LayeredImage& reference) {
    const Layer* total = reference.find("total");
    const Layer* variance = reference.find("variance");
    if (!total || !variance || total->image.channels < 3 || variance->image.channels < 3) return nullptr;
    if (variance->image.width != total->image.width || variance->image.height != total->image.height) return nullptr;
    const Image& r = total->image;
    const Image& v = variance->image;
    double sum = 0.0;
    for (int y = 0; y < r.height; ++y) {
        double row = 0.0;
        for (int x = 0; x < r.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const double value = r.at(x, y, c);
                row += double(v.at(x, y, c)) / (value * value + kRelMseEpsilon);
            }
        sum += row;
    }
    const double pixels = double(r.width) * double(r.height);
    return {{"total", pixels > 0 ? sum / (3.0 * pixels) : 0.0}};
}

}  // namespace gibench
