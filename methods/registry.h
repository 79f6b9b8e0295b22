#pragma once
// Every method gibench can run, by name: one table, read by `run`, `methods` and the tests that
// run over all methods.

#include "core/render/method.h"

#include <vector>

namespace gibench {

const std::vector<MethodInfo>& methodRegistry();
// Null when no method has that name.
const MethodInfo* findMethod(const std::string& name);
std::vector<std::string> methodNames();

}  // namespace gibench
