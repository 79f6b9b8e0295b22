#pragma once
// Names the probe-cache benchmarks register under, shared with main() that prints their ratios.

#include <array>

namespace gibench {

// Scenes of probe_cache/frame/<name>/<scene>.
inline constexpr std::array<const char*, 2> kFrameScenes = {"cornell_box", "sponza"};
// The <name> of the frame every cache frame is measured against: one path-traced sample per pixel.
inline constexpr const char* kPathTracedFrame = "path_traced_1spp";

}  // namespace gibench
