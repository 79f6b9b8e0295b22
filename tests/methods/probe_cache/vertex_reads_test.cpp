// The cache reads at the secondary paths' vertices take `vertex_neighbours` probes, the raster
// stage's lookups `gather_neighbours`: the paper's recursive update integrates "the secondary
// probe", the one nearest to v2, while its final gather blends the N = 2 nearest.

#include "support/forwarding_store.h"
#include "support/render_helpers.h"
#include "support/store_test_helpers.h"

#include "methods/probe_cache/probe_cache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <memory>

namespace gibench {
namespace {

// The counts lookups were asked for, a bit per count: by the single queries of path vertices and
// by the raster stage's tiles (several queries at once).
std::atomic<uint32_t> g_vertexCounts{0}, g_tileCounts{0};

class CountRecordingStore final : public test::ForwardingStore {
public:
    using ForwardingStore::ForwardingStore;

    void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const override {
        (n == 1 ? g_vertexCounts : g_tileCounts).fetch_or(1u << count);
        ForwardingStore::lookupBatch(queries, n, count, out);
    }
};

std::unique_ptr<ProbeStore> createRecordingMamba(Params& params) {
    return std::make_unique<CountRecordingStore>(test::storeRow("mamba").create(params));
}

TEST(ProbeCacheVertexReads, PathVerticesReadVertexNeighboursProbesAndTheRasterGatherNeighbours) {
    const PreparedScene scene(test::sceneFromJson(loadJsonFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json")));
    CameraDesc camera = *scene.scene.camera;
    camera.width = camera.height = 48;  // 9 tiles of the box: each asks for many pixels at once, never a single one
    ProbeStoreInfo recording = test::storeRow("mamba");
    recording.create = createRecordingMamba;
    for (const auto& [vertex, gather] : {std::pair{1, 3}, std::pair{4, 2}}) {
        g_vertexCounts = g_tileCounts = 0;
        const Json block = {{"vertex_neighbours", vertex}, {"gather_neighbours", gather}};
        test::renderFrames(*test::createMethod(probeCacheMethod(recording), block), scene, camera, 1, 4);
        EXPECT_EQ(g_vertexCounts.load(), 1u << vertex) << "vertex_neighbours " << vertex;
        EXPECT_EQ(g_tileCounts.load(), 1u << gather) << "gather_neighbours " << gather;
    }
}

}  // namespace
}  // namespace gibench
