#include "methods/dense_grid/dense_grid.h"

#include "core/probe_pipeline.h"
#include "methods/dense_grid/dense_grid_store.h"

namespace gibench {

const ParamTable& denseGridParams() {
    static const ParamTable table = withPipelineParams(kDenseGridStoreParams);
    return table;
}

std::unique_ptr<Method> createDenseGrid(Params& params) { return createProbeCacheMethod(params, &createDenseGridStore); }

}  // namespace gibench
