#pragma once
// Probe store "dense_grid" (GIBS-like): probes found through a dense uniform grid of cells over
// the scene's bounds, each cell holding a bounded list of probe ids. Parameters and memory at the
// top of dense_grid_store.cpp.

#include "core/probe_store.h"

#include <memory>

namespace gibench {

extern const ParamTable kDenseGridStoreParams;

// Reads only the keys of kDenseGridStoreParams through `params` (invalid values throw InputError
// naming the key). The grid is sized in ProbeStore::prepare(), which throws InputError when it
// would exceed max_cells.
std::unique_ptr<ProbeStore> createDenseGridStore(Params& params);

}  // namespace gibench
