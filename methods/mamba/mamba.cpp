#include "methods/mamba/mamba.h"

#include "core/probe_pipeline.h"
#include "methods/mamba/mamba_store.h"

namespace gibench {

const ParamTable& mambaParams() {
    static const ParamTable table = withPipelineParams(mambaStoreParams());
    return table;
}

std::unique_ptr<Method> createMamba(Params& params) { return createProbeCacheMethod(params, &createMambaStore); }

}  // namespace gibench
