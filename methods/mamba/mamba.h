#pragma once
// Method "mamba": the probe-cache pipeline (core/probe_pipeline.h) with probes in a sparse uniform grid stored as a two-level hash table.

#include "core/method.h"

namespace gibench {

const ParamTable& mambaParams();
std::unique_ptr<Method> createMamba(Params& params);

}  // namespace gibench
