#include "methods/registry.h"

#include "methods/cards/cards.h"
#include "methods/dense_grid/dense_grid.h"
#include "methods/mamba/mamba.h"
#include "methods/path_traced/path_traced.h"

namespace gibench {

const std::vector<MethodInfo>& methodRegistry() {
    static const std::vector<MethodInfo> registry = {
        {"path_traced", "unbiased path tracing with NEE and MIS: the ground truth", &kPathTracedParams, &createPathTraced},
        {"mamba", "probe cache: probes in a sparse uniform grid stored as a two-level hash table (MAMBA)", &mambaParams(), &createMamba},
        {"dense_grid", "probe cache: probes found through a dense uniform grid over the scene (GIBS-like)", &denseGridParams(), &createDenseGrid},
        {"cards", "probe cache: probe texels on box-projected surface cards in an atlas (Lumen-like)", &cardsParams(), &createCards},
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
