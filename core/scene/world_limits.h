#pragma once
// How far from the origin a scene may reach. Embree drops geometry with a coordinate beyond its
// FLT_LARGE (1.844e18) without a word and rejects a ray whose origin lies beyond it. The renderers
// see coordinates relative to the scene's world origin (Scene::worldOrigin), the difference of
// two world positions, so world positions stay within half of that; products of two such numbers
// still fit a float.

namespace gibench {

inline constexpr float kMaxCoordinate = 0.5f * 1.844e18f;

}  // namespace gibench
