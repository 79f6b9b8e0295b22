#pragma once
// Float images and their files: multi-layer OpenEXR for data, PNG for looking at.

#include "core/util/image_limits.h"
#include "core/util/math.h"

#include <filesystem>
#include <deque>
#include <string>
#include <variant>
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
    std::deque<Layer> layers;  // a deque: add() hands out references that later add()s keep valid

    LayeredImage() = default;
    LayeredImage(int w, int h) : width(w), height(h) {}

    // Adds a zero-filled width × height layer and returns its image (valid until the next add).
    // Layer names are unique: adding an existing name throws std::invalid_argument.
    Image& add(const std::string& name, std::vector<std::string> channelNames);
    // add() of a layer whose every value the caller then writes: its memory is not cleared first
    // (it holds a dropped layer's values, zeros beyond them). Clearing a cache frame's layers was
    // a serial pass over 4.5 MB at 256², 0.3–0.5 ms of its resolve stage.
    Image& addOverwritten(const std::string& name, std::vector<std::string> channelNames);
    // The layer called `name`, or null.
    const Layer* find(const std::string& name) const;
    Layer* find(const std::string& name);

    // Drops every layer but keeps their memory for the next add()s, which refill it: the frame
    // loop's way to start a frame. Fresh layers every frame cost about 1 000 page faults at 256²
    // (4.5 MB), 2.4 ms of a 20 ms cache frame in `gibench run` (docs/performance.md).
    void clearLayersKeepingMemory();

private:
    Image& addLayer(const std::string& name, std::vector<std::string> channelNames, bool cleared);

    std::vector<std::vector<float>> m_spare;  // the memory of dropped layers
};

// A header attribute of an EXR file beyond the channels, e.g. {"gibench:method", "mamba"}: an
// OpenEXR string, int or float attribute of that name.
struct ExrAttribute {
    std::string name;
    std::variant<std::string, int, float> value;
};

// Writes all layers as 32-bit float channels (lossless ZIP compression) to exactly `file`, in
// OpenEXR whatever its extension, with `attributes` in its header. Throws std::runtime_error
// naming the file on I/O failure and std::invalid_argument when a layer's size or channel count
// disagrees with the image.
void writeExr(const std::filesystem::path& file, const LayeredImage& image, const std::vector<ExrAttribute>& attributes = {});

// Reads any image OpenImageIO reads (its first subimage, i.e. the first part of an EXR) as floats.
// Plain R,G,B (and A, dropped) become layer "total", or a lone plain Y becomes "total" with
// R = G = B = Y; any other plain channel C becomes a one-channel layer "C". "name.C" channels
// become layer "name" (split at the last dot), channels in the order OpenImageIO lists them.
// "total" comes first, then the other layers in order of their first channel.
// Throws InputError "FILE: cannot read image: REASON" on failure: missing, truncated or corrupt
// files, and headers claiming more than kMaxImageValues values ("the header claims WxH pixels of
// C channels, ..."). What the image libraries print on their own is captured, not shown: the
// reason is OpenImageIO's message, or theirs when OpenImageIO gives none.
LayeredImage readLayeredImage(const std::filesystem::path& file);

// How the values of an image file are encoded: OpenImageIO's "oiio:ColorSpace" of its first
// subimage ("sRGB" for PNG and JPEG unless they say otherwise, "Linear" for EXR, "" when the file
// says nothing) and whether its pixels are stored as floating point. Reads the header only;
// throws InputError "FILE: cannot read image: REASON" as readLayeredImage() does.
struct ImageEncoding {
    std::string colorSpace;
    bool floatingPoint = false;
};
ImageEncoding readImageEncoding(const std::filesystem::path& file);

// 8-bit sRGB PNG of the first 3 channels: radiance × 2^exposure, clamped to [0,1] (NaN as 0),
// sRGB-encoded, byte = floor(255 · encoded + 0.5). Writes PNG to exactly `file` whatever its
// extension. Throws std::runtime_error naming the file on I/O failure, std::invalid_argument when
// the image has fewer than 3 channels.
void writePng(const std::filesystem::path& file, const Image& rgb, float exposure = 0.0f);

// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0,1]: 12.92·v up to
// 0.0031308, 1.055·v^(1/2.4) − 0.055 above. Shared by PNG output and the perceptual metrics.
double srgbEncode(double linear);
// Its inverse, the sRGB EOTF of an encoded value in [0,1]: v / 12.92 up to 0.04045,
// ((v + 0.055) / 1.055)^2.4 above.
double srgbDecode(double encoded);

}  // namespace gibench
