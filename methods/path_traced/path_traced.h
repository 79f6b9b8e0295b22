#pragma once
// Method "path_traced": the ground truth every cache is measured against.

#include "core/render/method.h"

namespace gibench {

const ParamTable& pathTracedParams();
std::unique_ptr<Method> createPathTraced(Params& params);

}  // namespace gibench
