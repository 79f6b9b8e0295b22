// The update stage takes a sample's receiver from the lookup of its point made earlier in the frame
// (the raster stage's at v1, the cache read's at v2) unless a probe placed since could change it
// (ProbeLookup::receiver). That must not change what any store caches: the same frames rendered
// through a store whose lookups report no receiver, so that every sample asks receiverOf() after
// the allocation stage as before, are bit-identical.

#include "support/forwarding_store.h"
#include "support/render_helpers.h"

#include "methods/probe_cache/probe_cache.h"
#include "methods/probe_cache/stores/store_table.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <memory>

namespace gibench {
namespace {

// A store of the table whose lookups leave every receiver unknown.
class WithoutReportedReceivers final : public test::ForwardingStore {
public:
    using ForwardingStore::ForwardingStore;

    void lookup(const ProbeQuery& query, int count, ProbeLookup& out) const override {
        ForwardingStore::lookup(query, count, out);
        out.receiver = kReceiverUnknown;
    }
    void lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const override {
        ForwardingStore::lookupBatch(queries, n, count, out);
        for (int i = 0; i < n; ++i) out[i].receiver = kReceiverUnknown;
    }
    bool receiverIsNearest() const override { return false; }  // lookupNearest() reports none
};

// ProbeStoreInfo::create is a plain function: one per row of the store table.
template <std::size_t Row>
std::unique_ptr<ProbeStore> createWithoutReportedReceivers(Params& params) {
    return std::make_unique<WithoutReportedReceivers>(probeStoreTable()[Row].create(params));
}
constexpr std::array<std::unique_ptr<ProbeStore> (*)(Params&), 8> kWithoutReportedReceivers = {
    createWithoutReportedReceivers<0>, createWithoutReportedReceivers<1>, createWithoutReportedReceivers<2>,
    createWithoutReportedReceivers<3>, createWithoutReportedReceivers<4>, createWithoutReportedReceivers<5>,
    createWithoutReportedReceivers<6>, createWithoutReportedReceivers<7>};

bool sameBits(const LayeredImage& a, const LayeredImage& b, std::string& firstDifference) {
    for (const Layer& layer : a.layers) {
        const Layer* other = b.find(layer.name);
        if (!other || other->image.data.size() != layer.image.data.size() ||
            std::memcmp(other->image.data.data(), layer.image.data.data(), layer.image.data.size() * sizeof(float)) != 0) {
            firstDifference = layer.name;
            return false;
        }
    }
    return a.layers.size() == b.layers.size();
}

TEST(ProbeCacheReceivers, ReceiversFromEarlierLookupsCacheExactlyWhatReceiverOfWould) {
    // 48² pixels make 9 allocation tiles, so that every frame places fewer probes than the update
    // stage scans one by one: the receivers from the lookups are checked against each of them.
    // Cells of 0.05 keep probes being placed over all 40 frames, at updates too.
    const PreparedScene scene(test::sceneFromJson(loadJsonFile(std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json")));
    CameraDesc camera = *scene.scene.camera;
    camera.width = camera.height = 48;
    const std::vector<ProbeStoreInfo>& table = probeStoreTable();
    ASSERT_LE(table.size(), kWithoutReportedReceivers.size());
    for (std::size_t row = 0; row < table.size(); ++row)
        for (const char* lookup : {"native", "nearest"}) {
            const Json block = {{table[row].spacingKey, 0.05}, {"lookup", lookup}};
            ProbeStoreInfo hiding = table[row];
            hiding.create = kWithoutReportedReceivers[row];
            const LayeredImage reused = test::renderFrames(*test::createMethod(probeCacheMethod(table[row]), block), scene, camera, 5, 40);
            const LayeredImage asked = test::renderFrames(*test::createMethod(probeCacheMethod(hiding), block), scene, camera, 5, 40);
            std::string layer;
            EXPECT_TRUE(sameBits(reused, asked, layer)) << table[row].name << ", lookup " << lookup << ": layer " << layer << " differs";
        }
}

}  // namespace
}  // namespace gibench
