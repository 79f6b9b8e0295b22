#include "core/scene/transform.h"

#include "core/scene/scene.h"
#include "core/scene/unit_vector.h"

#include "core/config/json_summary.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <utility>
#include <vector>

namespace gibench {

const ParamTable kTransformParams = {
    {"scale", ParamType::Json, 1.0, "number or [sx, sy, sz], non-zero; applied first"},
    {"rotate_deg", ParamType::Json, Json(), "[axis_x, axis_y, axis_z, angle_deg], right-handed; applied after scale"},
    {"translate", ParamType::Vec3, Json::array({0, 0, 0}), "offset applied last (scene units)"},
    {"matrix", ParamType::Json, Json(), "4x4 affine matrix, row-major; instead of scale/rotate_deg/translate"},
};

namespace {

// What a message adds when a number of `v` does not fit a float, or is not 0 but becomes 0 as one.
std::string floatNote(const Json& v) {
    std::vector<const Json*> numbers = {&v};
    if (v.is_array())
        for (const Json& x : v) numbers.push_back(&x);
    for (const Json* x : numbers) {
        if (!x->is_number()) continue;
        if (!asFloat(*x)) return " (" + summarize(*x) + " is " + kFloatLimit + ")";
        if (*asFloat(*x) == 0.0f && x->get<double>() != 0.0) return " (" + summarize(*x) + " is 0 as a float)";
    }
    return "";
}

vec3 readScale(Params& p) {
    const Json v = p.getJson("scale");
    // Zero is checked as a float: 1e-46 is not 0 but becomes 0 and collapses the shape.
    auto nonZero = [](const Json& x) { return asFloat(x).value_or(0.0f) != 0.0f; };
    if (nonZero(v)) return vec3(*asFloat(v));
    if (v.is_array() && v.size() == 3 && nonZero(v[0]) && nonZero(v[1]) && nonZero(v[2]))
        return vec3(*asFloat(v[0]), *asFloat(v[1]), *asFloat(v[2]));
    p.fail("scale", "expected a non-zero number or an array of 3 non-zero numbers, got " + summarize(v) + floatNote(v));
}

mat4 readRotation(Params& p) {
    const Json v = p.getJson("rotate_deg");
    const bool shapeOk = v.is_array() && v.size() == 4 && asFloat(v[0]) && asFloat(v[1]) && asFloat(v[2]) && asFloat(v[3]);
    const std::optional<vec3> axis = shapeOk ? unitVector(vec3(*asFloat(v[0]), *asFloat(v[1]), *asFloat(v[2]))) : std::nullopt;
    if (!axis)
        p.fail("rotate_deg", "expected [axis_x, axis_y, axis_z, angle_deg] with a non-zero axis, got " + summarize(v) + floatNote(v));
    return glm::rotate(mat4(1.0f), glm::radians(*asFloat(v[3])), *axis);
}

mat4 readMatrix(Params& p) {
    const Json v = p.getJson("matrix");
    const std::string expected = "expected 4 rows of 4 numbers with the last row [0, 0, 0, 1], got " + summarize(v);
    if (!v.is_array() || v.size() != 4) p.fail("matrix", expected);
    mat4 m(1.0f);
    for (int row = 0; row < 4; ++row) {
        const Json& r = v[row];
        if (!r.is_array() || r.size() != 4) p.fail("matrix", expected);
        for (int col = 0; col < 4; ++col) {
            const std::optional<float> x = asFloat(r[col]);
            if (!x) p.fail("matrix", expected + floatNote(r));
            m[col][row] = *x;  // glm is column-major
        }
    }
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) p.fail("matrix", expected);
    // In double: the float determinant of a valid matrix with entries of 1e-13 or 1e13 under- or overflows.
    if (glm::determinant(glm::dmat3(mat3(m))) == 0.0) p.fail("matrix", "expected an invertible matrix, got " + summarize(v));
    return m;
}

}  // namespace

Transform::Transform(const mat4& matrix) : m_matrix(matrix) {
    const glm::dmat3 linear{mat3(matrix)};
    m_normalMatrix = glm::transpose(glm::inverse(linear));
    m_flipsWinding = glm::determinant(linear) < 0.0;
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
