#pragma once
// Scenes, stores and queries shared by the probe-store tests.

#include "core/util/error.h"
#include "methods/probe_cache/probe_store.h"
#include "methods/probe_cache/stores/store_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace gibench::test {

// A rectangle from `corner` spanning edges `a` and `b`, counter-clockwise seen from a × b.
inline void addQuad(Mesh& mesh, const vec3& corner, const vec3& a, const vec3& b) {
    const auto base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {corner, corner + a, corner + a + b, corner + b});
    mesh.indices.insert(mesh.indices.end(), {{base, base + 1, base + 2}, {base, base + 2, base + 3}});
    mesh.materials.insert(mesh.materials.end(), {0u, 0u});
}

// An axis-aligned box, counter-clockwise seen from outside.
inline Mesh boxMesh(const vec3& lo, const vec3& hi) {
    Mesh mesh;
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // u × v = +axis
        vec3 du(0.0f), dv(0.0f);
        du[u] = hi[u] - lo[u];
        dv[v] = hi[v] - lo[v];
        vec3 top = lo;
        top[axis] = hi[axis];
        addQuad(mesh, top, du, dv);
        addQuad(mesh, lo, dv, du);
    }
    return mesh;
}

inline Scene sceneOf(std::vector<Mesh> meshes) {
    Scene scene;
    scene.meshes = std::move(meshes);
    scene.materials.resize(1);
    return scene;
}

// The row of the store table (stores/store_table.h) named `name`.
inline const ProbeStoreInfo& storeRow(const std::string& name) {
    for (const ProbeStoreInfo& row : probeStoreTable())
        if (row.name == name) return row;
    throw std::logic_error("no probe store named \"" + name + "\"");
}

// The store of a row built from a method block through its factory, every key checked.
inline std::unique_ptr<ProbeStore> makeStore(const Json& block, const ProbeStoreInfo& info) {
    Params params(block, "cfg.json", "/method", "method \"" + info.name + "\"", &info.parameters());
    auto store = info.create(params);
    params.finish();
    return store;
}

// `block` with the keys that make `info`'s store start empty after prepare(): a store that
// places probes in prepare() (cards' scene capture) is asked not to, so that a test sees only the
// probes it inserts.
inline Json startingEmpty(const ProbeStoreInfo& info, Json block) {
    const ParamTable& table = info.parameters();
    if (std::any_of(table.begin(), table.end(), [](const ParamSpec& row) { return row.name == "capture"; }) && !block.contains("capture"))
        block["capture"] = "on_demand";
    return block;
}

// `store` after prepare(scene); the notes it records go to `notes` when given.
inline std::unique_ptr<ProbeStore> prepared(std::unique_ptr<ProbeStore> store, const Scene& scene, RunNotes* notes = nullptr) {
    RunNotes ignored;
    store->prepare(scene, notes ? *notes : ignored);
    return store;
}

inline ProbeQuery queryAt(const vec3& position, const vec3& normal, int mesh = 0) { return {position, normal, mesh, 0}; }

// What nearest(query, count) offers, exactly as many entries as it returned.
inline std::vector<ProbeNeighbour> nearestOf(const ProbeStore& store, const ProbeQuery& query, int count) {
    std::vector<ProbeNeighbour> found(std::size_t(std::max(count, 1)));
    const int n = store.nearest(query, count, found.data());
    found.resize(std::size_t(std::clamp(n, 0, count)));
    return found;
}

// The exact message of the InputError `f` throws, or "" when it throws none.
template <typename F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace gibench::test
