#include "core/render/shading_triangles.h"

#include "core/render/surface.h"

namespace gibench {

ShadingTriangle packShadingTriangle(const Scene& scene, int meshIndex, uint32_t triangle) {
    const Mesh& mesh = scene.meshes[meshIndex];
    const uvec3 i = mesh.indices[triangle];
    ShadingTriangle t;
    t.geometricNormal = triangleNormal(mesh, triangle);
    t.material = &scene.materials[mesh.materials[triangle]];
    t.hasNormals = !mesh.normals.empty();
    t.hasUvs = !mesh.uvs.empty();
    for (int k = 0; k < 3; ++k) {
        t.positions[k] = mesh.positions[i[k]];
        t.normals[k] = t.hasNormals ? mesh.normals[i[k]] : vec3(0.0f);
        t.uvs[k] = t.hasUvs ? mesh.uvs[i[k]] : vec2(0.0f);
    }
    return t;
}

ShadingTriangles::ShadingTriangles(const Scene& scene) {
    m_firstOfMesh.reserve(scene.meshes.size());
    m_triangles.reserve(scene.triangleCount());
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        m_firstOfMesh.push_back(m_triangles.size());
        for (uint32_t t = 0; t < scene.meshes[m].triangleCount(); ++t) m_triangles.push_back(packShadingTriangle(scene, int(m), t));
    }
}

}  // namespace gibench
