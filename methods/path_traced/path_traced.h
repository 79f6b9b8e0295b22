#pragma once
// Method "path_traced": the ground truth every cache is measured against.

#include "core/method.h"

namespace gibench {

extern const ParamTable kPathTracedParams;
std::unique_ptr<Method> createPathTraced(Params& params);

}  // namespace gibench
