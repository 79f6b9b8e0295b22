#include "experiments/compare.h"

#include "core/config/input_file.h"
#include "core/image/finite_values.h"
#include "core/image/flip.h"
#include "core/image/image.h"
#include "core/image/metrics.h"
#include "core/util/error.h"
#include "experiments/output_dir.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace gibench {
namespace {

std::string sizeText(const Image& image) { return std::to_string(image.width) + "x" + std::to_string(image.height); }

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

// An image's values as compare measures them, and whether the file held display (sRGB) values.
struct LinearLayer {
    Image image;
    bool srgb = false;
};

// Whether `file` holds sRGB-encoded values (true) or linear ones (false); refuses any other.
bool isSrgbEncoded(const std::filesystem::path& file) {
    const ImageEncoding encoding = readImageEncoding(file);
    std::string space = encoding.colorSpace;
    std::transform(space.begin(), space.end(), space.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (space == "srgb") return true;
    if (space == "linear" || (space.empty() && encoding.floatingPoint)) return false;
    throw InputError(file.string() + ": expected linear or sRGB values, got " +
                     (space.empty() ? std::string("integer pixels that name no colour space") : "colour space \"" + encoding.colorSpace + "\"") +
                     " (oiio:ColorSpace); compare reads linear files (EXR, HDR, float TIFF) and sRGB ones (PNG, JPEG)");
}

// The RGB layer `name` of the image read from `file`, linear, or an InputError naming what is there.
LinearLayer rgbLayer(const std::filesystem::path& file, const std::string& name) {
    LayeredImage image = readLayeredImage(file);
    const bool srgb = isSrgbEncoded(file);
    Layer* layer = image.find(name);
    if (!layer) {
        std::vector<std::string> names;
        for (const auto& l : image.layers) names.push_back(l.name);
        throw InputError(file.string() + ": no layer \"" + name + "\" (layers: " + joined(names) + ")");
    }
    if (layer->image.channels < 3)
        throw InputError(file.string() + ": layer \"" + name + "\": expected at least 3 channels, got " +
                         std::to_string(layer->image.channels) + " (" + joined(layer->channelNames) + ")");
    requireFinite(file, *layer, 3);
    if (srgb)
        for (float& v : layer->image.data) v = float(srgbDecode(v));
    return {std::move(layer->image), srgb};
}

// FLIP of the pair, as "flip" of the result; LDR-FLIP for display images, HDR-FLIP for radiance.
Json flipJson(const LinearLayer& test, const LinearLayer& reference, Image& map) {
    const bool ldr = test.srgb && reference.srgb;
    Json flip = {{"kind", ldr ? "ldr" : "hdr"}, {"pixels_per_degree", kFlipDefaultPixelsPerDegree}};
    if (ldr) {
        map = ldrFlip(test.image, reference.image);
    } else {
        const FlipExposures exposures = flipExposures(reference.image);
        map = hdrFlip(test.image, reference.image, exposures);
        flip["start_exposure"] = exposures.start;
        flip["stop_exposure"] = exposures.stop;
        flip["exposures"] = exposures.count;
    }
    const FlipStatistics s = flipStatistics(map);
    flip["mean"] = s.mean;
    flip["median"] = s.median;
    flip["max"] = s.max;
    return flip;
}

std::string formatted(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

// The error map's file must go into an existing folder: checked before the images are read.
void checkErrorMapPath(const std::filesystem::path& file) {
    const std::filesystem::path folder = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
    std::error_code error;
    if (!std::filesystem::is_directory(folder, error))
        throw InputError("--error-map: expected a file in an existing folder, got \"" + file.string() + "\" (no folder \"" +
                         folder.string() + "\")");
    if (std::filesystem::is_directory(file, error))
        throw InputError("--error-map: expected a file in an existing folder, got \"" + file.string() + "\", which is a folder");
}

}  // namespace

Json compareImages(const std::filesystem::path& test, const std::filesystem::path& reference, const std::string& layer,
                   const std::optional<std::filesystem::path>& errorMapExr) {
    // The output names the files: names JSON cannot hold are refused before any work.
    checkUtf8Path(test);
    checkUtf8Path(reference);
    if (errorMapExr) {
        checkUtf8Path(*errorMapExr);
        checkErrorMapPath(*errorMapExr);
    }
    Json result = {{"test", test.string()}, {"reference", reference.string()}, {"layer", layer}};
    if (errorMapExr) result["error_map"] = errorMapExr->string();

    const LinearLayer testLayer = rgbLayer(test, layer);
    const LinearLayer referenceLayer = rgbLayer(reference, layer);
    const Image& testImage = testLayer.image;
    const Image& referenceImage = referenceLayer.image;
    if (testImage.width != referenceImage.width || testImage.height != referenceImage.height)
        throw InputError(test.string() + ": expected the size of reference " + reference.string() + " (" + sizeText(referenceImage) +
                         "), got " + sizeText(testImage));

    result["width"] = testImage.width;
    result["height"] = testImage.height;
    result["metrics"] = toJson(computeMetrics(testImage, referenceImage));
    Image flipMap;
    result["flip"] = flipJson(testLayer, referenceLayer, flipMap);
    result["metrics"][result["flip"]["kind"] == "ldr" ? "flip_ldr" : "flip_hdr"] = result["flip"]["mean"];
    if (errorMapExr) {
        LayeredImage maps(testImage.width, testImage.height);
        const std::pair<const char*, ErrorMapKind> kinds[] = {
            {"squared_error", ErrorMapKind::SquaredError}, {"relmse", ErrorMapKind::RelMse}, {"smape", ErrorMapKind::Smape}};
        for (const auto& [name, kind] : kinds) maps.add(name, {"Y"}) = errorMap(testImage, referenceImage, kind);
        maps.add("flip", {"Y"}) = flipMap;
        TemporaryFile temporary(*errorMapExr);
        writeExr(temporary.path(), maps);
        temporary.commit();
    }
    return result;
}

std::vector<std::string> comparisonMetricNames() {
    std::vector<std::string> names;
    const Json metrics = toJson(ImageMetrics{});
    for (const auto& [name, value] : metrics.items()) names.push_back(name);
    names.push_back("flip_ldr");
    names.push_back("flip_hdr");
    return names;
}

MetricLimit parseMetricLimit(const std::string& text) {
    const std::vector<std::string> names = comparisonMetricNames();
    const auto fail = [&] {
        return InputError("--fail-above: expected METRIC=VALUE, VALUE a finite number >= 0 and METRIC one of " + joined(names) +
                          ", got \"" + text + "\"");
    };
    const auto equals = text.find('=');
    if (equals == std::string::npos) throw fail();
    MetricLimit limit{text.substr(0, equals), 0.0};
    const std::string value = text.substr(equals + 1);
    const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), limit.limit);
    if (value.empty() || error != std::errc() || end != value.data() + value.size() || !std::isfinite(limit.limit) || limit.limit < 0.0 ||
        std::find(names.begin(), names.end(), limit.metric) == names.end())
        throw fail();
    return limit;
}

std::vector<std::string> exceededLimits(const Json& comparison, const std::vector<MetricLimit>& limits) {
    std::vector<std::string> exceeded;
    const Json& metrics = comparison.at("metrics");
    for (const MetricLimit& l : limits) {
        if (!metrics.contains(l.metric))
            throw InputError("--fail-above " + l.metric + ": this comparison has no such metric (FLIP is flip_ldr when both files are sRGB, "
                             "flip_hdr otherwise)");
        const double value = metrics[l.metric].get<double>();
        if (value > l.limit)
            exceeded.push_back(l.metric + " = " + formatted(value) + " is above --fail-above " + l.metric + "=" + formatted(l.limit) + " by " +
                               formatted(value - l.limit));
    }
    return exceeded;
}

}  // namespace gibench
