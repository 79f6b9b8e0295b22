#pragma once
// `gibench compare`: error metrics of one image file against a reference file.

#include "core/config/params.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gibench {

// Reads both files (any format readLayeredImage reads), takes layer `layer` of each and returns
//   {"test": TEST, "reference": REFERENCE, "layer": LAYER, "width": W, "height": H,
//    "metrics": toJson(computeMetrics(...)) plus "flip_ldr" or "flip_hdr" (the FLIP map's mean),
//    "flip": {"kind": "ldr"|"hdr", "mean", "median", "max", "pixels_per_degree",
//             and for "hdr" "start_exposure", "stop_exposure", "exposures"},
//    "error_map": FILE (only when written)}.
// Values are compared linear: files whose colour space (readImageEncoding()) is "sRGB" (PNG,
// JPEG) are decoded with srgbDecode(), "Linear" ones (EXR, HDR) and floating-point ones that name
// none are taken as stored, any other is refused ("FILE: expected linear or sRGB values, got
// colour space \"Gamma1.8\" ..."). FLIP (core/image/flip.h, at the default 67 pixels per degree) is
// LDR-FLIP ("flip_ldr") when both files are sRGB and HDR-FLIP ("flip_hdr") otherwise.
// When `errorMapExr` is set, writes there an EXR with one-channel layers "squared_error",
// "relmse", "smape" and "flip" (channel "Y", i.e. "squared_error.Y", ...): errorMap() of each
// kind and the FLIP map, which viewers show as grey, through a temporary file (no half-written
// map is left). Throws
// InputError naming the file for an unreadable file, a missing layer ("FILE: no layer \"L\"
// (layers: total, direct, ...)"), a layer with fewer than 3 channels, a NaN or infinity in its
// first 3 channels (requireFinite(); the metrics and maps of such an image would not be numbers),
// or sizes that differ ("TEST: expected the size of reference REFERENCE (WxH), got WxH"), and,
// before reading, for file names that are not UTF-8 (checkUtf8Path(): the output names them) and
// naming --error-map when its folder does not exist;
// std::runtime_error when the error map cannot be written.
Json compareImages(const std::filesystem::path& test, const std::filesystem::path& reference, const std::string& layer,
                   const std::optional<std::filesystem::path>& errorMapExr);

// `--fail-above METRIC=VALUE`: compare fails when METRIC of its "metrics" is above VALUE.
struct MetricLimit {
    std::string metric;
    double limit = 0.0;
};
// Every name a MetricLimit may use: the keys of "metrics" above.
std::vector<std::string> comparisonMetricNames();
// Throws InputError "--fail-above: expected METRIC=VALUE, VALUE a finite number >= 0 and METRIC one
// of mse, rmse, ..., got \"TEXT\"".
MetricLimit parseMetricLimit(const std::string& text);
// One line per limit that `comparison` (compareImages()'s result) exceeds: "relmse = 0.02 is above
// --fail-above relmse=0.01 by 0.01". Throws InputError naming the option when a limit's metric is
// not in the comparison (flip_ldr asked of HDR inputs, or the other way round).
std::vector<std::string> exceededLimits(const Json& comparison, const std::vector<MetricLimit>& limits);

}  // namespace gibench
