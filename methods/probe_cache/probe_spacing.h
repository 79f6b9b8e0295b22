#pragma once
// A store's probe spacing (its cell or texel edge), given by two keys: `<key>` in scene units, or,
// when that is 0, `<key>_relative` as a fraction of the largest side of the scene's bounding box,
// so that one config fits scenes of any scale (1/75: 0.4 units on Sponza, MAMBA's fine cell).
//
// A spacing must be one float positions can tell apart: the scene may reach at most
// kMaxSpacingsFromOrigin spacings from the origin, so that a float position (24-bit mantissa)
// resolves a cell to 1/8 of its edge or better even at the scene's far end, and every cell
// coordinate fits a 32-bit integer with room to spare.

#include "core/config/params.h"
#include "core/util/math.h"

#include <string>

namespace gibench {

// The two rows of a spacing, `what` naming the edge ("grid cell edge").
ParamTable spacingParams(const std::string& key, const std::string& what);

inline constexpr double kMaxSpacingsFromOrigin = 1 << 20;

class ProbeSpacing {
public:
    ProbeSpacing() = default;  // 0 in scene units and relative: resolve() gives 0
    // Reads `key` and `key_relative` (rows from spacingParams).
    ProbeSpacing(Params& params, const std::string& key);

    // The edge in scene units for a scene of these bounds; 0 when the bounds are empty (no
    // geometry: nothing to place probes on). Throws InputError naming `key_relative` when the
    // relative size is used on bounds with no extent, and naming the key in use when the scene
    // reaches more than kMaxSpacingsFromOrigin edges from the origin.
    float resolve(const Bounds3& sceneBounds) const;

private:
    float m_absolute = 0.0f;
    float m_relative = 0.0f;
    std::string m_key;
    // "FILE: /pointer/key: " and ".../key_relative: ", for the errors only resolve() can find.
    std::string m_absoluteWhere;
    std::string m_relativeWhere;
};

}  // namespace gibench
