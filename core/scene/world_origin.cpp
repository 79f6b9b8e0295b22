#include "core/scene/world_origin.h"

#include <algorithm>
#include <cmath>

namespace gibench {

glm::dvec3 worldOriginFor(const WorldBounds& bounds) {
    if (bounds.empty()) return glm::dvec3(0.0);
    const glm::dvec3 side = bounds.max - bounds.min;
    const double largest = std::max({side.x, side.y, side.z});
    // A point (every vertex the same) still gets a grid: the smallest normal double.
    const double step = std::ldexp(1.0, std::ilogb(std::max(largest, 0x1p-1022)) + 3);
    const glm::dvec3 centre = 0.5 * (bounds.min + bounds.max);
    return glm::round(centre / step) * step;
}

}  // namespace gibench
