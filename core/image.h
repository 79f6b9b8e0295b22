#pragma once
// Float images and their files: multi-layer OpenEXR for data, PNG for looking at.

#include "core/math.h"

#include <filesystem>
#include <string>
#include <vector>

namespace gibench {

// `channels` interleaved floats per pixel, rows from the top, pixels from the left.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> data;

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f) : width(w), height(h), channels(c), data(std::size_t(w) * h * c, fill) {}

    std::size_t pixelCount() const { return std::size_t(width) * height; }
    float& at(int x, int y, int c) { return data[(std::size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return data[(std::size_t(y) * width + x) * channels + c]; }
    vec3 rgb(int x, int y) const { return vec3(at(x, y, 0), at(x, y, 1), at(x, y, 2)); }
    void setRgb(int x, int y, const vec3& v) {
        at(x, y, 0) = v.x;
        at(x, y, 1) = v.y;
        at(x, y, 2) = v.z;
    }
};

// One named layer of a multi-layer image: "total" (R,G,B), "direct", "indirect", "albedo",
// "normal" (X,Y,Z), "depth" (Z), "variance" (R,G,B), ...
struct Layer {
    std::string name;
    std::vector<std::string> channelNames;  // e.g. {"R","G","B"}; size == image.channels
    Image image;
};

// Every AOV of one rendered frame. In an EXR file the "total" layer is stored as the plain
// channels R,G,B (what viewers show first) and every other layer as "name.channel".
struct LayeredImage {
    int width = 0;
    int height = 0;
    std::vector<Layer> layers;

    LayeredImage() = default;
    LayeredImage(int w, int h) : width(w), height(h) {}

    // Adds a zero-filled layer and returns its image.
    Image& add(const std::string& name, std::vector<std::string> channelNames);
    const Layer* find(const std::string& name) const;
    Layer* find(const std::string& name);
};

// Writes all layers as 32-bit float channels; throws std::runtime_error on I/O failure.
void writeExr(const std::filesystem::path& file, const LayeredImage& image);

// Reads any image OpenImageIO reads. Plain R,G,B (and A, dropped) become layer "total";
// "name.C" channels become layer "name". Throws InputError naming the file on failure.
LayeredImage readLayeredImage(const std::filesystem::path& file);

// 8-bit sRGB PNG of an RGB image: radiance × 2^exposure, clamped to [0,1], sRGB-encoded.
void writePng(const std::filesystem::path& file, const Image& rgb, float exposure = 0.0f);

}  // namespace gibench
