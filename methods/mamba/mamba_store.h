#pragma once
// MAMBA's probe store: probes in a sparse uniform grid stored as a two-level hash table.

#include "core/params.h"
#include "core/probe_store.h"

#include <memory>

namespace gibench {

const ParamTable& mambaStoreParams();
std::unique_ptr<ProbeStore> createMambaStore(Params& params);

}  // namespace gibench
