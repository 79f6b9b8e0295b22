#include "methods/probe_cache/probe_store.h"

#include <cmath>

namespace gibench {

void normaliseWeights(ProbeLookup& lookup) {
    float sum = 0.0f;
    for (int i = 0; i < lookup.count; ++i) sum += lookup.probes[i].weight;
    for (int i = 0; i < lookup.count; ++i) lookup.probes[i].weight = sum > 0.0f ? lookup.probes[i].weight / sum : 1.0f / float(lookup.count);
}

void ProbeStore::lookupNearest(const ProbeQuery& query, int count, ProbeLookup& out) const {
    ProbeNeighbour neighbours[kMaxServedProbes];
    out.count = nearest(query, count, neighbours);
    out.covered = false;
    out.distance = kInfinity;
    if (out.count == 0) return;
    const float radius = searchRadius(query);
    for (int i = 0; i < out.count; ++i) {
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
