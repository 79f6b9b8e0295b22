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
    weighNearest(*this, query, neighbours, nearest(query, count, neighbours), out);
}

bool ProbeStore::receiverOf(const ProbeQuery& query, uint32_t& id) const {
    ProbeNeighbour nearestProbe;
    if (nearest(query, 1, &nearestProbe) == 0) return false;
    id = nearestProbe.id;
    return true;
}

}  // namespace gibench
