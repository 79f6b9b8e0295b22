#pragma once
// Analytic shapes of scene files, as triangle meshes in object space. Every mesh comes back with
// its `materials` empty; the caller assigns them.

#include "core/scene/scene.h"

#include <array>

namespace gibench {

// Two triangles 0-1-2 and 0-2-3 over corners given counter-clockwise seen from the front, with
// uvs (0,0) (1,0) (1,1) (0,1) at the corners; flat (no shading normals).
Mesh makeQuad(const std::array<vec3, 4>& corners);

// The unit quad [-1,1]^2 in the XZ plane, facing +Y.
Mesh makeUnitQuad();

// The cube [-1,1]^3 as 12 triangles facing out (in when `inward`), each face with uvs over
// [0,1]^2; flat.
Mesh makeBox(bool inward);

// An icosphere: the icosahedron with each triangle split in four `subdivisions` times
// (20 * 4^subdivisions triangles) and its vertices pushed onto the sphere. Closed (every edge is
// shared by exactly two triangles), with unit shading normals along the radius. `inward` turns
// the winding and the normals towards the centre. No uvs.
Mesh makeSphere(const vec3& centre, float radius, int subdivisions, bool inward);

}  // namespace gibench
