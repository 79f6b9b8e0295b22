#pragma once
// Wavefront OBJ + MTL files through tinyobjloader, as meshes and raw materials; scene_loader turns
// the materials into scene materials.

#include "core/scene/scene.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gibench {

// The terms of an MTL material gibench uses. Every other term (Ka, Ks, Ns, Ni, d, illum, bump
// and other maps, texture options such as -s and -o) is ignored.
struct ObjMaterial {
    std::string name;
    Color diffuse{0.0f};                   // Kd
    Color emission{0.0f};                  // Ke, radiance W/(sr m^2)
    std::filesystem::path diffuseTexture;  // map_Kd resolved against the MTL's folder; empty: none
    std::filesystem::path mtlFile;         // the file that defines the material
};

// Mesh::materials value of a face that has no material (no usemtl before it).
inline constexpr uint32_t kNoObjMaterial = UINT32_MAX;

struct ObjModel {
    // One mesh per OBJ group, in object space; Mesh::materials index `materials`.
    std::vector<Mesh> meshes;
    std::vector<ObjMaterial> materials;
    std::vector<std::filesystem::path> files;  // the OBJ, then every MTL read
};

// Reads `file` and the MTL files its mtllib lines name (relative to the OBJ's folder), splitting
// polygons into triangles. A mesh keeps shading normals and uvs when every face corner of it has
// them, one vertex per distinct (position, normal, uv) corner. Normals are normalised; a zero
// normal (Sponza has one) becomes the area-weighted normal of the faces around it.
// Everything tinyobjloader reports, warnings included (an unknown usemtl name, an index out of
// range, a face of two vertices), is an InputError, since each one means data was dropped or
// replaced by a default. Messages start with `where` (e.g. "scene.json: /shapes/0/file: "):
//   <where>cannot read OBJ "<file>": <reason>
//   <where>cannot read MTL "<mtl>" named by "<file>": <reason>
//   <where>invalid OBJ "<file>": <tinyobjloader's message>
// Before tinyobjloader reads them, the OBJ and its MTLs pass checkObjText()/checkMtlText()
// (obj_text.h: numbers, face indices, mtllib names, binary files, each error naming the line).
// A model that would render as nothing is refused too:
//   <where>invalid OBJ "<file>": no faces
//   <where>invalid OBJ "<file>": all N triangles are degenerate (zero area)
ObjModel readObj(const std::filesystem::path& file, const std::string& where);

}  // namespace gibench
