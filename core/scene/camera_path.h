#pragma once
// Where a camera path degenerates between its keyframes. CameraDesc::poseAt() interpolates eye,
// target and up linearly, so a path whose keyframes are each valid can still pass a pose whose eye
// meets its target, whose up vanishes or whose up lies along the view: the camera then has no
// basis and its rays are NaN.

#include "core/scene/camera.h"

#include <optional>

namespace gibench {

struct PoseDegeneracy {
    enum class Kind { EyeMeetsTarget, UpVanishes, UpAlongView };
    Kind kind;
    double t;  // in (0, 1): how far from the first keyframe to the second
};

// The degenerate pose strictly between the poses `a` and `b` (each valid on its own), found
// analytically; a pose counts as degenerate when it is within float rounding of the interpolated
// coordinates of being so. None when every pose between them has a camera basis.
std::optional<PoseDegeneracy> findDegeneratePose(const CameraPose& a, const CameraPose& b);

}  // namespace gibench
