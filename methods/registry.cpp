#include "methods/registry.h"

#include "methods/path_traced/path_traced.h"
#include "methods/probe_cache/probe_cache.h"
#include "methods/probe_cache/stores/store_table.h"

namespace gibench {

const std::vector<MethodInfo>& methodRegistry() {
    static const std::vector<MethodInfo> registry = [] {
        std::vector<MethodInfo> rows = {
            {"path_traced", "unbiased path tracing with NEE and MIS: the ground truth", pathTracedParams(), &createPathTraced},
        };
        // One method per probe store: the same pipeline over each store.
        for (const ProbeStoreInfo& store : probeStoreTable()) rows.push_back(probeCacheMethod(store));
        return rows;
    }();
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
