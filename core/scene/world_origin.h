#pragma once
// Where the renderers' coordinates start. Meshes and the camera are stored as float offsets from a
// world origin chosen near the scene, computed in double from the file's coordinates, so that a
// scene renders the same wherever it is placed: a Cornell box moved 1e7 units from the origin keeps
// the millimetres float would round to a metre there.

#include "core/util/math.h"

namespace gibench {

// World-space bounds in double, of the scene's transformed vertices.
struct WorldBounds {
    glm::dvec3 min{kInfinity};
    glm::dvec3 max{-kInfinity};

    void extend(const glm::dvec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
};

// The origin for a scene of these bounds: its centre rounded to a multiple of a power of two of at
// least 4x its largest side. Offsets from it are exact in double, and a scene that contains or
// nearly contains the origin keeps 0 (the same floats as its file). A scene moved by a multiple of
// that power of two gets the same floats as before the move, hence the same image; (0, 0, 0) for
// empty bounds.
glm::dvec3 worldOriginFor(const WorldBounds& bounds);

}  // namespace gibench
