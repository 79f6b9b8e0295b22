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

glm::dvec3 readScale(Params& p) {
    const Json v = p.getJson("scale");
    // Zero is checked as a float: 1e-46 is not 0 but becomes 0 and collapses the shape.
    auto nonZero = [](const Json& x) { return asFloat(x).value_or(0.0f) != 0.0f; };
    if (nonZero(v)) return glm::dvec3(v.get<double>());
    if (v.is_array() && v.size() == 3 && nonZero(v[0]) && nonZero(v[1]) && nonZero(v[2]))
        return glm::dvec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    p.fail("scale", "expected a non-zero number or an array of 3 non-zero numbers, got " + summarize(v) + floatNote(v));
}

glm::dmat4 readRotation(Params& p) {
    const Json v = p.getJson("rotate_deg");
    const bool shapeOk = v.is_array() && v.size() == 4 && asFloat(v[0]) && asFloat(v[1]) && asFloat(v[2]) && asFloat(v[3]);
    const std::optional<vec3> axis = shapeOk ? unitVector(vec3(*asFloat(v[0]), *asFloat(v[1]), *asFloat(v[2]))) : std::nullopt;
    if (!axis)
        p.fail("rotate_deg", "expected [axis_x, axis_y, axis_z, angle_deg] with a non-zero axis, got " + summarize(v) + floatNote(v));
    return glm::rotate(glm::dmat4(1.0), glm::radians(v[3].get<double>()), glm::dvec3(*axis));
}

glm::dmat4 readMatrix(Params& p) {
    const Json v = p.getJson("matrix");
    const std::string expected = "expected 4 rows of 4 numbers with the last row [0, 0, 0, 1], got " + summarize(v);
    if (!v.is_array() || v.size() != 4) p.fail("matrix", expected);
    glm::dmat4 m(1.0);
    for (int row = 0; row < 4; ++row) {
        const Json& r = v[row];
        if (!r.is_array() || r.size() != 4) p.fail("matrix", expected);
        for (int col = 0; col < 4; ++col) {
            if (!asFloat(r[col])) p.fail("matrix", expected + floatNote(r));
            m[col][row] = r[col].get<double>();  // glm is column-major
        }
    }
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) p.fail("matrix", expected);
    if (glm::determinant(glm::dmat3(m)) == 0.0) p.fail("matrix", "expected an invertible matrix, got " + summarize(v));
    return m;
}

}  // namespace

Transform::Transform(const glm::dmat4& matrix) : m_matrix(matrix) {
    const glm::dmat3 linear{matrix};
    m_normalMatrix = glm::transpose(glm::inverse(linear));
    m_flipsWinding = glm::determinant(linear) < 0.0;
}

Transform Transform::afterTranslation(const glm::dvec3& offset) const {
    return Transform(m_matrix * glm::translate(glm::dmat4(1.0), offset));
}

Transform parseTransform(Params& p) {
    if (p.has("matrix")) {
        if (p.has("scale") || p.has("rotate_deg") || p.has("translate"))
            p.fail("matrix", "expected either \"matrix\" or \"scale\"/\"rotate_deg\"/\"translate\", not both");
        const glm::dmat4 m = readMatrix(p);
        p.finish();
        return Transform(m);
    }
    const glm::dvec3 scale = readScale(p);
    const glm::dmat4 rotation = p.has("rotate_deg") ? readRotation(p) : glm::dmat4(1.0);
    const glm::dvec3 translation = p.getDVec3("translate");
    p.finish();
    return Transform(glm::translate(glm::dmat4(1.0), translation) * rotation * glm::scale(glm::dmat4(1.0), scale));
}

void transformMesh(Mesh& mesh, const Transform& transform, const glm::dvec3& origin) {
    for (vec3& p : mesh.positions) p = vec3(transform.point(p) - origin);
    for (vec3& n : mesh.normals) n = transform.normal(n);
    if (transform.flipsWinding())
        for (uvec3& t : mesh.indices) std::swap(t.y, t.z);
}

}  // namespace gibench
