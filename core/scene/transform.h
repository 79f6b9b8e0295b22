#pragma once
// Affine placement of shapes in a scene: the "transform" object of a scene file.

#include "core/config/params.h"
#include "core/util/math.h"

namespace gibench {

struct Mesh;

// An invertible affine map of points, with the matching map of normals. In double: a shape placed
// 1e7 units from the origin keeps its millimetres until the scene is rebased (scene_loader.h).
class Transform {
public:
    Transform() = default;
    // `matrix` must be affine (last row 0 0 0 1) and invertible.
    explicit Transform(const glm::dmat4& matrix);

    glm::dvec3 point(const vec3& p) const { return glm::dvec3(m_matrix * glm::dvec4(glm::dvec3(p), 1.0)); }
    // Unit normal of a surface whose unit normal was `n` before: the inverse transpose keeps it
    // perpendicular under non-uniform scale. In double, since the inverse of a float scale of
    // 1e-30 or 1e30 under- or overflows in float.
    vec3 normal(const vec3& n) const { return vec3(glm::normalize(m_normalMatrix * glm::dvec3(n))); }
    // This transform applied after a translation by `offset`.
    Transform afterTranslation(const glm::dvec3& offset) const;
    // A mirror (negative determinant) turns counter-clockwise triangles clockwise.
    bool flipsWinding() const { return m_flipsWinding; }

private:
    glm::dmat4 m_matrix{1.0};
    glm::dmat3 m_normalMatrix{1.0};
    bool m_flipsWinding = false;
};

// Reads a transform object (table below): scale, then rotate, then translate; or a full matrix.
// Throws InputError with the JSON pointer of a bad value (zero scale, zero rotation axis,
// singular or non-affine matrix, "matrix" combined with the others).
Transform parseTransform(Params& params);

// Parameters of a transform:
//   scale       number or [sx,sy,sz]   1        non-zero; negative mirrors
//   rotate_deg  [ax,ay,az,angle_deg]   none     right-handed rotation about the axis
//   translate   [x,y,z]                [0,0,0]
//   matrix      4x4 rows               none     affine, row-major; excludes the three above
extern const ParamTable kTransformParams;

// Maps positions and normals of `mesh` in place, positions to T(p) - origin rounded once to float;
// flips each triangle's winding under a mirror so the front face stays the front face.
void transformMesh(Mesh& mesh, const Transform& transform, const glm::dvec3& origin);

}  // namespace gibench
