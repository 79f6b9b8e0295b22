#pragma once
// Reference images: high-spp path-traced renders keyed by a hash of everything that changes the
// image (scene JSON and the content of every file it reads, camera, resolution, path tracer
// settings, seed), kept in <output root>/references/<key>.exr so any run of the same scene and
// camera finds it. An external reference (Mitsuba, pbrt, Cycles, ...) can be named instead.
//
// A reference shows one camera pose: the last keyframe's. Frames of a run at that pose (every
// frame of a static camera) are measured against it. A run whose scene changes (events,
// scene_events.h) has one reference per segment, keyed by the events applied before it; every
// function below takes the segment's first frame (0: the scene as loaded).

#include "core/image/image.h"
#include "experiments/run_config.h"

#include <filesystem>
#include <optional>

namespace gibench {

WorldPose referencePose(const CameraDesc& camera);
// SHA-256 of the canonical JSON of the key's inputs; throws if the run has no rendered reference.
std::string referenceKey(const RunConfig& config, int segmentStart = 0);
// Where the run's reference image is (or would be) stored.
std::filesystem::path referencePath(const RunConfig& config, int segmentStart = 0);

struct ReferenceOutcome {
    std::filesystem::path image;
    bool rendered = false;  // false: an existing image was reused
    double seconds = 0.0;
};

// Renders the reference unless it exists (or `force`); requires "reference" settings in the config.
// Writes <key>.exr and its record <key>.json through temporary files: a failure leaves neither
// half-written, and the record's strings are checked (InputError) before the render.
ReferenceOutcome ensureReference(const RunConfig& config, bool force, bool showProgress, int segmentStart = 0);

// Whether runs are measured on this layer of a reference: one with at least 3 channels (radiance,
// albedo, normal), except "variance", which describes a render's noise, not its image.
bool isMeasured(const Layer& referenceLayer);

// The run's reference image when it exists; nullopt when it was never rendered. Throws
// InputError naming the file when it has no RGB (or Y) channels ("expected channels R, G, B (or
// Y), found ...") or when a measured layer holds a NaN or an infinity (requireFinite()).
std::optional<LayeredImage> loadReference(const RunConfig& config, int segmentStart = 0);

}  // namespace gibench
