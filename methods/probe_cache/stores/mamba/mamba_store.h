#pragma once
// Probe store "mamba": probes in a sparse uniform grid stored as a two-level hash table
// (sparse_hash_grid.h). Lookup and the original's constants are described at the top of
// mamba_store.cpp.

#include "methods/probe_cache/probe_store.h"

#include <memory>

namespace gibench {

const ParamTable& mambaStoreParams();
std::unique_ptr<ProbeStore> createMambaStore(Params& params);

}  // namespace gibench
