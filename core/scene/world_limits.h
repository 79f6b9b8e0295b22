#pragma once
// How far from the origin a scene may reach. Embree drops geometry with a coordinate beyond its
// FLT_LARGE (1.844e18) without a word and rejects a ray whose origin lies beyond it, so scene
// coordinates and the camera stay within; products of two such numbers still fit a float.

namespace gibench {

inline constexpr float kMaxCoordinate = 1.844e18f;

}  // namespace gibench
