#include "core/scene/transform.h"

#include "core/scene/scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <utility>

namespace gibench {

const ParamTable kTransformParams = {
    {"scale", ParamType::Json, 1.0, "number or [sx, sy, sz], non-zero; applied first"},
    {"rotate_deg", ParamType::Json, Json(), "[axis_x, axis_y, axis_z, angle_deg], right-handed; applied after scale"},
    {"translate", ParamType::Vec3, Json::array({0, 0, 0}), "offset applied last (scene units)"},
    {"matrix", ParamType::Json, Json(), "4x4 affine matrix, row-major; instead of scale/rotate_deg/translate"},
};

namespace {

bool isFiniteNumber(const Json& v) { return v.is_number() && std::isfinite(v.get<double>()); }

vec3 readScale(Params& p) {
    const Json v = p.getJson("scale");
    auto nonZero = [](const Json& x) { return isFiniteNumber(x) && x.get<double>() != 0.0; };
    if (nonZero(v)) return vec3(v.get<float>());
    if (v.is_array() && v.size() == 3 && nonZero(v[0]) && nonZero(v[1]) && nonZero(v[2]))
        return vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
    p.fail("scale", "expected a non-zero number or an array of 3 non-zero numbers, got " + v.dump());
}

mat4 readRotation(Params& p) {
    const Json v = p.getJson("rotate_deg");
    const bool shapeOk = v.is_array() && v.size() == 4 && isFiniteNumber(v[0]) && isFiniteNumber(v[1]) &&
                         isFiniteNumber(v[2]) && isFiniteNumber(v[3]);
    const vec3 axis = shapeOk ? vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>()) : vec3(0.0f);
    if (!shapeOk || glm::length(axis) == 0.0f)
        p.fail("rotate_deg", "expected [axis_x, axis_y, axis_z, angle_deg] with a non-zero axis, got " + v.dump());
    return glm::rotate(mat4(1.0f), glm::radians(v[3].get<float>()), glm::normalize(axis));
}

mat4 readMatrix(Params& p) {
    const Json v = p.getJson("matrix");
    const std::string expected = "expected 4 rows of 4 numbers with the last row [0, 0, 0, 1], got " + v.dump();
    if (!v.is_array() || v.size() != 4) p.fail("matrix", expected);
    mat4 m(1.0f);
    for (int row = 0; row < 4; ++row) {
        const Json& r = v[row];
        if (!r.is_array() || r.size() != 4) p.fail("matrix", expected);
        for (int col = 0; col < 4; ++col) {
            if (!isFiniteNumber(r[col])) p.fail("matrix", expected);
            m[col][row] = r[col].get<float>();  // glm is column-major
        }
    }
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) p.fail("matrix", expected);
    const float det = glm::determinant(mat3(m));
    if (!std::isfinite(det) || det == 0.0f) p.fail("matrix", "expected an invertible matrix, got " + v.dump());
    return m;
}

}  // namespace

Transform::Transform(const mat4& matrix) : m_matrix(matrix) {
    const mat3 linear(matrix);
    m_normalMatrix = glm::transpose(glm::inverse(linear));
    m_flipsWinding = glm::determinant(linear) < 0.0f;
}

Transform parseTransform(Params& p) {
    if (p.has("matrix")) {
        if (p.has("scale") || p.has("rotate_deg") || p.has("translate"))
            p.fail("matrix", "expected either \"matrix\" or \"scale\"/\"rotate_deg\"/\"translate\", not both");
        const mat4 m = readMatrix(p);
        p.finish();
        return Transform(m);
    }
    const vec3 scale = readScale(p);
    const mat4 rotation = p.has("rotate_deg") ? readRotation(p) : mat4(1.0f);
    const vec3 translation = p.getVec3("translate");
    p.finish();
    return Transform(glm::translate(mat4(1.0f), translation) * rotation * glm::scale(mat4(1.0f), scale));
}

void transformMesh(Mesh& mesh, const Transform& transform) {
    for (vec3& p : mesh.positions) p = transform.point(p);
    for (vec3& n : mesh.normals) n = transform.normal(n);
    if (transform.flipsWinding())
        for (uvec3& t : mesh.indices) std::swap(t.y, t.z);
}

}  // namespace gibench
