// Method "mamba": the probe-cache pipeline (core/probe_pipeline.h) over MAMBA's sparse hash grid.

#include "methods/mamba/mamba.h"

#include "core/probe_pipeline.h"
#include "methods/mamba/mamba_store.h"

namespace gibench {

const ParamTable& mambaParams() {
    static const ParamTable table = withPipelineParams(mambaStoreParams());
    return table;
}

std::unique_ptr<Method> createMamba(Params& params) {
    const ProbePipelineSettings settings = readProbePipelineSettings(params);
    return makeProbeCacheMethod(createMambaStore(params), settings);
}

}  // namespace gibench
