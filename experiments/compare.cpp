#include "experiments/compare.h"

#include "core/config/input_file.h"
#include "core/image/finite_values.h"
#include "core/image/image.h"
#include "core/image/metrics.h"
#include "core/util/error.h"
#include "experiments/output_dir.h"

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

// The RGB layer `name` of the image read from `file`, or an InputError naming what is there.
Image rgbLayer(const std::filesystem::path& file, const std::string& name) {
    LayeredImage image = readLayeredImage(file);
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
    return std::move(layer->image);
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

    const Image testImage = rgbLayer(test, layer);
    const Image referenceImage = rgbLayer(reference, layer);
    if (testImage.width != referenceImage.width || testImage.height != referenceImage.height)
        throw InputError(test.string() + ": expected the size of reference " + reference.string() + " (" + sizeText(referenceImage) +
                         "), got " + sizeText(testImage));

    result["width"] = testImage.width;
    result["height"] = testImage.height;
    result["metrics"] = toJson(computeMetrics(testImage, referenceImage));
    if (errorMapExr) {
        LayeredImage maps(testImage.width, testImage.height);
        const std::pair<const char*, ErrorMapKind> kinds[] = {
            {"squared_error", ErrorMapKind::SquaredError}, {"relmse", ErrorMapKind::RelMse}, {"smape", ErrorMapKind::Smape}};
        for (const auto& [name, kind] : kinds) maps.add(name, {"Y"}) = errorMap(testImage, referenceImage, kind);
        TemporaryFile temporary(*errorMapExr);
        writeExr(temporary.path(), maps);
        temporary.commit();
    }
    return result;
}

}  // namespace gibench
