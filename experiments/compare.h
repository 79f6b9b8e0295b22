#pragma once
// `gibench compare`: error metrics of one image file against a reference file.

#include "core/config/params.h"

#include <filesystem>
#include <optional>
#include <string>

namespace gibench {

// Reads both files (any format readLayeredImage reads), takes layer `layer` of each and returns
//   {"test": TEST, "reference": REFERENCE, "layer": LAYER, "width": W, "height": H,
//    "metrics": toJson(computeMetrics(...)), "error_map": FILE (only when written)}.
// When `errorMapExr` is set, writes there an EXR with one-channel layers "squared_error",
// "relmse" and "smape" (channel "Y", i.e. "squared_error.Y", ...): errorMap() of each kind,
// which viewers show as grey, through a temporary file (no half-written map is left). Throws
// InputError naming the file for an unreadable file, a missing layer ("FILE: no layer \"L\"
// (layers: total, direct, ...)"), a layer with fewer than 3 channels, a NaN or infinity in its
// first 3 channels (requireFinite(); the metrics and maps of such an image would not be numbers),
// or sizes that differ ("TEST: expected the size of reference REFERENCE (WxH), got WxH"), and,
// before reading, for file names that are not UTF-8 (checkUtf8Path(): the output names them) and
// naming --error-map when its folder does not exist;
// std::runtime_error when the error map cannot be written.
Json compareImages(const std::filesystem::path& test, const std::filesystem::path& reference, const std::string& layer,
                   const std::optional<std::filesystem::path>& errorMapExr);

}  // namespace gibench
