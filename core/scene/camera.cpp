#include "core/scene/camera.h"

#include "core/config/json_summary.h"
#include "core/scene/camera_path.h"
#include "core/scene/world_limits.h"
#include "core/util/text_format.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace gibench {

const ParamTable kCameraParams = {
    {"eye", ParamType::Vec3, nullptr, "camera position (scene units)"},
    {"target", ParamType::Vec3, nullptr, "point the camera looks at"},
    {"up", ParamType::Vec3, Json::array({0, 1, 0}), "up direction"},
    {"vfov_deg", ParamType::Float, 45.0, "full vertical field of view in degrees", 1e-3, 179.0},
    {"resolution", ParamType::Json, Json::array({256, 256}), "[width, height] in pixels"},
    {"path", ParamType::Json, Json::array(), "keyframes [{frame, eye, target, up?, vfov_deg?}], linearly interpolated"},
};

static const ParamTable kKeyframeParams = {
    {"frame", ParamType::Float, nullptr, "frame index of this keyframe", 0.0},
    {"eye", ParamType::Vec3, nullptr, "camera position"},
    {"target", ParamType::Vec3, nullptr, "point looked at"},
    {"up", ParamType::Vec3, Json(), "up direction (default: the camera's)"},
    {"vfov_deg", ParamType::Float, Json(), "vertical field of view (default: the camera's)", 1e-3, 179.0},
};

// The camera basis, in double so that any finite float pose with eye != target and up not along
// the view gives a unit basis: in float, normalize() overflows or underflows for very long or
// very short vectors.
struct CameraBasis {
    glm::dvec3 forward, right;
};

static CameraBasis basisOf(const CameraPose& pose) {
    const glm::dvec3 forward = glm::normalize(glm::dvec3(pose.target) - glm::dvec3(pose.eye));
    return {forward, glm::normalize(glm::cross(forward, glm::dvec3(pose.up)))};
}

static void checkPose(Params& p, const WorldPose& pose, const glm::dvec3& worldOrigin) {
    const glm::dvec3 distance = glm::abs(pose.eye);
    if (std::max({distance.x, distance.y, distance.z}) > double(kMaxCoordinate))
        p.fail("eye", "expected coordinates within +-" + formatNumber(kMaxCoordinate) +
                          " (beyond, Embree may reject the camera's rays), got " + summarize(p.json().at("eye")));
    // As the renderers see it: relative to the world origin, in float.
    const CameraPose rounded = pose.relativeTo(worldOrigin);
    if (rounded.target == rounded.eye) p.fail("target", "expected a target different from eye");
    if (glm::cross(glm::dvec3(rounded.target) - glm::dvec3(rounded.eye), glm::dvec3(pose.up)) == glm::dvec3(0.0))
        p.fail("up", "expected an up direction not parallel to the view direction");
}

static std::string formatFrame(double frame) {
    std::ostringstream out;
    out << frame;
    return out.str();
}

// Refuses a path whose interpolated poses degenerate between keyframes `a` (at pointer `from`)
// and `b` (read by `p`).
static void checkSegment(Params& p, const std::string& from, const CameraDesc::Keyframe& a, const CameraDesc::Keyframe& b,
                         const glm::dvec3& worldOrigin) {
    const auto degeneracy = findDegeneratePose(a.pose.relativeTo(worldOrigin), b.pose.relativeTo(worldOrigin));
    if (!degeneracy) return;
    const std::string frame = formatFrame(double(a.frame) + degeneracy->t * double(b.frame - a.frame));
    const std::string between = "expected every pose interpolated between keyframes " + from + " and " + p.pointer() + " to ";
    switch (degeneracy->kind) {
        case PoseDegeneracy::Kind::EyeMeetsTarget: p.fail("", between + "keep eye and target apart, got eye == target near frame " + frame);
        case PoseDegeneracy::Kind::UpVanishes: p.fail("", between + "keep a non-zero up direction, got up == [0, 0, 0] near frame " + frame);
        case PoseDegeneracy::Kind::UpAlongView:
            p.fail("", between + "keep up not parallel to the view direction, got them parallel near frame " + frame);
    }
}

CameraDesc parseCamera(Params& p, const glm::dvec3& worldOrigin) {
    CameraDesc desc;
    WorldPose base;
    base.eye = p.getDVec3("eye");
    base.target = p.getDVec3("target");
    base.up = p.getVec3("up");
    base.vfovDeg = p.getFloat("vfov_deg");
    checkPose(p, base, worldOrigin);

    const Json res = p.getJson("resolution");
    const bool resOk = res.is_array() && res.size() == 2 && res[0].is_number_integer() && res[1].is_number_integer() &&
                       res[0].get<long long>() >= 1 && res[1].get<long long>() >= 1 && res[0].get<long long>() <= 16384 &&
                       res[1].get<long long>() <= 16384;
    if (!resOk) p.fail("resolution", "expected [width, height], integers in [1, 16384], got " + summarize(res));
    desc.width = res[0].get<int>();
    desc.height = res[1].get<int>();

    std::string previous;  // pointer of the keyframe before
    for (Params& k : p.children("path", "camera keyframe")) {
        Params kp = k.withTable(kKeyframeParams, "camera keyframe");
        CameraDesc::Keyframe key;
        key.frame = kp.getFloat("frame");
        key.pose.eye = kp.getDVec3("eye");
        key.pose.target = kp.getDVec3("target");
        key.pose.up = kp.has("up") ? kp.getVec3("up") : base.up;
        key.pose.vfovDeg = kp.has("vfov_deg") ? kp.getFloat("vfov_deg") : base.vfovDeg;
        checkPose(kp, key.pose, worldOrigin);
        kp.finish();
        if (!desc.keyframes.empty() && key.frame <= desc.keyframes.back().frame)
            kp.fail("frame", "expected keyframes in increasing frame order");
        if (!desc.keyframes.empty()) checkSegment(kp, previous, desc.keyframes.back(), key, worldOrigin);
        desc.keyframes.push_back(key);
        previous = kp.pointer();
    }
    if (desc.keyframes.empty()) desc.keyframes.push_back({0.0f, base});
    p.finish();
    return desc;
}

WorldPose CameraDesc::poseAt(float frame) const {
    if (frame <= keyframes.front().frame) return keyframes.front().pose;
    if (frame >= keyframes.back().frame) return keyframes.back().pose;
    auto next = std::upper_bound(keyframes.begin(), keyframes.end(), frame,
                                 [](float f, const Keyframe& k) { return f < k.frame; });
    const Keyframe& b = *next;
    const Keyframe& a = *(next - 1);
    const float t = (frame - a.frame) / (b.frame - a.frame);
    WorldPose pose;
    pose.eye = glm::mix(a.pose.eye, b.pose.eye, double(t));
    pose.target = glm::mix(a.pose.target, b.pose.target, double(t));
    pose.up = glm::mix(a.pose.up, b.pose.up, t);
    pose.vfovDeg = glm::mix(a.pose.vfovDeg, b.pose.vfovDeg, t);
    return pose;
}

PinholeCamera::PinholeCamera(const CameraPose& pose, int width, int height)
    : m_width(width), m_height(height), m_eye(pose.eye) {
    const CameraBasis basis = basisOf(pose);
    m_forward = vec3(basis.forward);
    const vec3 right = vec3(basis.right), up = vec3(glm::cross(basis.right, basis.forward));
    const float tanHalfFov = std::tan(0.5f * pose.vfovDeg * kPi / 180.0f);
    const float halfWidth = tanHalfFov * float(width) / float(height);  // of the film, at distance 1
    m_filmTopLeft = m_forward - halfWidth * right + tanHalfFov * up;
    m_filmPerPixelX = (2.0f * halfWidth / float(width)) * right;
    m_filmPerPixelY = (-2.0f * tanHalfFov / float(height)) * up;
}

}  // namespace gibench
