#pragma once
// Everything surfaceAt() reads about a triangle, copied out of the scene's meshes once per run
// into one record per triangle. A mesh keeps its vertices in separate arrays shared through an
// index buffer, so that a hit gathered an index, three positions, three normals, three uvs and a
// material from up to a dozen cache lines (Sponza's hits missed in them: surfaceAt() took a seventh
// of its path tracer's time); a record holds them in two, the first of them (positions and
// material) being all a mesh without normals or uvs needs.

#include "core/scene/scene.h"

#include <vector>

namespace gibench {

struct alignas(64) ShadingTriangle {
    vec3 positions[3];  // world space, in the mesh's counter-clockwise order
    // Unit normal by that order (triangleNormal): normalizing Embree's at every hit cost a
    // square root and three divisions on each path vertex's chain of dependent arithmetic.
    vec3 geometricNormal;
    const Material* material = nullptr;
    bool hasNormals = false;
    bool hasUvs = false;
    vec3 normals[3];  // the mesh's unit vertex normals when hasNormals
    vec2 uvs[3];      // the mesh's texture coordinates when hasUvs
};

// Triangle `triangle` of mesh `mesh` of `scene`, packed.
ShadingTriangle packShadingTriangle(const Scene& scene, int mesh, uint32_t triangle);

// Every triangle of a scene, packed; refers to the scene's materials, so it must not outlive them.
class ShadingTriangles {
public:
    explicit ShadingTriangles(const Scene& scene);

    const ShadingTriangle& at(int mesh, uint32_t triangle) const { return m_triangles[m_firstOfMesh[mesh] + triangle]; }
    // Asks for the record's two cache lines ahead of at(): a wave's hits ask for theirs all at
    // once, so that on a big scene their misses overlap rather than wait one after another.
    void prefetch(int mesh, uint32_t triangle) const {
        const char* record = reinterpret_cast<const char*>(&at(mesh, triangle));
        __builtin_prefetch(record);
        __builtin_prefetch(record + 64);
    }

private:
    std::vector<ShadingTriangle> m_triangles;
    std::vector<std::size_t> m_firstOfMesh;  // index of each mesh's first triangle in m_triangles
};

}  // namespace gibench
