#include "methods/probe_cache/probe_store.h"

#include <algorithm>
#include <cmath>

namespace gibench {

void normaliseWeights(ProbeLookup& lookup) {
    float sum = 0.0f;
    for (int i = 0; i < lookup.count; ++i) sum += lookup.probes[i].weight;
    for (int i = 0; i < lookup.count; ++i) lookup.probes[i].weight = sum > 0.0f ? lookup.probes[i].weight / sum : 1.0f / float(lookup.count);
}

void ProbeStore::lookupBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const {
    for (int i = 0; i < n; ++i) lookup(queries[i], count, out[i]);
}

void ProbeStore::nearestBatch(const ProbeQuery* queries, int n, int count, ProbeNeighbour* out, int* found) const {
    for (int i = 0; i < n; ++i) found[i] = nearest(queries[i], count, out + std::size_t(i) * count);
}

void ProbeStore::lookupNearest(const ProbeQuery& query, int count, ProbeLookup& out) const {
    ProbeNeighbour neighbours[kMaxServedProbes];
    weighNearest(query, neighbours, nearest(query, count, neighbours), out);
}

void ProbeStore::lookupNearestBatch(const ProbeQuery* queries, int n, int count, ProbeLookup* out) const {
    // A tile's worth at a time, so that the neighbours need no allocation.
    constexpr int kChunk = kLookupTile * kLookupTile;
    ProbeNeighbour neighbours[kChunk * kMaxServedProbes];
    int found[kChunk];
    for (int first = 0; first < n; first += kChunk) {
        const int size = std::min(kChunk, n - first);
        nearestBatch(queries + first, size, count, neighbours, found);
        for (int i = 0; i < size; ++i) weighNearest(queries[first + i], neighbours + std::size_t(i) * count, found[i], out[first + i]);
    }
}

void ProbeStore::weighNearest(const ProbeQuery& query, const ProbeNeighbour* neighbours, int found, ProbeLookup& out) const {
    out.count = found;
    out.covered = false;
    out.distance = kInfinity;
    // nearest() ranks by (distance, id) within searchRadius(query) whatever the count: its first is
    // nearest(query, 1)'s, the default receiverOf().
    out.receiver = !receiverIsNearest() ? kReceiverUnknown : found > 0 ? neighbours[0].id : kNoReceiver;
    if (found == 0) return;
    const float radius = searchRadius(query);
    for (int i = 0; i < found; ++i) {
        const float t = neighbours[i].distance / radius;
        out.probes[i] = {neighbours[i].id, t < 1.0f ? (1.0f - t * t) * (1.0f - t * t) : 0.0f};
    }
    normaliseWeights(out);
    out.distance = neighbours[0].distance;
    const vec3 d = probe(neighbours[0].id).position - query.position;
    const float along = glm::dot(d, query.normal);
    const float tangential = glm::length(d - along * query.normal);
    const float cover = coverageRadius(query);
    out.covered = tangential < cover && std::fabs(along) < cover;
}

bool ProbeStore::receiverOf(const ProbeQuery& query, uint32_t& id) const {
    ProbeNeighbour nearestProbe;
    if (nearest(query, 1, &nearestProbe) == 0) return false;
    id = nearestProbe.id;
    return true;
}

}  // namespace gibench
