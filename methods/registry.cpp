#include "methods/registry.h"

#include "methods/mamba/mamba.h"
#include "methods/path_traced/path_traced.h"

namespace gibench {

const std::vector<MethodInfo>& methodRegistry() {
    static const std::vector<MethodInfo> registry = {
        {"path_traced", "unbiased path tracing with NEE and MIS: the ground truth", &kPathTracedParams, &createPathTraced},
        {"mamba", "probe cache with probes in a sparse two-level hash grid (MAMBA)", &mambaParams(), &createMamba},
    };
    return registry;
}

const MethodInfo* findMethod(const std::string& name) {
    for (const MethodInfo& m : methodRegistry())
        if (m.name == name) return &m;
    return nullptr;
}

std::vector<std::string> methodNames() {
    std::vector<std::string> names;
    for (const MethodInfo& m : methodRegistry()) names.push_back(m.name);
    return names;
}

}  // namespace gibench
