#include "core/image/image.h"

#include "core/image/captured_stderr.h"
#include "core/util/error.h"
#include "core/util/exr_header_check.h"
#include "core/util/pixel_read.h"
#include "core/util/text_format.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <variant>

namespace gibench {
namespace {

// Where each channel of a layer comes from in the file's interleaved pixels.
struct LayerSource {
    std::string name;
    std::vector<std::string> channelNames;
    std::vector<int> fileChannels;
};

[[noreturn]] void failWrite(const std::filesystem::path& file, const std::string& reason) {
    throw std::runtime_error(file.string() + ": cannot write image: " + reason);
}

// Opens, writes and closes in one go; `format` names the OpenImageIO plugin so that the file's
// extension (e.g. a temporary "x.exr.tmp") does not decide the format.
void writeWithFormat(const std::filesystem::path& file, const char* format, const OIIO::ImageSpec& spec, const void* pixels) {
    const auto out = OIIO::ImageOutput::create(format);
    if (!out) failWrite(file, OIIO::geterror());
    if (!out->open(file.string(), spec)) failWrite(file, out->geterror());
    if (!out->write_image(spec.format, pixels)) failWrite(file, out->geterror());
    if (!out->close()) failWrite(file, out->geterror());
}

// Groups the file's channels into layers following the rules in image.h.
std::vector<LayerSource> layerSources(const std::vector<std::string>& fileNames) {
    std::vector<LayerSource> layers;
    auto layerNamed = [&](const std::string& name) -> LayerSource& {
        for (auto& l : layers)
            if (l.name == name) return l;
        return layers.emplace_back(LayerSource{name, {}, {}});
    };
    auto plainIndex = [&](const std::string& channel) {
        const auto it = std::find(fileNames.begin(), fileNames.end(), channel);
        return it == fileNames.end() ? -1 : int(it - fileNames.begin());
    };

    const int r = plainIndex("R"), g = plainIndex("G"), b = plainIndex("B"), y = plainIndex("Y"), a = plainIndex("A");
    std::vector<bool> used(fileNames.size(), false);
    if (a >= 0) used[a] = true;
    if (r >= 0 && g >= 0 && b >= 0) {
        layers.push_back({"total", {"R", "G", "B"}, {r, g, b}});
        used[r] = used[g] = used[b] = true;
    } else if (y >= 0) {
        layers.push_back({"total", {"R", "G", "B"}, {y, y, y}});
        used[y] = true;
    }

    for (int i = 0; i < int(fileNames.size()); ++i) {
        if (used[i]) continue;
        const std::string& full = fileNames[i];
        const auto dot = full.rfind('.');
        const bool plain = dot == std::string::npos;
        LayerSource& l = layerNamed(plain ? full : full.substr(0, dot));
        l.channelNames.push_back(plain ? full : full.substr(dot + 1));
        l.fileChannels.push_back(i);
    }
    return layers;
}

}  // namespace

Image& LayeredImage::add(const std::string& name, std::vector<std::string> channelNames) { return addLayer(name, std::move(channelNames), true); }

Image& LayeredImage::addOverwritten(const std::string& name, std::vector<std::string> channelNames) {
    return addLayer(name, std::move(channelNames), false);
}

Image& LayeredImage::addLayer(const std::string& name, std::vector<std::string> channelNames, bool cleared) {
    if (find(name)) throw std::invalid_argument("LayeredImage::add: layer \"" + name + "\" already exists");
    const int channels = int(channelNames.size());
    const std::size_t size = std::size_t(width) * height * std::size_t(channels);
    // The smallest kept memory that holds the layer, if any.
    auto fits = m_spare.end();
    for (auto it = m_spare.begin(); it != m_spare.end(); ++it)
        if (it->capacity() >= size && (fits == m_spare.end() || it->capacity() < fits->capacity())) fits = it;
    if (fits == m_spare.end()) {
        layers.push_back(Layer{name, std::move(channelNames), Image(width, height, channels)});
    } else {
        Image image;
        image.width = width;
        image.height = height;
        image.channels = channels;
        image.data = std::move(*fits);
        m_spare.erase(fits);
        if (cleared)
            image.data.assign(size, 0.0f);
        else
            image.data.resize(size);
        layers.push_back(Layer{name, std::move(channelNames), std::move(image)});
    }
    return layers.back().image;
}

void LayeredImage::clearLayersKeepingMemory() {
    for (Layer& layer : layers) m_spare.push_back(std::move(layer.image.data));
    layers.clear();
}

const Layer* LayeredImage::find(const std::string& name) const {
    for (const auto& l : layers)
        if (l.name == name) return &l;
    return nullptr;
}

Layer* LayeredImage::find(const std::string& name) {
    return const_cast<Layer*>(std::as_const(*this).find(name));
}

void writeExr(const std::filesystem::path& file, const LayeredImage& image, const std::vector<ExrAttribute>& attributes) {
    std::vector<std::string> names;
    for (const auto& l : image.layers) {
        if (l.image.width != image.width || l.image.height != image.height || int(l.channelNames.size()) != l.image.channels)
            throw std::invalid_argument(file.string() + ": layer \"" + l.name + "\" is " + std::to_string(l.image.width) + "x" +
                                        std::to_string(l.image.height) + " with " + std::to_string(l.image.channels) + " channels and " +
                                        std::to_string(l.channelNames.size()) + " channel names, the image is " +
                                        std::to_string(image.width) + "x" + std::to_string(image.height));
        for (const auto& c : l.channelNames) names.push_back(l.name == "total" ? c : l.name + "." + c);
    }

    const int channels = int(names.size());
    std::vector<float> pixels(std::size_t(image.width) * image.height * channels);
    int first = 0;
    for (const auto& l : image.layers) {
        for (std::size_t p = 0; p < l.image.pixelCount(); ++p)
            for (int c = 0; c < l.image.channels; ++c) pixels[p * channels + first + c] = l.image.data[p * l.image.channels + c];
        first += l.image.channels;
    }

    OIIO::ImageSpec spec(image.width, image.height, channels, OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    // The constructor guessed R,G,B,A names and an alpha channel; our names carry no such role.
    spec.alpha_channel = -1;
    spec.z_channel = -1;
    spec.attribute("compression", "zip");
    // OpenEXR stamps files with the time of writing unless told a DateTime; an empty one keeps
    // the same pixels the same bytes (runs record their time in the manifest instead).
    spec.attribute("DateTime", "");
    for (const ExrAttribute& a : attributes) std::visit([&](const auto& value) { spec.attribute(a.name, value); }, a.value);
    writeWithFormat(file, "openexr", spec, pixels.data());
}

LayeredImage readLayeredImage(const std::filesystem::path& file) {
    const CapturedStderr libraryOutput;
    auto fail = [&](std::string reason) {
        if (reason.empty()) reason = libraryOutput.text();
        if (reason.empty()) reason = "no reason given by the image library";
        return InputError(file.string() + ": cannot read image: " + reason);
    };
    // Alpha is dropped, so colour must stay as stored rather than premultiplied by it (PNG, TIFF).
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    checkExrHeader(file);
    const auto in = OIIO::ImageInput::open(file.string(), &config);
    if (!in) throw fail(OIIO::geterror());
    const OIIO::ImageSpec spec = in->spec();
    if (spec.depth != 1) throw fail("volume images (depth " + std::to_string(spec.depth) + ") are not supported");
    const double values = valuesToRead(spec);
    const std::string claimed = "the header claims " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " pixels of " +
                                std::to_string(spec.nchannels) + " channels" +
                                (spec.tile_width > 0 ? " in tiles of " + std::to_string(spec.tile_width) + "x" + std::to_string(spec.tile_height) : "");
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1) throw fail(claimed);
    if (values > kMaxImageValues)
        throw fail(claimed + ", " + formatCount(values) + " values, more than the " + formatCount(kMaxImageValues) +
                   " (4 GiB of floats) gibench reads");

    const int channels = spec.nchannels;
    std::vector<float> pixels(std::size_t(spec.width) * spec.height * channels);
    if (!readPixels(*in, channels, OIIO::TypeDesc::FLOAT, pixels.data())) throw fail(in->geterror());

    LayeredImage image(spec.width, spec.height);
    for (const auto& source : layerSources(spec.channelnames)) {
        Image& layer = image.add(source.name, source.channelNames);
        for (std::size_t p = 0; p < layer.pixelCount(); ++p)
            for (int c = 0; c < layer.channels; ++c) layer.data[p * layer.channels + c] = pixels[p * channels + source.fileChannels[c]];
    }
    return image;
}

ImageEncoding readImageEncoding(const std::filesystem::path& file) {
    const CapturedStderr libraryOutput;
    checkExrHeader(file);
    const auto in = OIIO::ImageInput::open(file.string());
    if (!in) {
        std::string reason = OIIO::geterror();
        if (reason.empty()) reason = libraryOutput.text();
        throw InputError(file.string() + ": cannot read image: " + (reason.empty() ? "no reason given by the image library" : reason));
    }
    const OIIO::ImageSpec& spec = in->spec();
    return {spec.get_string_attribute("oiio:ColorSpace"), spec.format.is_floating_point()};
}

double srgbDecode(double encoded) {
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

double srgbEncode(double linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

void writePng(const std::filesystem::path& file, const Image& rgb, float exposure) {
    if (rgb.channels < 3)
        throw std::invalid_argument(file.string() + ": writePng needs at least 3 channels, got " + std::to_string(rgb.channels));
    const float scale = std::exp2(exposure);
    std::vector<std::uint8_t> bytes(rgb.pixelCount() * 3);
    for (std::size_t p = 0; p < rgb.pixelCount(); ++p)
        for (int c = 0; c < 3; ++c) {
            const float v = rgb.data[p * rgb.channels + c] * scale;
            const double clamped = std::isnan(v) ? 0.0 : std::clamp(double(v), 0.0, 1.0);
            bytes[p * 3 + c] = std::uint8_t(std::floor(255.0 * srgbEncode(clamped) + 0.5));
        }

    OIIO::ImageSpec spec(rgb.width, rgb.height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    writeWithFormat(file, "png", spec, bytes.data());
}

}  // namespace gibench
