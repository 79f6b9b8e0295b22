#include "core/scene/scene_loader.h"

#include "core/config/input_file.h"
#include "core/config/json_summary.h"
#include "core/scene/obj_loader.h"
#include "core/scene/primitives.h"
#include "core/scene/texture_io.h"
#include "core/scene/transform.h"
#include "core/scene/unit_vector.h"
#include "core/scene/world_limits.h"
#include "core/scene/world_origin.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/text_format.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace gibench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Parameter tables, one per object type of a scene file. A "type" key selects the table of a
// material, shape or light.

const ParamTable kSceneParams = {
    {"camera", ParamType::Json, Json::object(), "suggested camera (keys of kCameraParams); {}: none"},
    {"default_albedo", ParamType::Color, 0.8, "albedo of OBJ faces without a material and of shapes without \"material\"", 0.0, 1.0},
    {"materials", ParamType::Json, Json::object(), "named materials {name: {type, ...}}"},
    {"shapes", ParamType::Json, Json::array(), "geometry [{type, ...}]"},
    {"lights", ParamType::Json, Json::array(), "suns and at most one environment [{type, ...}]"},
};

const ParamTable kDiffuseParams = {
    {"type", ParamType::String, nullptr, "\"diffuse\": Lambertian"},
    {"albedo", ParamType::Color, 0.8, "diffuse reflectance", 0.0, 1.0},
    {"albedo_texture", ParamType::String, Json(), "image whose texels replace albedo (uv-mapped); excludes albedo"},
    {"emission", ParamType::Color, 0.0, "radiance W/(sr m^2) leaving the front face", 0.0, kInf},
};

const ParamTable kGlossyParams = {
    {"type", ParamType::String, nullptr, "\"glossy\": Lambertian base + GGX lobe with Schlick Fresnel"},
    {"albedo", ParamType::Color, 0.8, "diffuse reflectance; albedo + specular <= 1 per channel", 0.0, 1.0},
    {"albedo_texture", ParamType::String, Json(), "image whose texels replace albedo (uv-mapped); excludes albedo"},
    {"specular", ParamType::Color, 0.04, "Fresnel reflectance at normal incidence", 0.0, 1.0},
    {"roughness", ParamType::Float, 0.5, "GGX alpha = roughness^2", 0.01, 1.0},
    {"emission", ParamType::Color, 0.0, "radiance W/(sr m^2) leaving the front face", 0.0, kInf},
};

// Every shape takes "name" (the mesh name; default: the shape's JSON pointer), "transform"
// (see kTransformParams; default: identity) and "material" (a name in "materials"; default: a
// diffuse material of albedo default_albedo).
ParamTable shapeTable(std::string type, ParamTable own) {
    ParamTable table = {{"type", ParamType::String, nullptr, "\"" + type + "\""}};
    table.insert(table.end(), own.begin(), own.end());
    table.push_back({"name", ParamType::String, Json(), "mesh name (default: the shape's JSON pointer)"});
    table.push_back({"transform", ParamType::Json, Json(), "placement {scale, rotate_deg, translate} or {matrix}"});
    table.push_back({"material", ParamType::String, Json(), "material name (default: default_albedo)"});
    return table;
}

const ParamTable kObjParams = shapeTable(
    "obj", {{"file", ParamType::String, nullptr, "Wavefront OBJ; its MTL gives materials unless \"material\" overrides them"},
            {"normals", ParamType::Bool, true, "shade with the OBJ's vertex normals where it has them (false: flat, the geometric normals)"}});
const ParamTable kQuadParams = shapeTable(
    "quad", {{"vertices", ParamType::Json, Json(), "4 corners counter-clockwise seen from the front (default: [-1,1]^2 in XZ facing +Y)"}});
const ParamTable kBoxParams = shapeTable(
    "box", {{"inward", ParamType::Bool, false, "faces point into the cube [-1,1]^3"}});
const ParamTable kSphereParams = shapeTable(
    "sphere", {{"center", ParamType::Vec3, Json::array({0, 0, 0}), "centre (scene units)"},
               {"radius", ParamType::Float, 1.0, "radius > 0 (scene units)"},
               {"subdivisions", ParamType::Int, 3, "icosphere levels: 20 * 4^subdivisions triangles", 0, 7},
               {"inward", ParamType::Bool, false, "winding and normals face the centre"}});
const ParamTable kTrianglesParams = shapeTable(
    "triangles", {{"vertices", ParamType::Json, nullptr, "[[x,y,z], ...]"},
                  {"indices", ParamType::Json, nullptr, "[[i,j,k], ...] counter-clockwise seen from the front"},
                  {"normals", ParamType::Json, Json(), "[[x,y,z], ...] one shading normal per vertex"},
                  {"uvs", ParamType::Json, Json(), "[[u,v], ...] one per vertex, (0,0) bottom-left of a texture"}});

const ParamTable kSunParams = {
    {"type", ParamType::String, nullptr, "\"sun\": parallel light"},
    {"direction", ParamType::Vec3, nullptr, "direction of travel, non-zero; normalised"},
    {"irradiance", ParamType::Color, nullptr, "W/m^2 on a surface facing the sun", 0.0, kInf},
};

const ParamTable kEnvironmentParams = {
    {"type", ParamType::String, nullptr, "\"environment\": constant radiance from every direction"},
    {"radiance", ParamType::Color, nullptr, "W/(sr m^2)", 0.0, kInf},
};

const ParamTable kEnvironmentMapParams = {
    {"type", ParamType::String, nullptr, "\"environment_map\": lat-long image, +Y up"},
    {"file", ParamType::String, nullptr, "image of radiance W/(sr m^2), e.g. an EXR"},
    {"scale", ParamType::Float, 1.0, "factor on the image", 0.0, kInf},
    {"rotate_y_deg", ParamType::Float, 0.0, "rotation of the map about +Y (right-handed), degrees"},
};

std::string formatColor(const Color& c) {
    std::ostringstream out;
    out << "[" << c.x << ", " << c.y << ", " << c.z << "]";
    return out.str();
}

std::string quotedNames(const std::map<std::string, uint32_t>& names) {
    std::string out;
    for (const auto& [name, index] : names) out += (out.empty() ? "\"" : ", \"") + name + "\"";
    return out.empty() ? "none" : out;
}

float minComponent(const Color& c) { return glm::min(c.x, glm::min(c.y, c.z)); }

// The renderer forms light powers and sampling weights as float products; half of FLT_MAX leaves
// room for their rounding.
constexpr double kMaxFloatProduct = 0.5 * double(FLT_MAX);

// An array of `size`-number tuples, `count` of them (0: any count), as floats.
std::vector<std::vector<float>> readTuples(Params& p, const std::string& name, std::size_t size, std::size_t count,
                                           const std::string& what) {
    const Json v = p.getJson(name);
    const std::string expected =
        "expected an array of " + (count ? std::to_string(count) + " " : std::string()) + what + ", got " + summarize(v);
    if (!v.is_array() || (count && v.size() != count)) p.fail(name, expected);
    std::vector<std::vector<float>> tuples;
    tuples.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const Json& t = v[i];
        if (!t.is_array() || t.size() != size) p.fail(name, expected);
        std::vector<float>& tuple = tuples.emplace_back();
        for (std::size_t k = 0; k < size; ++k) {
            const std::optional<float> x = asFloat(t[k]);
            if (!x && t[k].is_number())
                p.fail(name, expected + " (" + summarize(t[k]) + " at [" + std::to_string(i) + "][" + std::to_string(k) + "] is " +
                                 kFloatLimit + ")");
            if (!x) p.fail(name, expected);
            tuple.push_back(*x);
        }
    }
    return tuples;
}

std::vector<vec3> readPoints(Params& p, const std::string& name, std::size_t count) {
    std::vector<vec3> points;
    for (const auto& t : readTuples(p, name, 3, count, "[x, y, z] points")) points.emplace_back(t[0], t[1], t[2]);
    return points;
}

float triangleArea(const vec3& a, const vec3& b, const vec3& c) { return 0.5f * glm::length(glm::cross(b - a, c - a)); }

// Per-channel extremes and mean of a texture, for checking it as an albedo.
struct TextureStats {
    Color min{kInfinity}, max{-kInfinity}, mean{0.0f};
    bool finite = true;
};

TextureStats statsOf(const Texture& t) {
    TextureStats s;
    glm::dvec3 sum(0.0);
    for (const Color& c : t.texels) {
        s.finite = s.finite && isFinite(c);
        s.min = glm::min(s.min, c);
        s.max = glm::max(s.max, c);
        sum += glm::dvec3(c);
    }
    s.mean = Color(sum / double(std::max<std::size_t>(t.texels.size(), 1)));
    return s;
}

// A shape as read: meshes in its own coordinates, placed by SceneReader::placeShapes() once every
// shape is known.
struct Shape {
    Params params;
    std::vector<Mesh> meshes;
    Transform transform;
    std::string where;  // prefix of messages about its material
};

class SceneReader {
public:
    // Hashes `file` into Scene::files unless it is there already.
    void recordFile(const std::filesystem::path& file) {
        checkUtf8Path(file);
        if (m_recorded.insert(file.string()).second) m_scene.files.push_back({file.string(), sha256File(file)});
    }

    Scene read(Params& block) {
        Params p = block.withTable(kSceneParams, "scene");
        m_scene.description = block.json();
        m_defaultAlbedo = p.getColor("default_albedo");
        Params materials = p.child("materials", nullptr, "materials");
        std::optional<Params> camera;
        if (p.has("camera")) camera = p.child("camera", &kCameraParams, "camera");
        std::vector<Params> shapes = p.children("shapes", "shape");
        std::vector<Params> lights = p.children("lights", "light");
        p.finish();

        for (const auto& [name, value] : materials.json().items()) {
            Params m = materials.child(name, nullptr, "material \"" + name + "\"");
            const Material material = readMaterial(m, name);
            m_materialByName[name] = addMaterial(material, m.where("emission"));
        }
        for (Params& light : lights) readLight(light);
        for (Params& shape : shapes) readShape(shape);
        placeShapes();
        if (camera && !camera->json().empty()) m_scene.camera = parseCamera(*camera, m_scene.worldOrigin);
        checkLightPowers();
        return std::move(m_scene);
    }

private:
    // Loads `file` once per scene and checks it as an albedo map; `where` prefixes errors.
    const std::pair<int, TextureStats>& albedoTexture(const std::filesystem::path& file, const std::string& where) {
        if (auto it = m_textures.find(file.string()); it != m_textures.end()) return it->second;
        Texture texture;
        try {
            texture = loadTexture(file);
        } catch (const InputError& e) {
            throw InputError(where + e.what());
        }
        const TextureStats stats = statsOf(texture);
        if (!stats.finite || minComponent(stats.min) < 0.0f || maxComponent(stats.max) > 1.0f)
            throw InputError(where + "expected texels in [0, 1] in \"" + file.string() + "\", got values from " +
                             formatColor(stats.min) + " to " + formatColor(stats.max));
        recordFile(file);
        m_scene.textures.push_back(std::move(texture));
        const int index = static_cast<int>(m_scene.textures.size()) - 1;
        return m_textures.emplace(file.string(), std::make_pair(index, stats)).first->second;
    }

    // Adds `m`, whose emission key `emissionWhere` names in messages.
    uint32_t addMaterial(const Material& m, std::string emissionWhere) {
        m_scene.materials.push_back(m);
        m_emissionWhere.push_back(std::move(emissionWhere));
        return static_cast<uint32_t>(m_scene.materials.size()) - 1;
    }

    Material readMaterial(Params& block, const std::string& name) {
        const std::string type = block.discriminator("type", {"diffuse", "glossy"});
        Params p = block.withTable(type == "diffuse" ? kDiffuseParams : kGlossyParams, type + " material");
        Material m;
        m.name = name;
        m.type = type == "diffuse" ? MaterialType::Diffuse : MaterialType::Glossy;
        // With a texture, `albedo` holds its mean and `brightest` its per-channel maximum.
        Color brightest(0.0f);
        if (p.has("albedo_texture")) {
            if (p.has("albedo")) p.fail("albedo_texture", "expected either \"albedo\" or \"albedo_texture\", not both");
            const std::filesystem::path file = readPath(p, "albedo_texture");
            const auto& [index, stats] = albedoTexture(file, p.where("albedo_texture"));
            m.albedoTexture = index;
            m.albedo = stats.mean;
            brightest = stats.max;
        } else {
            m.albedo = p.getColor("albedo");
            brightest = m.albedo;
        }
        m.emission = p.getColor("emission");
        if (m.type == MaterialType::Glossy) {
            m.specular = p.getColor("specular");
            m.roughness = p.getFloat("roughness");
            const Color total = brightest + m.specular;
            if (maxComponent(total) > 1.0f)
                p.fail("specular", "expected albedo + specular <= 1 in every channel, got " + formatColor(brightest) + " + " +
                                       formatColor(m.specular) + (m.albedoTexture >= 0 ? " (the brightest texel)" : ""));
        }
        p.finish();
        return m;
    }

    uint32_t materialNamed(Params& p) {
        const std::string name = p.getString("material");
        auto it = m_materialByName.find(name);
        if (it == m_materialByName.end())
            p.fail("material", "unknown material \"" + name + "\" (defined: " + quotedNames(m_materialByName) + ")");
        return it->second;
    }

    uint32_t defaultMaterial() {
        if (!m_defaultMaterial) {
            Material m;
            m.name = "default";
            m.albedo = m_defaultAlbedo;
            m_defaultMaterial = addMaterial(m, "");
        }
        return *m_defaultMaterial;
    }

    uint32_t addObjMaterial(const ObjMaterial& source) {
        const std::string where = source.mtlFile.string() + ": material \"" + source.name + "\": ";
        const bool kdOk = isFinite(source.diffuse) && minComponent(source.diffuse) >= 0.0f && maxComponent(source.diffuse) <= 1.0f;
        if (!kdOk) throw InputError(where + "Kd: expected numbers in [0, 1], got " + formatColor(source.diffuse));
        if (!isFinite(source.emission) || minComponent(source.emission) < 0.0f)
            throw InputError(where + "Ke: expected numbers >= 0, got " + formatColor(source.emission));
        Material m;
        m.name = source.name;
        m.albedo = source.diffuse;
        m.emission = source.emission;
        if (!source.diffuseTexture.empty()) {
            const auto& [index, stats] = albedoTexture(source.diffuseTexture, where + "map_Kd: ");
            m.albedoTexture = index;
            m.albedo = stats.mean;
        }
        return addMaterial(m, where + "Ke: ");
    }

    // OBJ meshes with their materials mapped to scene materials, each MTL material added once
    // and only when a face uses it (so unused maps are not loaded).
    std::vector<Mesh> readObjShape(Params& p, const std::filesystem::path& file, bool shadingNormals, std::optional<uint32_t> override) {
        ObjModel model = readObj(file, p.where("file"));
        if (!shadingNormals)
            for (Mesh& mesh : model.meshes) mesh.normals.clear();
        for (const auto& f : model.files) recordFile(f);
        std::vector<std::optional<uint32_t>> sceneIndex(model.materials.size());
        for (Mesh& mesh : model.meshes) {
            for (uint32_t& m : mesh.materials) {
                if (override) {
                    m = *override;
                } else if (m == kNoObjMaterial) {
                    m = defaultMaterial();
                } else {
                    if (!sceneIndex[m]) sceneIndex[m] = addObjMaterial(model.materials[m]);
                    m = *sceneIndex[m];
                }
            }
        }
        return std::move(model.meshes);
    }

    Mesh readTriangles(Params& p) {
        Mesh mesh;
        mesh.positions = readPoints(p, "vertices", 0);
        const std::size_t n = mesh.positions.size();
        const Json indices = p.getJson("indices");
        const std::string expected = "expected an array of [i, j, k] vertex indices, each in [0, " + std::to_string(n) + ")";
        if (!indices.is_array() || indices.empty()) p.fail("indices", expected + ", at least one, got " + summarize(indices));
        for (const Json& t : indices) {
            const bool ok = t.is_array() && t.size() == 3 && std::all_of(t.begin(), t.end(), [&](const Json& i) {
                                return i.is_number_integer() && i.get<long long>() >= 0 && i.get<long long>() < static_cast<long long>(n);
                            });
            if (!ok) p.fail("indices", expected + ", got " + summarize(t));
            mesh.indices.emplace_back(t[0].get<uint32_t>(), t[1].get<uint32_t>(), t[2].get<uint32_t>());
        }
        if (p.has("normals")) {
            mesh.normals = readPoints(p, "normals", n);
            for (vec3& normal : mesh.normals) {
                const std::optional<vec3> unit = unitVector(normal);
                if (!unit) p.fail("normals", "expected non-zero normals");
                normal = *unit;
            }
        }
        if (p.has("uvs"))
            for (const auto& t : readTuples(p, "uvs", 2, n, "[u, v] pairs, one per vertex")) mesh.uvs.emplace_back(t[0], t[1]);
        return mesh;
    }

    void readShape(Params& block) {
        const std::string type = block.discriminator("type", {"obj", "quad", "box", "sphere", "triangles"});
        static const std::map<std::string, const ParamTable*> tables = {
            {"obj", &kObjParams}, {"quad", &kQuadParams}, {"box", &kBoxParams}, {"sphere", &kSphereParams}, {"triangles", &kTrianglesParams}};
        Params p = block.withTable(*tables.at(type), "shape \"" + type + "\"");

        // Every key is read and checked before the (possibly slow) geometry is built.
        const std::string name = p.has("name") ? p.getString("name") : std::string();
        Transform transform;
        if (p.has("transform")) {
            Params t = p.child("transform", &kTransformParams, "transform");
            transform = parseTransform(t);
        }
        std::optional<uint32_t> material;
        if (p.has("material")) material = materialNamed(p);

        std::vector<Mesh> meshes;
        if (type == "obj") {
            const std::filesystem::path file = readPath(p, "file");
            const bool shadingNormals = p.getBool("normals");
            p.finish();
            meshes = readObjShape(p, file, shadingNormals, material);
            if (!name.empty())
                for (Mesh& mesh : meshes) mesh.name = name + "/" + mesh.name;
        } else {
            Mesh mesh;
            if (type == "quad") {
                if (p.has("vertices")) {
                    const std::vector<vec3> v = readPoints(p, "vertices", 4);
                    if (triangleArea(v[0], v[1], v[2]) == 0.0f || triangleArea(v[0], v[2], v[3]) == 0.0f)
                        p.fail("vertices", "expected 4 corners whose triangles 0-1-2 and 0-2-3 have non-zero area, got " +
                                               summarize(p.json().at("vertices")));
                    mesh = makeQuad({v[0], v[1], v[2], v[3]});
                } else {
                    mesh = makeUnitQuad();
                }
            } else if (type == "box") {
                mesh = makeBox(p.getBool("inward"));
            } else if (type == "sphere") {
                // The centre joins the transform, in double, so that a sphere far away stays round.
                transform = transform.afterTranslation(p.getDVec3("center"));
                const float radius = p.getFloat("radius");
                if (radius <= 0.0f) p.fail("radius", "expected a number > 0, got " + summarize(p.json().at("radius")));
                const int subdivisions = static_cast<int>(p.getInt("subdivisions"));
                mesh = makeSphere(vec3(0.0f), radius, subdivisions, p.getBool("inward"));
            } else {
                mesh = readTriangles(p);
            }
            p.finish();
            mesh.name = name.empty() ? p.pointer() : name;
            mesh.materials.assign(mesh.indices.size(), material ? *material : defaultMaterial());
            meshes.push_back(std::move(mesh));
        }

        checkResolution(p, meshes);
        m_shapes.push_back({p, std::move(meshes), transform, p.where(material ? "material" : (type == "obj" ? "file" : ""))});
    }

    // A shape's own coordinates are floats: they must resolve the shape to 1/4096 of its size,
    // else far-off vertices have already lost it (an OBJ exported 1e6 units from its origin). The
    // transform, in double, is what places a shape far away.
    static void checkResolution(Params& p, const std::vector<Mesh>& meshes) {
        Bounds3 bounds;
        for (const Mesh& mesh : meshes)
            for (const vec3& v : mesh.positions) bounds.extend(v);
        if (bounds.empty()) return;
        const float farthest = maxComponent(glm::max(glm::abs(bounds.min), glm::abs(bounds.max)));
        const float size = maxComponent(bounds.extent());
        if (double(farthest) * 0x1p-23 > double(size) * 0x1p-12)
            p.fail(p.has("vertices") ? "vertices" : p.has("file") ? "file" : "", "expected vertices whose floats resolve the shape to 1/4096 of its size " +
                                                            formatNumber(size) + ", got coordinates up to " + formatNumber(farthest) +
                                                            "; give them near the origin and place the shape with \"transform\"");
    }

    // Chooses the world origin from every transformed vertex, then stores each shape's meshes
    // relative to it.
    void placeShapes() {
        WorldBounds world;
        for (const Shape& shape : m_shapes)
            for (const Mesh& mesh : shape.meshes)
                for (const vec3& v : mesh.positions) world.extend(shape.transform.point(v));
        m_scene.worldOrigin = worldOriginFor(world);
        for (Shape& shape : m_shapes) placeShape(shape);
        m_shapes.clear();
    }

    void placeShape(Shape& shape) {
        Params& p = shape.params;
        std::size_t triangles = 0, degenerate = 0;
        for (Mesh& mesh : shape.meshes) {
            checkCoordinates(p, mesh, shape.transform);
            transformMesh(mesh, shape.transform, m_scene.worldOrigin);
            triangles += mesh.triangleCount();
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) degenerate += hasZeroArea(mesh, t);
            if (mesh.uvs.empty())
                for (uint32_t m : mesh.materials)
                    if (m_scene.materials[m].albedoTexture >= 0)
                        throw InputError(shape.where + "mesh \"" + mesh.name + "\" has no uvs for the albedo texture of material \"" +
                                         m_scene.materials[m].name + "\"");
            m_scene.meshes.push_back(std::move(mesh));
        }
        // After the transform: a tiny scale can collapse every triangle of a valid mesh.
        if (degenerate == triangles)
            p.fail("", "expected a shape with triangles of non-zero area, got all " + std::to_string(triangles) +
                           " degenerate (zero area as floats) after its transform");
    }

    // World-space positions of `mesh`, a shape of `p`, must be within the ray tracer's reach.
    static void checkCoordinates(Params& p, const Mesh& mesh, const Transform& transform) {
        for (const vec3& local : mesh.positions) {
            const glm::dvec3 v = transform.point(local);
            const glm::dvec3 distance = glm::abs(v);
            if (!(std::max({distance.x, distance.y, distance.z}) <= double(kMaxCoordinate)))
                p.fail("", "mesh \"" + mesh.name + "\": expected vertices within +-" + formatNumber(kMaxCoordinate) +
                               " after the transform (Embree drops geometry beyond), got [" + formatNumber(v.x) + ", " +
                               formatNumber(v.y) + ", " + formatNumber(v.z) + "]");
        }
    }

    // The light sampler weighs lights by power, in float (core/render/light_sampler.cpp): emitting
    // triangles by pi * area * luminance(emission), suns and the environment over the disc of the
    // scene's bounding sphere. Each must be finite for it; refused here, with the key to change.
    void checkLightPowers() {
        for (const Mesh& mesh : m_scene.meshes)
            for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
                const Material& material = m_scene.materials[mesh.materials[t]];
                if (!material.isEmissive()) continue;
                const uvec3 i = mesh.indices[t];
                const glm::dvec3 a(mesh.positions[i.x]), b(mesh.positions[i.y]), c(mesh.positions[i.z]);
                const double twiceArea = glm::length(glm::cross(b - a, c - a));
                const double power = kPi * 0.5 * twiceArea * double(luminance(material.emission));
                // The float area is half the length of the cross product, whose squared length must fit.
                if (twiceArea * twiceArea > kMaxFloatProduct || power > kMaxFloatProduct)
                    throw InputError(m_emissionWhere[mesh.materials[t]] + "expected an emission whose light power (pi x area x "
                                     "luminance) on mesh \"" + mesh.name + "\" fits a float, got " + formatNumber(power) +
                                     " W on a triangle of " + formatNumber(0.5 * twiceArea) + " m^2");
            }
        const double radius = 0.5 * glm::length(glm::dvec3(m_scene.bounds().extent()));
        const double discArea = kPi * std::max(radius * radius, 1e-30);
        for (std::size_t s = 0; s < m_scene.suns.size(); ++s) {
            const double power = discArea * double(luminance(m_scene.suns[s].irradiance));
            if (power > kMaxFloatProduct)
                throw InputError(m_sunWhere[s] + "expected an irradiance whose power over the scene (irradiance x " +
                                 formatNumber(discArea) + " m^2, the disc of its bounding sphere) fits a float, got " +
                                 formatNumber(power) + " W");
        }
        if (!m_scene.environment) return;
        const EnvironmentLight& environment = *m_scene.environment;
        double brightest = luminance(environment.radiance);  // W/(sr m^2)
        std::size_t rowLength = 1;
        if (environment.map) {
            brightest = 0.0;
            for (const Color& texel : environment.map->texels) brightest = std::max(brightest, double(luminance(texel)));
            brightest *= environment.scale;
            rowLength = std::size_t(environment.map->width);
        }
        const double power = 4.0 * kPi * discArea * brightest;
        // A map's sampling weights are summed per row and stored as floats.
        if (power > kMaxFloatProduct || brightest * double(rowLength) > kMaxFloatProduct)
            throw InputError(m_environmentWhere + "expected an environment whose power over the scene (4 pi x " + formatNumber(discArea) +
                             " m^2, the disc of its bounding sphere, x radiance) and whose map rows fit a float, got " +
                             formatNumber(power) + " W");
    }

    void readLight(Params& block) {
        const std::string type = block.discriminator("type", {"sun", "environment", "environment_map"});
        if (type == "sun") {
            Params p = block.withTable(kSunParams, "light \"sun\"");
            SunLight sun;
            const std::optional<vec3> direction = unitVector(p.getVec3("direction"));
            if (!direction) p.fail("direction", "expected a non-zero direction, got [0, 0, 0]");
            sun.direction = *direction;
            sun.irradiance = p.getColor("irradiance");
            p.finish();
            m_scene.suns.push_back(sun);
            m_sunWhere.push_back(p.where("irradiance"));
            return;
        }
        if (m_scene.environment)
            block.fail("", "expected at most one environment light (\"environment\" or \"environment_map\"); " + m_environmentPointer +
                               " is one already");
        m_environmentPointer = block.pointer();
        EnvironmentLight environment;
        if (type == "environment") {
            Params p = block.withTable(kEnvironmentParams, "light \"environment\"");
            environment.radiance = p.getColor("radiance");
            p.finish();
            m_environmentWhere = p.where("radiance");
        } else {
            Params p = block.withTable(kEnvironmentMapParams, "light \"environment_map\"");
            const std::filesystem::path file = readPath(p, "file");
            environment.scale = p.getFloat("scale");
            const float degrees = p.getFloat("rotate_y_deg");
            p.finish();
            m_environmentWhere = p.where("scale");
            Texture map;
            try {
                map = loadTexture(file);
            } catch (const InputError& e) {
                throw InputError(p.where("file") + e.what());
            }
            const TextureStats stats = statsOf(map);
            if (!stats.finite || minComponent(stats.min) < 0.0f)
                p.fail("file", "expected finite radiance >= 0 in \"" + file.string() + "\", got values from " + formatColor(stats.min) +
                                   " to " + formatColor(stats.max));
            recordFile(file);
            environment.map = std::make_shared<const Texture>(std::move(map));
            environment.toWorld = mat3(glm::rotate(mat4(1.0f), glm::radians(degrees), vec3(0.0f, 1.0f, 0.0f)));
        }
        m_scene.environment = environment;
    }

    Scene m_scene;
    std::vector<Shape> m_shapes;
    Color m_defaultAlbedo{0.8f};
    std::optional<uint32_t> m_defaultMaterial;
    std::map<std::string, uint32_t> m_materialByName;
    std::map<std::string, std::pair<int, TextureStats>> m_textures;  // by path
    std::set<std::string> m_recorded;
    std::string m_environmentPointer;
    // Where messages about light power point, per material, sun and the environment.
    std::vector<std::string> m_emissionWhere;
    std::vector<std::string> m_sunWhere;
    std::string m_environmentWhere;
};

}  // namespace

std::filesystem::path scenesDirectory() {
    const char* value = std::getenv("GIBENCH_SCENES");
    if (value && *value) return std::filesystem::path(value);
    return (std::filesystem::path(GIBENCH_SOURCE_DIR) / ".." / "shared" / "scenes").lexically_normal();
}

std::filesystem::path readPath(Params& p, const std::string& name) {
    static const std::string kVariable = "${GIBENCH_SCENES}";
    const std::string text = p.getString(name);
    if (text.empty()) p.fail(name, "expected a file path, got \"\"");
    const bool prefixed = text.rfind(kVariable, 0) == 0;
    const std::string rest = prefixed ? text.substr(kVariable.size()) : text;
    if (rest.find("${") != std::string::npos || (prefixed && !rest.empty() && rest[0] != '/'))
        p.fail(name, "expected a path with no variable other than a leading \"" + kVariable + "/\", got \"" + text + "\"");
    std::filesystem::path path = prefixed ? scenesDirectory() / rest.substr(rest.empty() ? 0 : 1) : std::filesystem::path(text);
    if (path.is_relative()) path = p.baseDir() / path;
    return path.lexically_normal();
}

Scene loadSceneFile(const std::filesystem::path& file) {
    Params block(loadJsonFile(file), file.string(), "", "scene", &kSceneParams);
    SceneReader reader;
    reader.recordFile(file);
    return reader.read(block);
}

Scene loadScene(Params& block) { return SceneReader().read(block); }

}  // namespace gibench
