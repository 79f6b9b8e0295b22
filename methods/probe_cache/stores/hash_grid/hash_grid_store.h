#pragma once
// Probe store "hash_grid" (SHaRC-like, one level): the cell at a surface point is the cache entry,
// found by hashing its quantised position, level of detail and facing into one fixed table.
// Keys, lookup, eviction and memory are described at the top of hash_grid_store.cpp.

#include "methods/probe_cache/probe_store.h"

#include <memory>

namespace gibench {

const ParamTable& hashGridStoreParams();
std::unique_ptr<ProbeStore> createHashGridStore(Params& params);

}  // namespace gibench
