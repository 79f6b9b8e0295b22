// Probe views (methods/probe_cache/probe_views.h): the film projection inverts the camera's rays,
// probe_centres marks exactly the pixels probes project onto, probe_splat shows each pixel's
// nearest serving probe alone, and turning the views on changes no other layer.

#include "support/render_helpers.h"

#include "core/scene/scene_loader.h"
#include "methods/probe_cache/probe_views.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>
#include <utility>
#include <vector>

namespace gibench {
namespace {

// A store that holds the probes a test gives it, with a fixed coverage radius: the views read only
// probes() and coverageRadius().
class ListedProbes final : public ProbeStore {
public:
    ListedProbes(std::vector<Probe> probes, float coverage) : m_probes(std::move(probes)), m_coverage(coverage) {}
    ProbeInsert insert(const ProbeQuery&, uint32_t) override { return {ProbeInsert::Status::Refused}; }
    int nearest(const ProbeQuery&, int, ProbeNeighbour*) const override { return 0; }
    std::span<const Probe> probes() const override { return m_probes; }
    float coverageRadius(const ProbeQuery&) const override { return m_coverage; }
    float searchRadius(const ProbeQuery&) const override { return kSearchRings * m_coverage; }
    Json stats() const override { return Json::object(); }

private:
    std::vector<Probe> m_probes;
    float m_coverage;
};

const CameraPose kPose{vec3(0.3f, 0.2f, 2.0f), vec3(0.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 50.0f};
constexpr int kWidth = 24, kHeight = 16;

// A G-buffer of the camera's size that sees no surface anywhere.
GBuffer emptyGBuffer() {
    GBuffer g;
    g.width = kWidth;
    g.height = kHeight;
    g.texels.assign(std::size_t(kWidth) * kHeight, GBufferTexel{});
    return g;
}

// A probe cache's light over `probes` ids, probe i's state holding one sample of radiance
// `radiance[i]` straight down its normal, or none where radiance[i] is negative.
struct EncodingLight {
    std::unique_ptr<ProbeEncoding> encoding = makeProbeEncoding(ProbeEncodingKind::Hemispherical, 5);
    std::unique_ptr<ProbeLight> light = std::make_unique<ProbeLight>(*encoding, ProbeStateFormat::Float32);

    static EncodingLight of(const std::vector<float>& radiance) {
        EncodingLight e;
        e.light->grow(radiance.size());
        std::vector<uint32_t> written;
        for (uint32_t id = 0; id < radiance.size(); ++id) {
            if (radiance[id] < 0.0f) continue;
            e.light->update(id, [&](float* state) { e.encoding->addSample(state, vec3(0, 0, 1), Color(radiance[id]), 1.0f / (2.0f * kPi)); });
        }
        return e;
    }
    static EncodingLight empty(std::size_t probes) { return of(std::vector<float>(probes, -1.0f)); }
};

// The point `distance` along the ray through film position (x, y).
vec3 alongRay(const PinholeCamera& camera, float x, float y, float distance) {
    const Ray ray = camera.generateRay(x, y);
    return ray.origin + distance * ray.direction;
}

TEST(ProbeViews, FilmProjectionInvertsTheCamerasRays) {
    const PinholeCamera camera(kPose, kWidth, kHeight);
    const FilmProjection projection(camera);
    for (const vec2 film : {vec2(0.5f, 0.5f), vec2(3.25f, 11.75f), vec2(23.9f, 0.1f), vec2(12.0f, 8.0f)})
        for (const float distance : {0.01f, 1.0f, 37.0f}) {
            vec2 back;
            ASSERT_TRUE(projection.project(alongRay(camera, film.x, film.y, distance), back));
            EXPECT_NEAR(back.x, film.x, 1e-3f) << "distance " << distance;
            EXPECT_NEAR(back.y, film.y, 1e-3f) << "distance " << distance;
        }
    vec2 back;
    EXPECT_FALSE(projection.project(alongRay(camera, 5.0f, 5.0f, -1.0f), back)) << "behind the camera";
    EXPECT_FALSE(projection.project(camera.position(), back)) << "at the eye";
}

TEST(ProbeViews, CentresMarkExactlyThePixelsProbesProjectOnto) {
    const PinholeCamera camera(kPose, kWidth, kHeight);
    // Two probes on pixel (5, 3) (counted twice), one each on (0, 0), (23, 15) and (10, 7); one
    // behind the camera and one beyond the film's right edge, marked nowhere.
    const std::vector<std::pair<int, int>> onFilm = {{5, 3}, {5, 3}, {0, 0}, {23, 15}, {10, 7}};
    std::vector<Probe> probes;
    for (const auto& [x, y] : onFilm) probes.push_back({alongRay(camera, float(x) + 0.5f, float(y) + 0.5f, 1.5f + 0.1f * float(probes.size())), vec3(0, 0, 1)});
    probes.push_back({alongRay(camera, 8.5f, 8.5f, -2.0f), vec3(0, 0, 1)});
    probes.push_back({alongRay(camera, float(kWidth) + 3.0f, 4.5f, 2.0f), vec3(0, 0, 1)});
    const ListedProbes store(probes, 0.05f);
    const EncodingLight light = EncodingLight::empty(store.idCapacity());
    const GBuffer gbuffer = emptyGBuffer();
    const std::vector<uint8_t> noneServed(gbuffer.texels.size(), 0);
    const std::vector<uint32_t> noOffsets(gbuffer.texels.size(), 0);
    LayeredImage out(kWidth, kHeight);
    addProbeViews(camera, gbuffer, store, *light.light, {nullptr, noOffsets.data(), noneServed.data()}, out);

    const Image& centres = out.find("probe_centres")->image;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            float expected = 0.0f;
            for (const auto& [px, py] : onFilm) expected += (px == x && py == y) ? 1.0f : 0.0f;
            EXPECT_EQ(centres.at(x, y, 0), expected) << "pixel " << x << "," << y;
        }
}

TEST(ProbeViews, APixelsSurfaceWellInFrontOfAProbeHidesIt) {
    const PinholeCamera camera(kPose, kWidth, kHeight);
    const float coverage = 0.05f, distance = 2.0f;
    // Probes on (2, 2), (4, 4), (6, 6), each at `distance`; the surfaces at their pixels lie
    // in front of them by: twice the coverage radius (a wall: hidden), less than it (the probe's
    // own surface: shown), and not at all.
    const std::vector<float> inFront = {2.0f * coverage, 0.5f * coverage, 0.0f};
    std::vector<Probe> probes;
    GBuffer gbuffer = emptyGBuffer();
    for (std::size_t i = 0; i < inFront.size(); ++i) {
        const int p = 2 + 2 * int(i);
        probes.push_back({alongRay(camera, float(p) + 0.5f, float(p) + 0.5f, distance), vec3(0, 0, 1)});
        GBufferTexel& t = gbuffer.texels[std::size_t(p) * kWidth + p];
        t.valid = true;
        t.depth = distance - inFront[i];
        t.surface.position = alongRay(camera, float(p) + 0.5f, float(p) + 0.5f, t.depth);
        t.surface.shadingNormal = vec3(0, 0, 1);
    }
    const ListedProbes store(probes, coverage);
    const EncodingLight light = EncodingLight::empty(store.idCapacity());
    const std::vector<uint8_t> noneServed(gbuffer.texels.size(), 0);
    const std::vector<uint32_t> noOffsets(gbuffer.texels.size(), 0);
    LayeredImage out(kWidth, kHeight);
    addProbeViews(camera, gbuffer, store, *light.light, {nullptr, noOffsets.data(), noneServed.data()}, out);
    const Image& centres = out.find("probe_centres")->image;
    EXPECT_EQ(centres.at(2, 2, 0), 0.0f) << "behind a surface twice the coverage radius in front";
    EXPECT_EQ(centres.at(4, 4, 0), 1.0f) << "on its own surface, within the coverage radius";
    EXPECT_EQ(centres.at(6, 6, 0), 1.0f);
}

TEST(ProbeViews, SplatShowsTheNearestServingProbeWithSamplesAlone) {
    const PinholeCamera camera(kPose, kWidth, kHeight);
    // Pixel (0, 0) is served by probe 1 only; pixel (1, 0) by probes 0 (far), 2 (near) and 3
    // (nearest, but without samples) with weights that favour the others; pixel (2, 0) by probe 3
    // only; pixel (3, 0) sees no surface though a probe is listed.
    const vec3 at(0.0f, 0.0f, 0.0f);
    const std::vector<Probe> probes = {{at + vec3(0.3f, 0, 0), vec3(0, 0, 1)},
                                       {at + vec3(0.1f, 0, 0), vec3(0, 0, 1)},
                                       {at + vec3(0.0f, 0.1f, 0), vec3(0, 0, 1)},
                                       {at + vec3(0.0f, 0.0f, 0.01f), vec3(0, 0, 1)}};
    const ListedProbes store(probes, 0.05f);
    const EncodingLight light = EncodingLight::of({0.5f, 2.0f, 7.0f, -1.0f});
    GBuffer gbuffer = emptyGBuffer();
    for (int x = 0; x < 3; ++x) {
        GBufferTexel& t = gbuffer.texels[std::size_t(x)];
        t.valid = true;
        t.depth = 1.0f;
        t.surface.position = at;
        t.surface.shadingNormal = vec3(0, 0, 1);
    }
    // The pixels' probes one after another, as the raster stage packs a tile's.
    std::vector<ProbeWeight> served;
    std::vector<uint32_t> offsets(gbuffer.texels.size(), 0);
    std::vector<uint8_t> counts(gbuffer.texels.size(), 0);
    auto serve = [&](int pixel, std::vector<ProbeWeight> list) {
        offsets[std::size_t(pixel)] = uint32_t(served.size());
        served.insert(served.end(), list.begin(), list.end());
        counts[std::size_t(pixel)] = uint8_t(list.size());
    };
    serve(0, {{1, 1.0f}});
    serve(1, {{0, 0.7f}, {2, 0.1f}, {3, 0.2f}});
    serve(2, {{3, 1.0f}});
    serve(3, {{1, 1.0f}});
    LayeredImage out(kWidth, kHeight);
    addProbeViews(camera, gbuffer, store, *light.light, {served.data(), offsets.data(), counts.data()}, out);

    const Image& splat = out.find("probe_splat")->image;
    const Color one = light.light->irradiance(1, vec3(0, 0, 1)) * kInvPi, two = light.light->irradiance(2, vec3(0, 0, 1)) * kInvPi;
    ASSERT_GT(one.x, 0.0f);
    ASSERT_NE(one, two);
    EXPECT_EQ(splat.rgb(0, 0), one) << "the only serving probe's E(+z) / pi";
    EXPECT_EQ(splat.rgb(1, 0), two) << "the nearest with samples, whatever the weights";
    EXPECT_EQ(splat.rgb(2, 0), Color(0.0f)) << "no serving probe holds samples";
    EXPECT_EQ(splat.rgb(3, 0), Color(0.0f)) << "no surface";
    for (float v : splat.data) EXPECT_TRUE(std::isfinite(v));
}

TEST(ProbeViews, TurningTheViewsOnChangesNoOtherLayer) {
    Scene cornell = loadSceneFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json");
    CameraDesc cam = *cornell.camera;
    cam.width = cam.height = 24;
    const PreparedScene prepared(std::move(cornell));
    Json method = {{"name", "mamba"}, {"allocation_tile", 8}};
    const LayeredImage without = test::render(prepared, cam, method, 3, 6);
    method["probe_views"] = true;
    const LayeredImage with = test::render(prepared, cam, method, 3, 6);
    std::set<std::string> names;
    for (const Layer& layer : without.layers) {
        names.insert(layer.name);
        ASSERT_NE(with.find(layer.name), nullptr) << layer.name;
        EXPECT_EQ(with.find(layer.name)->image.data, layer.image.data) << layer.name;
    }
    std::set<std::string> added;
    for (const Layer& layer : with.layers)
        if (!names.count(layer.name)) added.insert(layer.name);
    EXPECT_EQ(added, (std::set<std::string>{"probe_centres", "probe_splat"}));
    // After six frames the box's walls hold probes in view, and some pixels read lit ones.
    const Image& centres = with.find("probe_centres")->image;
    const Image& splat = with.find("probe_splat")->image;
    double marked = 0.0, lit = 0.0;
    for (float v : centres.data) marked += v;
    for (float v : splat.data) {
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
        lit += v > 0.0f;
    }
    EXPECT_GT(marked, 0.0);
    EXPECT_GT(lit, 0.0);
}

}  // namespace
}  // namespace gibench
