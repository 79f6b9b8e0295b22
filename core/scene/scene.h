#pragma once
// A scene as the renderers see it: triangle meshes in world space, materials, textures, lights
// and a camera. Built by loadScene() (scene_loader.h) from a JSON scene description.

#include "core/config/params.h"
#include "core/scene/camera.h"
#include "core/util/math.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gibench {

// Linear RGB texels, rows from the top; used for albedo maps and environment maps.
struct Texture {
    int width = 0;
    int height = 0;
    std::vector<Color> texels;

    // Bilinear lookup with repeat wrapping; uv (0,0) is the bottom-left corner (OBJ convention).
    Color lookup(const vec2& uv) const;
};

enum class MaterialType {
    Diffuse,  // Lambertian
    Glossy,   // Lambertian base plus a GGX microfacet lobe with Schlick Fresnel
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    Color albedo{0.8f};      // diffuse reflectance in [0,1]
    int albedoTexture = -1;  // index into Scene::textures; when set, replaces `albedo`
    Color specular{0.0f};    // Glossy: Fresnel reflectance at normal incidence; albedo + specular <= 1
    float roughness = 0.5f;  // Glossy: GGX alpha = roughness^2, roughness in [0.01, 1]
    Color emission{0.0f};    // radiance W/(sr m^2) leaving the front face (counter-clockwise winding)

    bool isEmissive() const { return maxComponent(emission) > 0.0f; }
};

struct Mesh {
    std::string name;
    std::vector<vec3> positions;       // world space, relative to Scene::worldOrigin
    std::vector<vec3> normals;         // empty, or one unit shading normal per position
    std::vector<vec2> uvs;             // empty, or one per position
    std::vector<uvec3> indices;        // triangles, counter-clockwise seen from the front
    std::vector<uint32_t> materials;   // one index into Scene::materials per triangle

    std::size_t triangleCount() const { return indices.size(); }
};

// Whether triangle `t` of `mesh` has an area below the smallest normal float: zero for a renderer
// that flushes subnormals, and never hit by a ray.
bool hasZeroArea(const Mesh& mesh, std::size_t t);

// A directional light: parallel rays travelling along `direction`, delivering `irradiance`
// W/m^2 to a surface facing them.
struct SunLight {
    vec3 direction{0.0f, -1.0f, 0.0f};  // unit, direction of travel
    Color irradiance{1.0f};
};

// Light arriving from infinitely far away: `radiance` everywhere, or `map` (lat-long, +Y up)
// × `scale`, turned into the world by `toWorld`.
struct EnvironmentLight {
    Color radiance{0.0f};
    std::shared_ptr<const Texture> map;  // null: constant radiance
    float scale = 1.0f;
    mat3 toWorld{1.0f};
};

// A file the scene read, with its content hash, so a reference image can be keyed on content.
struct SceneFile {
    std::string path;
    std::string sha256;
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<SunLight> suns;
    std::optional<EnvironmentLight> environment;
    std::optional<CameraDesc> camera;  // the scene's suggested camera, if it has one
    // Where the meshes' coordinates start in the scene file's world (world_origin.h); a camera
    // pose becomes the renderers' by WorldPose::relativeTo(worldOrigin).
    glm::dvec3 worldOrigin{0.0};
    std::vector<SceneFile> files;      // every file read, with its SHA-256
    Json description;                  // the scene JSON as read (identifies the scene with `files`)

    Bounds3 bounds() const;
    std::size_t triangleCount() const;
};

}  // namespace gibench
