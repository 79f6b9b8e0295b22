#pragma once
// Pinhole camera and camera paths (keyframes), since cache methods run over many frames.

#include "core/config/params.h"
#include "core/util/math.h"

#include <vector>

namespace gibench {

// A camera pose where the renderers work: relative to the scene's world origin
// (Scene::worldOrigin), in float like the meshes.
struct CameraPose {
    vec3 eye{0.0f};
    vec3 target{0.0f, 0.0f, -1.0f};
    vec3 up{0.0f, 1.0f, 0.0f};
    float vfovDeg = 45.0f;  // full vertical field of view
};

// A camera pose as a scene or run config writes it: positions in world coordinates, in double so
// that a camera 1e7 units from the origin keeps its millimetres until the pose is rebased.
struct WorldPose {
    glm::dvec3 eye{0.0};
    glm::dvec3 target{0.0, 0.0, -1.0};
    vec3 up{0.0f, 1.0f, 0.0f};
    float vfovDeg = 45.0f;

    // The pose relative to `worldOrigin`, rounded once to float.
    CameraPose relativeTo(const glm::dvec3& worldOrigin) const {
        return {vec3(eye - worldOrigin), vec3(target - worldOrigin), up, vfovDeg};
    }
    bool operator==(const WorldPose&) const = default;
};

// What a scene or run config says of the camera: resolution and one pose per keyframe.
struct CameraDesc {
    int width = 256;
    int height = 256;
    struct Keyframe {
        float frame = 0.0f;
        WorldPose pose;
    };
    std::vector<Keyframe> keyframes;  // sorted by frame, at least one

    // Linear interpolation between the keyframes around `frame`; held constant outside them.
    WorldPose poseAt(float frame) const;
    bool isStatic() const { return keyframes.size() == 1; }
};

// Reads {"eye", "target", "up", "vfov_deg", "resolution": [w, h], "path": [{"frame", "eye",
// "target", "up"?, "vfov_deg"?}, ...]}; a path's keys default to the top-level pose. Every pose,
// the interpolated ones included (camera_path.h), must have eye != target and up neither zero nor
// along the view as the renderers see it (relative to the scene's `worldOrigin`, in float), and
// the eye must lie within kMaxCoordinate (world_limits.h); else InputError.
CameraDesc parseCamera(Params& params, const glm::dvec3& worldOrigin);
extern const ParamTable kCameraParams;

struct Ray {
    vec3 origin;
    vec3 direction;  // unit length
};

class PinholeCamera {
public:
    PinholeCamera(const CameraPose& pose, int width, int height);

    // Ray through film position (x, y) in pixels, (0,0) the top-left corner of the image. Inline,
    // with the film's steps per pixel precomputed: a call with two divisions took 2.6 % of a
    // probe-cache frame's samples.
    Ray generateRay(float x, float y) const { return {m_eye, directionThrough(x, y)}; }
    // The unit direction of generateRay(x, y), for a caller that writes a ray's fields in place.
    vec3 directionThrough(float x, float y) const { return glm::normalize(m_filmTopLeft + x * m_filmPerPixelX + y * m_filmPerPixelY); }
    int width() const { return m_width; }
    int height() const { return m_height; }
    const vec3& position() const { return m_eye; }
    const vec3& forward() const { return m_forward; }

private:
    int m_width, m_height;
    vec3 m_eye, m_forward;
    // The unnormalised direction through the film's top-left corner, and its change per pixel
    // rightwards and downwards: the film lies at distance 1 along m_forward.
    vec3 m_filmTopLeft, m_filmPerPixelX, m_filmPerPixelY;
};

}  // namespace gibench
