// Scheduled scene changes (experiments/scene_events.h): what a config may ask, what the scene of
// each segment is, the references per segment, and the recovery table (event_recovery.h).

#include "experiments/event_recovery.h"
#include "experiments/reference.h"
#include "experiments/run.h"
#include "experiments/scene_events.h"

#include "support/temp_folder.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

#include <fstream>

namespace gibench {
namespace {

Json cornellRun(const TempFolder& dir, const Json& events, int frames = 8) {
    return {{"experiment", "events"},
            {"run", "r"},
            {"scene", std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"},
            {"camera", {{"resolution", {16, 16}}}},
            {"frames", frames},
            {"events", events},
            {"method", {{"name", "path_traced"}, {"spp", 4}}},
            {"reference", {{"spp", 64}}},
            {"output", {{"root", (dir / "results").string()}}}};
}

std::string errorOf(const TempFolder& dir, const Json& config) {
    try {
        loadRunConfig(dir.write("run.json", config.dump()));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(SceneEvents, EachChangeAppliesFromItsFrameOnRelativeToTheSceneAsLoaded) {
    TempFolder dir;
    const RunConfig config = loadRunConfig(dir.write("run.json", cornellRun(dir, Json::parse(R"([
        {"frame": 6, "type": "move", "shape": "tall_block_top", "translate": [0, 0.1, 0]},
        {"frame": 3, "type": "emission", "material": "light", "scale": 0.5},
        {"frame": 6, "type": "emission", "material": "light", "scale": 0}
    ])")).dump()));
    ASSERT_EQ(config.events.size(), 3u);
    EXPECT_EQ(config.events[0].frame, 3) << "sorted by frame";
    EXPECT_EQ(segmentStarts(config.events), (std::vector<int>{0, 3, 6}));
    const Scene& loaded = *config.scene;
    const auto light = std::find_if(loaded.materials.begin(), loaded.materials.end(), [](const Material& m) { return m.name == "light"; });
    const std::size_t l = std::size_t(light - loaded.materials.begin());
    const auto top = std::find_if(loaded.meshes.begin(), loaded.meshes.end(), [](const Mesh& m) { return m.name == "tall_block_top"; });
    ASSERT_NE(top, loaded.meshes.end());
    const std::size_t t = std::size_t(top - loaded.meshes.begin());

    const Scene first = sceneOfSegment(loaded, config.events, 0), dimmed = sceneOfSegment(loaded, config.events, 3),
                last = sceneOfSegment(loaded, config.events, 6);
    EXPECT_EQ(first.materials[l].emission, loaded.materials[l].emission);
    EXPECT_EQ(dimmed.materials[l].emission, loaded.materials[l].emission * 0.5f);
    EXPECT_EQ(last.materials[l].emission, Color(0.0f)) << "scaled from the loaded emission, switched off";
    EXPECT_EQ(dimmed.meshes[t].positions, loaded.meshes[t].positions);
    for (std::size_t v = 0; v < loaded.meshes[t].positions.size(); ++v)
        EXPECT_EQ(last.meshes[t].positions[v], loaded.meshes[t].positions[v] + vec3(0, 0.1f, 0));
    EXPECT_EQ(config.resolved["events"].size(), 3u) << "the manifest records the events";
}

TEST(SceneEvents, SegmentsShowingTheSameSceneShareTheirReference) {
    TempFolder dir;
    const RunConfig config = loadRunConfig(dir.write("run.json", cornellRun(dir, Json::parse(R"([
        {"frame": 2, "type": "emission", "material": "light", "scale": 0},
        {"frame": 4, "type": "emission", "material": "light", "scale": 1},
        {"frame": 5, "type": "move", "shape": "tall_block_top", "translate": [0, 0.1, 0]},
        {"frame": 6, "type": "move", "shape": "tall_block_top", "translate": [0, 0, 0]}
    ])")).dump()));
    EXPECT_EQ(referenceKey(config, 4), referenceKey(config, 0)) << "the light back on";
    EXPECT_NE(referenceKey(config, 2), referenceKey(config, 0));
    EXPECT_NE(referenceKey(config, 5), referenceKey(config, 0));
    EXPECT_EQ(referenceKey(config, 6), referenceKey(config, 0)) << "the block back where it was loaded";
}

TEST(SceneEvents, AnEventNamingNothingOfTheSceneOrAFrameTheRunNeverRendersIsAnInputErrorNamingTheKey) {
    TempFolder dir;
    const std::string file = (dir / "run.json").string();
    EXPECT_EQ(errorOf(dir, cornellRun(dir, {{{"frame", 2}, {"type", "emission"}, {"material", "white"}, {"scale", 0}}})),
              file + ": /events/0/material: expected an emissive material of the scene (\"light\"), got \"white\"");
    EXPECT_EQ(errorOf(dir, cornellRun(dir, {{{"frame", 8}, {"type", "emission"}, {"material", "light"}, {"scale", 0}}})),
              file + ": /events/0/frame: expected a frame the run renders, 1 to 7 (\"frames\" is 8), got 8");
    EXPECT_EQ(errorOf(dir, cornellRun(dir, {{{"frame", 2}, {"type", "sun"}, {"direction", {0, -1, 0}}}})),
              file + ": /events/0/sun: expected a sun of the scene, which has none");
    const std::string noShape = errorOf(dir, cornellRun(dir, {{{"frame", 2}, {"type", "move"}, {"shape", "teapot"}, {"translate", {0, 1, 0}}}}));
    EXPECT_NE(noShape.find(file + ": /events/0/shape: expected a shape of the scene (\"floor\", "), std::string::npos) << noShape;
    EXPECT_NE(errorOf(dir, cornellRun(dir, {{{"frame", 2}, {"type", "dim"}}})).find("/events/0/type"), std::string::npos);
    EXPECT_NE(errorOf(dir, cornellRun(dir, {{{"frame", 2}, {"type", "emission"}, {"material", "light"}, {"scale", 0}, {"colour", 1}}}))
                  .find("/events/0/colour: unknown key for event \"emission\" (known: frame, material, scale)"),
              std::string::npos)
        << "unknown keys are refused";
    Json external = cornellRun(dir, {{{"frame", 2}, {"type", "emission"}, {"material", "light"}, {"scale", 0}}});
    external["reference"] = {{"file", dir.write("ref.exr", "x").string()}};
    EXPECT_EQ(errorOf(dir, external), file + ": /events: a run whose scene changes is measured against a rendered reference per segment, not one \"file\"");
}

TEST(SceneEvents, EverySegmentHasItsOwnReferenceAndThePathTracerIsBackOnTheNewOneAtOnce) {
    // The path tracer keeps nothing across a change (its accumulation restarts): right after the
    // light is dimmed to a quarter its image matches the new reference as closely as before.
    TempFolder dir;
    RunConfig config = loadRunConfig(dir.write("run.json", cornellRun(dir, {{{"frame", 4}, {"type", "emission"}, {"material", "light"}, {"scale", 0.25}}}).dump()));
    EXPECT_NE(referenceKey(config, 0), referenceKey(config, 4));
    for (const int segment : segmentStarts(config.events)) ensureReference(config, false, false, segment);
    const LayeredImage bright = *loadReference(config, 0), dim = *loadReference(config, 4);
    const Image& a = bright.find("total")->image;
    const Image& b = dim.find("total")->image;
    double sumA = 0.0, sumB = 0.0;
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        sumA += a.data[i];
        sumB += b.data[i];
    }
    EXPECT_NEAR(sumB / sumA, 0.25, 1e-6) << "light is linear in the emission; the same seed draws the same paths";

    const RunResult result = executeRun(config, false);
    const Json& events = result.metrics.at("events");
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0]["frame"], 4);
    const Json& total = events[0]["total"];
    ASSERT_TRUE(total["before"].is_number() && total["first"].is_number()) << total.dump();
    // 4 spp against the new reference on frame 4, as on frame 0 against the old one: unbiased at
    // once (16 × 16 pixels of 4 samples each leave the mean a few percent of noise).
    EXPECT_NEAR(total["mean_ratio_first"].get<double>(), 1.0, 0.15) << total.dump();
    EXPECT_NEAR(total["mean_ratio_end"].get<double>(), 1.0, 0.1) << total.dump();
    EXPECT_EQ(result.metrics["reference"]["segments"].size(), 2u);
    std::ifstream frames(result.directory / "frames.jsonl");
    std::string line;
    int changed = 0;
    while (std::getline(frames, line)) changed += Json::parse(line).contains("scene_changed");
    EXPECT_EQ(changed, 1) << "frame 4's record says the scene changed";
}

Json frameRecord(int frame, double seconds, double relMse) {
    return {{"frame", frame}, {"cumulative_seconds", seconds}, {"error", {{"total", {{"relmse", relMse}, {"mean", 2.0}, {"reference_mean", 1.0}}}}}};
}

TEST(EventRecovery, FramesAndSecondsBackWithinTenPercentAndTheLagToHalfwayAreCountedFromTheEventsFrame) {
    // Error 0.1 before the change at frame 3, 0.9 on it, then 0.5, 0.2, 0.105: halfway (0.5) on
    // the second frame, within 10 % of 0.1 (0.11) on the fourth.
    SceneEvent e;
    e.frame = 3;
    e.resolved = {{"type", "emission"}};
    const std::vector<double> errors = {0.3, 0.2, 0.1, 0.9, 0.5, 0.2, 0.105, 0.1};
    std::vector<Json> frames;
    for (int f = 0; f < int(errors.size()); ++f) frames.push_back(frameRecord(f, 0.5 * (f + 1), errors[std::size_t(f)]));
    const Json out = eventRecovery({e}, frames);
    ASSERT_EQ(out.size(), 1u);
    const Json& total = out[0]["total"];
    EXPECT_EQ(total["before"], 0.1);
    EXPECT_EQ(total["first"], 0.9);
    EXPECT_EQ(total["lag_frames"], 2);
    EXPECT_EQ(total["recovery_frames"], 4);
    EXPECT_DOUBLE_EQ(total["recovery_seconds"].get<double>(), 3.5 - 1.5) << "frames 3 to 6, 0.5 s each";
    EXPECT_EQ(total["end"], 0.1);
    EXPECT_EQ(total["mean_ratio_end"], 2.0);
    EXPECT_TRUE(out[0]["indirect"]["before"].is_null()) << "a layer never measured";

    // Never back within the segment: null, not the last frame.
    frames.back() = frameRecord(7, 4.0, 0.5);
    frames[6] = frameRecord(6, 3.5, 0.5);
    frames[5] = frameRecord(5, 3.0, 0.5);
    EXPECT_TRUE(eventRecovery({e}, frames)[0]["total"]["recovery_frames"].is_null());
}

}  // namespace
}  // namespace gibench
