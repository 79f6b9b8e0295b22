// Bounded history (issue 9 item 3): a cache forgets the light it saw before a change within a
// bounded number of frames, for every store, and reaches the path-traced reference of the scene
// after the change.

#include "support/render_helpers.h"

#include "methods/probe_cache/probe_cache.h"
#include "methods/probe_cache/stores/store_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

namespace gibench {
namespace {

double meanIndirect(const LayeredImage& image) {
    double sum = 0.0;
    for (const float v : image.find("indirect")->image.data) sum += v;
    return sum / double(image.find("indirect")->image.data.size());
}

// The mean indirect light of each of `frames` frames of `method`, rendered in `before` up to
// frame `change` and in `after` from then on (sceneChanged on that frame, as a scheduled event
// sets it: experiments/scene_events.h).
std::vector<double> indirectAfterChange(const PreparedScene& before, const PreparedScene& after, const CameraDesc& camera, const Json& method,
                                        int change, int frames) {
    std::unique_ptr<Method> m = test::createMethod(method);
    RunNotes notes;
    m->prepare(before, camera.width, camera.height, notes);
    std::vector<double> indirect;
    for (int f = 0; f < frames; ++f) {
        const PreparedScene& scene = f < change ? before : after;
        StageTimer timer;
        LayeredImage image(camera.width, camera.height);
        FrameContext ctx{scene, camera.poseAt(float(f)).relativeTo(scene.scene.worldOrigin), camera.width, camera.height, f, frames, false, 1, timer, false};
        ctx.sceneChanged = f == change && change > 0;
        m->renderFrame(ctx, image);
        indirect.push_back(meanIndirect(image));
    }
    return indirect;
}

// Frames after `change` until `series` stays within `tolerance` of `target` to its end.
int framesUntilWithin(const std::vector<double>& series, int change, double target, double tolerance) {
    int last = int(series.size());
    while (last > change && std::fabs(series[std::size_t(last) - 1] / target - 1.0) <= tolerance) --last;
    return last - change;
}

// The built-in Cornell box with a second, dimmer light low on the red wall (facing into the room),
// the ceiling light's emission scaled by `ceiling`.
Scene cornellWithTwoLights(float ceiling) {
    Json json = loadJsonFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    json["materials"]["light"]["emission"] = {17.0 * ceiling, 12.0 * ceiling, 4.0 * ceiling};
    json["materials"]["lamp"] = {{"type", "diffuse"}, {"albedo", 0.78}, {"emission", 1.0}};
    json["shapes"].push_back({{"type", "quad"},
                              {"name", "lamp"},
                              {"material", "lamp"},
                              {"vertices", {{0.55, 0.05, 0.1}, {0.55, 0.05, 0.25}, {0.55, 0.2, 0.25}, {0.55, 0.2, 0.1}}}});
    return test::sceneFromJson(json);
}

TEST(ProbeCacheHistory, AfterALightIsSwitchedOffEveryStoresIndirectLightReachesTheNewReferenceWithinABoundedNumberOfFrames) {
    // The Cornell box lit by its ceiling light and a lamp on the red wall; on frame 48 the ceiling
    // light goes out, which leaves a sixth of the indirect light. 8 H frames later (H the default
    // history), each store's mean indirect light is within 10 % of the path-traced reference of
    // the lamp alone.
    // Why 8 H: the excess light e decays as e^(−(1 − f) t / H), f the share of a probe's samples
    // that the recursive update reads back from probes that are themselves still catching up;
    // measured here, e falls from 5.5 with a time constant of about 1.9 H (f ≈ 0.47), so it takes
    // ln(55) · 1.9 H ≈ 7.6 H to reach 0.1 (every store stays within 10 % from 222–244 frames after
    // the switch on, 7–7.6 H; the test prints it). In frames the bound holds only where probes get
    // samples: one probe sampled every k frames keeps its stale value for k frames whatever H
    // (32² here, cells of 0.07: each probe gets a sample every frame or two;
    // configs/experiments/light_switch measures the default cells at 128²). Without a bound (the
    // unbounded history, a running mean) the lit frames stay in every mean: about 3× the light.
    constexpr int kChange = 48;
    const int history = int(ProbePipelineSettings{}.historyFrames), framesToFollow = 8 * history;
    constexpr double kSpacing = 0.07;
    const auto unbounded = [](Json method) {
        method["history"] = kUnboundedHistory;
        return method;
    };
    const PreparedScene bothLights(cornellWithTwoLights(1.0f)), lampOnly(cornellWithTwoLights(0.0f));
    CameraDesc camera = *bothLights.scene.camera;
    camera.width = camera.height = 32;
    const double reference =
        meanIndirect(test::render(lampOnly, camera, {{"name", "path_traced"}, {"spp", 4096}, {"sampler", "independent"}}, 7));
    const double lit = meanIndirect(test::render(bothLights, camera, {{"name", "path_traced"}, {"spp", 1024}, {"sampler", "independent"}}, 7));
    ASSERT_GT(lit / reference, 4.0) << "the ceiling light is meant to dominate the indirect light before the switch";
    const int frames = kChange + framesToFollow;
    for (const ProbeStoreInfo& store : probeStoreTable()) {
        const Json method = {{"name", store.name}, {store.spacingKey, kSpacing}};
        const std::vector<double> followed = indirectAfterChange(bothLights, lampOnly, camera, method, kChange, frames);
        EXPECT_NEAR(followed.back() / reference, 1.0, 0.1) << store.name << ": " << framesToFollow << " frames after the switch, history " << history;
        const double remembered = indirectAfterChange(bothLights, lampOnly, camera, unbounded(method), kChange, frames).back();
        EXPECT_GT(remembered / reference, 2.0) << store.name << ": the unbounded history";
        std::cout << "[ history  ] " << store.name << ": indirect / reference " << followed.back() / reference << " " << framesToFollow
                  << " frames after the switch, within 10 % from " << framesUntilWithin(followed, kChange, reference, 0.1)
                  << " frames after it on (unbounded history: " << remembered / reference << ")\n";
    }
}

}  // namespace
}  // namespace gibench
