#pragma once
// Probe store "dense_grid" (GIBS-like): probes found through a dense uniform grid of cells over
// the scene's bounds, each cell holding a bounded list of probe ids. Lookup and memory are
// described at the top of dense_grid_store.cpp.

#include "methods/probe_cache/probe_store.h"

#include <memory>

namespace gibench {

const ParamTable& denseGridStoreParams();
// The grid is sized in ProbeStore::prepare(), which throws InputError when it would exceed
// max_cells.
std::unique_ptr<ProbeStore> createDenseGridStore(Params& params);

}  // namespace gibench
