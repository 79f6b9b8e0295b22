#pragma once
// The stages a render leaves out because its scene has no use for them (issue 8: "leave out what
// a scene does not need"), decided once per run from the scene. Each stage left out is one a
// renderer would otherwise run at every path vertex; leaving it out changes time, not results: a
// run with pruning off renders the same image bit for bit (tests/core/render/stage_plan_test.cpp).

#include "core/config/params.h"
#include "core/scene/scene.h"

#include <string>
#include <vector>

namespace gibench {

struct StagePlan {
    // Light samples at every vertex: the scene has emitting triangles, suns or an environment.
    bool nextEventEstimation = true;
    // Escaped rays read the environment: the scene has one.
    bool environmentLookup = true;
    // Albedo read from texels: some material has a texture.
    bool textureLookups = true;

    struct Decision {
        std::string stage;
        bool runs;
        std::string reason;  // why it is left out; empty when it runs
    };
    // One per flag above, in that order, then "glossy_lobes", which follows the materials
    // whatever `prune` says.
    std::vector<Decision> decisions;
    bool pruning = true;

    // With `prune` false every stage runs whatever the scene.
    static StagePlan forScene(const Scene& scene, bool prune);
    // {"pruning": bool, "ran": [stage, ...], "left_out": [{"stage", "reason"}, ...]}
    Json manifest() const;
};

}  // namespace gibench
