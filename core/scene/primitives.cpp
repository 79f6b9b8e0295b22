#include "core/scene/primitives.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace gibench {

Mesh makeQuad(const std::array<vec3, 4>& corners) {
    Mesh mesh;
    mesh.positions.assign(corners.begin(), corners.end());
    mesh.uvs = {vec2(0.0f, 0.0f), vec2(1.0f, 0.0f), vec2(1.0f, 1.0f), vec2(0.0f, 1.0f)};
    mesh.indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
    return mesh;
}

Mesh makeUnitQuad() {
    return makeQuad({vec3(-1.0f, 0.0f, 1.0f), vec3(1.0f, 0.0f, 1.0f), vec3(1.0f, 0.0f, -1.0f), vec3(-1.0f, 0.0f, -1.0f)});
}

Mesh makeBox(bool inward) {
    // Each face is the +Y unit quad turned to face along one axis; the corners stay
    // counter-clockwise seen from outside.
    const std::array<mat3, 6> faces = {
        mat3(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1)),    // +Y
        mat3(vec3(1, 0, 0), vec3(0, -1, 0), vec3(0, 0, -1)),  // -Y
        mat3(vec3(0, 1, 0), vec3(1, 0, 0), vec3(0, 0, -1)),   // +X
        mat3(vec3(0, -1, 0), vec3(-1, 0, 0), vec3(0, 0, -1)), // -X
        mat3(vec3(1, 0, 0), vec3(0, 0, 1), vec3(0, -1, 0)),   // +Z
        mat3(vec3(1, 0, 0), vec3(0, 0, -1), vec3(0, 1, 0)),   // -Z
    };
    const Mesh quad = makeUnitQuad();
    Mesh box;
    for (const mat3& rotation : faces) {
        const auto base = static_cast<uint32_t>(box.positions.size());
        for (std::size_t i = 0; i < quad.positions.size(); ++i) {
            box.positions.push_back(rotation * (quad.positions[i] + vec3(0.0f, 1.0f, 0.0f)));
            box.uvs.push_back(quad.uvs[i]);
        }
        for (const uvec3& t : quad.indices) box.indices.push_back(inward ? uvec3(base) + uvec3(t.x, t.z, t.y) : uvec3(base) + t);
    }
    return box;
}

Mesh makeSphere(const vec3& centre, float radius, int subdivisions, bool inward) {
    // Icosahedron: the 12 vertices (0, ±1, ±φ) and their cyclic permutations.
    const float phi = 0.5f * (1.0f + std::sqrt(5.0f));
    std::vector<vec3> unit = {
        {-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
        {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1},
    };
    for (vec3& v : unit) v = glm::normalize(v);
    std::vector<uvec3> triangles = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1},
    };

    for (int level = 0; level < subdivisions; ++level) {
        // One midpoint per edge, shared by the two triangles on it, keeps the sphere closed.
        std::unordered_map<uint64_t, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            auto [it, added] = midpoints.try_emplace(key, static_cast<uint32_t>(unit.size()));
            if (added) unit.push_back(glm::normalize(unit[a] + unit[b]));
            return it->second;
        };
        std::vector<uvec3> finer;
        finer.reserve(triangles.size() * 4);
        for (const uvec3& t : triangles) {
            const uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
            finer.insert(finer.end(), {uvec3(t.x, ab, ca), uvec3(t.y, bc, ab), uvec3(t.z, ca, bc), uvec3(ab, bc, ca)});
        }
        triangles = std::move(finer);
    }

    Mesh mesh;
    mesh.positions.reserve(unit.size());
    mesh.normals.reserve(unit.size());
    for (const vec3& u : unit) {
        mesh.positions.push_back(centre + radius * u);
        mesh.normals.push_back(inward ? -u : u);
    }
    if (inward)
        for (uvec3& t : triangles) std::swap(t.y, t.z);
    mesh.indices = std::move(triangles);
    return mesh;
}

}  // namespace gibench
