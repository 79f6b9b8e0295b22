#pragma once
// Method "dense_grid": the probe-cache pipeline (core/probe_pipeline.h) with probes found through a dense uniform grid over the scene bounds (GIBS-like).

#include "core/method.h"

namespace gibench {

const ParamTable& denseGridParams();
std::unique_ptr<Method> createDenseGrid(Params& params);

}  // namespace gibench
