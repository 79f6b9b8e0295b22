#include "core/scene/scene_loader.h"

#include "core/util/error.h"
#include "core/util/hash.h"
#include "support/temp_folder.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>

namespace gibench {
namespace {

const std::filesystem::path kSourceDir = GIBENCH_SOURCE_DIR;
const ParamTable kTestPathTable = {{"file", ParamType::String, nullptr, "a path"}};

vec3 faceNormal(const Mesh& m, const uvec3& t) {
    return glm::normalize(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
}

vec3 centroid(const Mesh& m, const uvec3& t) { return (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f; }

const Material* materialNamed(const Scene& scene, const std::string& name) {
    for (const Material& m : scene.materials)
        if (m.name == name) return &m;
    return nullptr;
}

void expectVec(const vec3& got, const vec3& want, float tolerance, const std::string& what) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tolerance) << what << " component " << c;
}

// The error loading `text` as a scene file "scene.json" in `folder` gives.
std::string errorOf(const TempFolder& folder, const std::string& text) {
    const auto file = folder.write("scene.json", text);
    try {
        loadSceneFile(file);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

Scene loadText(const TempFolder& folder, const std::string& text) { return loadSceneFile(folder.write("scene.json", text)); }

// Loads a scene of the third-party collection, or skips the test when the collection is absent.
#define LOAD_SHARED_SCENE(scene, config, required)                                                           \
    if (!std::filesystem::exists(scenesDirectory() / (required)))                                          \
        GTEST_SKIP() << "third-party scenes not found in " << scenesDirectory() << " (set GIBENCH_SCENES)";   \
    const auto loadStart = std::chrono::steady_clock::now();                                                \
    const Scene scene = loadSceneFile(kSourceDir / "configs" / "scenes" / (config));                        \
    std::cout << (config) << " loaded in "                                                                  \
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count() << " s\n"

// ---- The built-in Cornell box -------------------------------------------------------------------

TEST(CornellBox, BuiltInHasThirtyTwoTrianglesInAFiftyFiveCentimetreBox) {
    const Scene scene = loadSceneFile(kSourceDir / "configs" / "scenes" / "cornell_box.json");
    // 5 walls + light + 2 blocks of a top and 4 sides, 2 triangles each.
    EXPECT_EQ(scene.triangleCount(), 32u);
    EXPECT_EQ(scene.meshes.size(), 16u);
    const Bounds3 b = scene.bounds();
    expectVec(b.min, vec3(0.0f), 1e-6f, "min");
    expectVec(b.max, vec3(0.556f, 0.5488f, 0.5592f), 1e-6f, "max");
    EXPECT_TRUE(scene.suns.empty());
    EXPECT_FALSE(scene.environment.has_value());
}

TEST(CornellBox, EveryFaceFacesIntoTheBoxOrOutOfItsBlockAndTheLightDown) {
    const Scene scene = loadSceneFile(kSourceDir / "configs" / "scenes" / "cornell_box.json");
    auto blockCentre = [&](const std::string& prefix) {
        Bounds3 b;
        for (const Mesh& m : scene.meshes)
            if (m.name.rfind(prefix, 0) == 0)
                for (const vec3& p : m.positions) b.extend(p);
        return b.centre();
    };
    const vec3 boxCentre = scene.bounds().centre();
    const vec3 shortBlock = blockCentre("short_block"), tallBlock = blockCentre("tall_block");
    int walls = 0, blockFaces = 0, lights = 0;
    for (const Mesh& m : scene.meshes) {
        for (const uvec3& t : m.indices) {
            const vec3 n = faceNormal(m, t), c = centroid(m, t);
            if (m.name == "light") {
                expectVec(n, vec3(0, -1, 0), 1e-6f, "light normal");
                ++lights;
            } else if (m.name.rfind("short_block", 0) == 0 || m.name.rfind("tall_block", 0) == 0) {
                const vec3 centre = m.name[0] == 's' ? shortBlock : tallBlock;
                EXPECT_GT(glm::dot(n, glm::normalize(c - centre)), 0.2f) << m.name << " faces into its block";
                ++blockFaces;
            } else {
                EXPECT_GT(glm::dot(n, glm::normalize(boxCentre - c)), 0.2f) << m.name << " faces out of the box";
                // Walls are axis-aligned up to the published 3 mm skew of the left wall.
                EXPECT_GT(maxComponent(glm::abs(n)), 0.999f) << m.name;
                ++walls;
            }
        }
    }
    EXPECT_EQ(walls, 10);
    EXPECT_EQ(blockFaces, 20);
    EXPECT_EQ(lights, 2);
}

TEST(CornellBox, LightIsTheOnlyEmitterWithThePublishedRadianceAndReflectances) {
    const Scene scene = loadSceneFile(kSourceDir / "configs" / "scenes" / "cornell_box.json");
    std::map<std::string, Color> emitters;
    for (const Material& m : scene.materials)
        if (m.isEmissive()) emitters[m.name] = m.emission;
    EXPECT_EQ(emitters, (std::map<std::string, Color>{{"light", Color(17, 12, 4)}}));
    ASSERT_NE(materialNamed(scene, "light"), nullptr);
    EXPECT_EQ(materialNamed(scene, "light")->albedo, Color(0.78f));
    ASSERT_NE(materialNamed(scene, "white"), nullptr);
    EXPECT_EQ(materialNamed(scene, "white")->albedo, Color(0.725f, 0.71f, 0.68f));
    ASSERT_NE(materialNamed(scene, "red"), nullptr);
    EXPECT_EQ(materialNamed(scene, "red")->albedo, Color(0.63f, 0.065f, 0.05f));
    ASSERT_NE(materialNamed(scene, "green"), nullptr);
    EXPECT_EQ(materialNamed(scene, "green")->albedo, Color(0.14f, 0.45f, 0.091f));
    for (const Mesh& m : scene.meshes)
        for (uint32_t material : m.materials)
            EXPECT_EQ(scene.materials[material].isEmissive(), m.name == "light") << m.name;
}

TEST(CornellBox, CameraIsThePublishedOne) {
    const Scene scene = loadSceneFile(kSourceDir / "configs" / "scenes" / "cornell_box.json");
    ASSERT_TRUE(scene.camera.has_value());
    EXPECT_EQ(scene.camera->width, 256);
    EXPECT_EQ(scene.camera->height, 256);
    const CameraPose pose = scene.camera->poseAt(0.0f).relativeTo(scene.worldOrigin);
    expectVec(pose.eye, vec3(0.278f, 0.273f, -0.8f), 1e-6f, "eye");
    expectVec(glm::normalize(pose.target - pose.eye), vec3(0, 0, 1), 1e-6f, "view direction");
    // 35 mm lens over a 25 mm film.
    EXPECT_NEAR(pose.vfovDeg, 2.0 * std::atan(12.5 / 35.0) * 180.0 / kPi, 1e-4);
}

TEST(CornellBox, RecordsItsFileAndDescription) {
    const auto file = kSourceDir / "configs" / "scenes" / "cornell_box.json";
    const Scene scene = loadSceneFile(file);
    ASSERT_EQ(scene.files.size(), 1u);
    EXPECT_EQ(scene.files[0].path, file.string());
    EXPECT_EQ(scene.files[0].sha256, sha256File(file));
    EXPECT_EQ(scene.description, loadJsonFile(file));
}

// ---- Third-party scenes ---------------------------------------------------------------------------

TEST(SharedScenes, CornellBoxObjHas36TrianglesAndAKeLightFacingDown) {
    LOAD_SHARED_SCENE(scene, "cornell_box_obj.json", "cornell-box/CornellBox-Original.obj");
    EXPECT_EQ(scene.triangleCount(), 36u);
    const Material* light = materialNamed(scene, "light");
    ASSERT_NE(light, nullptr);
    EXPECT_EQ(light->emission, Color(17, 12, 4));
    int lightTriangles = 0;
    for (const Mesh& m : scene.meshes)
        for (std::size_t i = 0; i < m.indices.size(); ++i)
            if (scene.materials[m.materials[i]].isEmissive()) {
                expectVec(faceNormal(m, m.indices[i]), vec3(0, -1, 0), 1e-6f, "light normal");
                ++lightTriangles;
            }
    EXPECT_EQ(lightTriangles, 2);
    EXPECT_EQ(materialNamed(scene, "default"), nullptr) << "every face has an MTL material";
    ASSERT_EQ(scene.files.size(), 3u);  // scene, OBJ, MTL
    EXPECT_EQ(scene.files[2].path, (scenesDirectory() / "cornell-box" / "CornellBox-Original.mtl").string());
}

TEST(SharedScenes, SponzaHas66454TrianglesOfDefaultAlbedoUnderSunAndSky) {
    LOAD_SHARED_SCENE(scene, "sponza.json", "sponza-dabrovic/sponza.obj");
    EXPECT_EQ(scene.triangleCount(), 66454u);
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "default");
    EXPECT_EQ(scene.materials[0].albedo, Color(0.8f));
    for (const Mesh& m : scene.meshes) {
        EXPECT_EQ(m.normals.size(), m.positions.size()) << m.name;
        EXPECT_EQ(m.uvs.size(), m.positions.size()) << m.name;
        for (const vec3& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f) << m.name;
    }
    ASSERT_EQ(scene.suns.size(), 1u);
    expectVec(scene.suns[0].direction, glm::normalize(vec3(0.35f, -1.0f, 0.25f)), 1e-6f, "sun direction");
    EXPECT_EQ(scene.suns[0].irradiance, Color(3.0f));
    ASSERT_TRUE(scene.environment.has_value());
    EXPECT_EQ(scene.environment->radiance, Color(0.4f, 0.5f, 0.7f));
    EXPECT_EQ(scene.environment->map, nullptr);
    ASSERT_TRUE(scene.camera.has_value());
    EXPECT_EQ(scene.camera->width * 2, scene.camera->height * 3);
}

TEST(SharedScenes, LivingRoomHasItsTrianglesTexturesAndRotatedSkyWithHashesOfTheCollection) {
    LOAD_SHARED_SCENE(scene, "living_room.json", "living-room/living-room.obj");
    EXPECT_EQ(scene.triangleCount(), 139899u);
    EXPECT_EQ(scene.textures.size(), 3u);  // wood, wood5, picture8; the leaves are another OBJ
    const Material* floor = materialNamed(scene, "Floor");
    ASSERT_NE(floor, nullptr);
    ASSERT_GE(floor->albedoTexture, 0);
    EXPECT_EQ(scene.textures[floor->albedoTexture].width, 2048);
    EXPECT_EQ(scene.textures[floor->albedoTexture].height, 910);

    ASSERT_TRUE(scene.environment.has_value());
    ASSERT_NE(scene.environment->map, nullptr);
    EXPECT_EQ(scene.environment->map->width, 2048);
    EXPECT_EQ(scene.environment->map->height, 1024);
    // A right-handed quarter turn about +Y, as Mitsuba's toWorld: +X goes to -Z.
    expectVec(scene.environment->toWorld * vec3(1, 0, 0), vec3(0, 0, -1), 1e-6f, "toWorld x");
    expectVec(scene.environment->toWorld * vec3(0, 1, 0), vec3(0, 1, 0), 1e-6f, "toWorld y");

    // Every file read is one of the collection, with the hash it lists.
    std::ifstream sums(scenesDirectory() / "SHA256SUMS");
    std::map<std::string, std::string> expected;
    for (std::string line; std::getline(sums, line);)
        if (line.size() > 66) expected[(scenesDirectory() / line.substr(66)).lexically_normal().string()] = line.substr(0, 64);
    ASSERT_EQ(scene.files.size(), 7u);  // scene, OBJ, MTL, 3 textures, sky
    for (std::size_t i = 1; i < scene.files.size(); ++i) {
        ASSERT_EQ(expected.count(scene.files[i].path), 1u) << scene.files[i].path;
        EXPECT_EQ(scene.files[i].sha256, expected[scene.files[i].path]) << scene.files[i].path;
    }
}

// ---- Shapes and transforms -------------------------------------------------------------------------

TEST(SceneLoader, BoxIsScaledThenRotatedThenTranslated) {
    TempFolder folder;
    const Scene scene = loadText(folder, R"({"shapes": [{"type": "box",
        "transform": {"scale": [1, 2, 3], "rotate_deg": [0, 1, 0, 90], "translate": [10, 0, 0]}}]})");
    // A quarter turn about +Y sends the z extent (3) to x and the x extent (1) to z.
    const Bounds3 b = scene.bounds();
    expectVec(b.min, vec3(7, -2, -1), 1e-5f, "min");
    expectVec(b.max, vec3(13, 2, 1), 1e-5f, "max");
    EXPECT_EQ(scene.triangleCount(), 12u);
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "default");
    EXPECT_EQ(scene.meshes[0].name, "/shapes/0");
}

TEST(SceneLoader, MirroredShapesKeepTheirFrontFacesOutward) {
    TempFolder folder;
    const Scene scene = loadText(folder, R"({"shapes": [
        {"type": "box", "transform": {"scale": [-1, 1, 1], "translate": [5, 0, 0]}},
        {"type": "box", "transform": {"matrix": [[1, 0, 0, 0], [0, -2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}},
        {"type": "sphere", "subdivisions": 1, "transform": {"scale": [1, 1, -3]}}]})");
    const std::vector<vec3> centres = {vec3(5, 0, 0), vec3(0), vec3(0)};
    ASSERT_EQ(scene.meshes.size(), 3u);
    for (std::size_t s = 0; s < 3; ++s) {
        const Mesh& m = scene.meshes[s];
        for (const uvec3& t : m.indices) {
            const vec3 n = faceNormal(m, t);
            EXPECT_GT(glm::dot(n, centroid(m, t) - centres[s]), 0.0f) << "shape " << s;
            if (!m.normals.empty()) {
                EXPECT_GT(glm::dot(n, m.normals[t.x]), 0.5f) << "shape " << s << ": shading and face normals agree";
            }
        }
    }
}

TEST(SceneLoader, InwardSphereIsClosedAndFacesItsCentre) {
    TempFolder folder;
    const Scene scene = loadText(folder, R"({"shapes": [{"type": "sphere", "center": [1, 2, 3], "radius": 2,
        "subdivisions": 2, "inward": true}]})");
    ASSERT_EQ(scene.meshes.size(), 1u);
    const Mesh& m = scene.meshes[0];
    const vec3 centre(1, 2, 3);
    EXPECT_EQ(m.triangleCount(), 320u);
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        expectVec(m.normals[i], glm::normalize(centre - m.positions[i]), 1e-5f, "vertex " + std::to_string(i));
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const uvec3& t : m.indices) {
        EXPECT_GT(glm::dot(faceNormal(m, t), centre - centroid(m, t)), 0.0f);
        for (const auto& [a, b] : {std::make_pair(t.x, t.y), std::make_pair(t.y, t.z), std::make_pair(t.z, t.x)})
            ++edges[{std::min(a, b), std::max(a, b)}];
    }
    for (const auto& [edge, count] : edges) EXPECT_EQ(count, 2) << "edge " << edge.first << "-" << edge.second;
}

TEST(SceneLoader, QuadsTrianglesAndNamedMaterialsBuildTheGivenGeometry) {
    TempFolder folder;
    const Scene scene = loadText(folder, R"({
        "materials": {"metal": {"type": "glossy", "albedo": 0.1, "specular": 0.8, "roughness": 0.3}},
        "shapes": [
          {"type": "quad", "name": "wall", "material": "metal", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]},
          {"type": "quad", "transform": {"scale": 2}},
          {"type": "triangles", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]],
           "normals": [[0, 0, 3], [0, 0, 1], [0, 0, 1]], "uvs": [[0, 0], [1, 0], [0, 1]]}]})");
    ASSERT_EQ(scene.meshes.size(), 3u);
    EXPECT_EQ(scene.meshes[0].name, "wall");
    EXPECT_EQ(scene.meshes[0].indices, (std::vector<uvec3>{{0, 1, 2}, {0, 2, 3}}));
    const Material& metal = scene.materials[scene.meshes[0].materials[0]];
    EXPECT_EQ(metal.type, MaterialType::Glossy);
    EXPECT_EQ(metal.albedo, Color(0.1f));
    EXPECT_EQ(metal.specular, Color(0.8f));
    EXPECT_FLOAT_EQ(metal.roughness, 0.3f);
    expectVec(faceNormal(scene.meshes[1], scene.meshes[1].indices[0]), vec3(0, 1, 0), 1e-6f, "unit quad normal");
    expectVec(scene.bounds().min, vec3(-2, 0, -2), 1e-6f, "min");
    EXPECT_EQ(scene.meshes[2].normals[0], vec3(0, 0, 1));
    EXPECT_EQ(scene.meshes[2].uvs[2], vec2(0, 1));
}

// ---- Materials, textures and lights ----------------------------------------------------------------

void writePng(const std::filesystem::path& file, const std::vector<uint8_t>& rgb, int width) {
    std::filesystem::create_directories(file.parent_path());
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(width, int(rgb.size()) / (3 * width), 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb.data()));
    out->close();
}

TEST(SceneLoader, AlbedoTexturesAreLoadedOnceAndRecordedWithTheirHash) {
    TempFolder folder;
    writePng(folder.path() / "tex" / "checker.png", {255, 255, 255, 0, 0, 0}, 2);
    // map_Kd resolves against the MTL's folder, which is not the OBJ's.
    folder.write("model.mtl", "newmtl painted\nKd 0.5 0.5 0.5\nmap_Kd tex/checker.png\n");
    folder.write("obj/model.obj", "mtllib ../model.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl painted\nf 1/1 2/2 3/3\n");
    const Scene scene = loadText(folder, R"({
        "materials": {"wood": {"type": "diffuse", "albedo_texture": "tex/checker.png"}},
        "shapes": [{"type": "obj", "file": "obj/model.obj"}]})");
    ASSERT_EQ(scene.textures.size(), 1u) << "the MTL and the scene share one texture";
    const Material* wood = materialNamed(scene, "wood");
    const Material* painted = materialNamed(scene, "painted");
    ASSERT_TRUE(wood && painted);
    EXPECT_EQ(wood->albedoTexture, 0);
    EXPECT_EQ(painted->albedoTexture, 0);
    expectVec(wood->albedo, Color(0.5f), 1e-6f, "albedo is the texture's mean");
    std::vector<std::string> paths;
    for (const SceneFile& f : scene.files) {
        paths.push_back(std::filesystem::path(f.path).lexically_relative(folder.path()).string());
        EXPECT_EQ(f.sha256, sha256File(f.path)) << f.path;
    }
    EXPECT_EQ(paths, (std::vector<std::string>{"scene.json", "tex/checker.png", "obj/model.obj", "model.mtl"}));
}

TEST(SceneLoader, InlineSceneResolvesPathsAgainstItsConfigFolder) {
    TempFolder folder;
    folder.write("scenes/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    Params block(Json::parse(R"({"default_albedo": [0.1, 0.2, 0.3], "shapes": [{"type": "obj", "file": "scenes/tri.obj"}]})"),
                 (folder.path() / "run.json").string(), "/scene", "scene", nullptr);
    const Scene scene = loadScene(block);
    EXPECT_EQ(scene.triangleCount(), 1u);
    EXPECT_EQ(scene.materials.at(0).albedo, Color(0.1f, 0.2f, 0.3f));
    ASSERT_EQ(scene.files.size(), 1u);
    EXPECT_EQ(scene.files[0].path, (folder.path() / "scenes" / "tri.obj").string());
    EXPECT_EQ(scene.description, block.json());
}

TEST(SceneLoader, ScenesVariableExpandsToTheEnvironmentOrTheSharedFolder) {
    TempFolder folder;
    const char* previous = std::getenv("GIBENCH_SCENES");
    const std::optional<std::string> saved = previous ? std::optional<std::string>(previous) : std::nullopt;
    Params p(Json{{"file", "${GIBENCH_SCENES}/a/b.obj"}}, "x/scene.json", "", "shape", &kTestPathTable);
    unsetenv("GIBENCH_SCENES");
    EXPECT_EQ(scenesDirectory(), (kSourceDir / ".." / "shared" / "scenes").lexically_normal());
    setenv("GIBENCH_SCENES", folder.path().c_str(), 1);
    EXPECT_EQ(scenesDirectory(), folder.path());
    EXPECT_EQ(readPath(p, "file"), folder.path() / "a" / "b.obj");
    if (saved)
        setenv("GIBENCH_SCENES", saved->c_str(), 1);
    else
        unsetenv("GIBENCH_SCENES");
}

TEST(SceneLoader, LightsAreReadNormalisedAndOneEnvironmentIsAllowed) {
    TempFolder folder;
    const Scene scene = loadText(folder, R"({"lights": [
        {"type": "sun", "direction": [0, -2, 0], "irradiance": [1, 2, 3]},
        {"type": "sun", "direction": [1, 0, 0], "irradiance": 0.5},
        {"type": "environment", "radiance": 1}]})");
    ASSERT_EQ(scene.suns.size(), 2u);
    EXPECT_EQ(scene.suns[0].direction, vec3(0, -1, 0));
    EXPECT_EQ(scene.suns[0].irradiance, Color(1, 2, 3));
    ASSERT_TRUE(scene.environment.has_value());
    EXPECT_EQ(scene.environment->radiance, Color(1.0f));
    EXPECT_FALSE(scene.camera.has_value());
}

// ---- Pinned error texts --------------------------------------------------------------------------

TEST(SceneLoaderErrors, EveryProblemNamesTheFileAndItsPointer) {
    TempFolder folder;
    const std::string file = (folder.path() / "scene.json").string();
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "colour": "red"}]})"),
              file + ": /shapes/0/colour: unknown key for shape \"box\" (known: type, inward, name, transform, material)");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"white": {"type": "diffuse"}, "red": {"type": "diffuse", "albedo": [0.6, 0, 0]}},
                                  "shapes": [{"type": "box"}, {"type": "box", "material": "whte"}]})"),
              file + ": /shapes/1/material: unknown material \"whte\" (defined: \"red\", \"white\")");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "obj", "file": "models/../missing.obj"}]})"),
              file + ": /shapes/0/file: cannot read OBJ \"" + (folder.path() / "missing.obj").string() + "\": No such file or directory");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"white": {"type": "diffuse", "albedo": 1.5}}})"),
              file + ": /materials/white/albedo: expected a number in [0, 1] or an array of 3 such numbers, got 1.5");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"metal": {"type": "glossy", "albedo": [0.5, 0.1, 0.1], "specular": 0.6}}})"),
              file + ": /materials/metal/specular: expected albedo + specular <= 1 in every channel, got [0.5, 0.1, 0.1] + [0.6, 0.6, 0.6]");
    EXPECT_EQ(errorOf(folder, R"({"lights": [{"type": "environment", "radiance": 1}, {"type": "environment_map", "file": "sky.exr"}]})"),
              file + ": /lights/1: expected at most one environment light (\"environment\" or \"environment_map\"); /lights/0 is one already");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"m": {"type": "glossy", "roughness": 0}}})"),
              file + ": /materials/m/roughness: expected a number in [0.01, 1], got 0");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"m": {"type": "diffuse", "albedo": 0.5, "albedo_texture": "a.png"}}})"),
              file + ": /materials/m/albedo_texture: expected either \"albedo\" or \"albedo_texture\", not both");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"m": {"type": "diffuse", "albedo_texture": "a.png"}}})"),
              file + ": /materials/m/albedo_texture: cannot read image \"" + (folder.path() / "a.png").string() +
                  "\": No such file or directory");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "obj", "file": "${GIBENCH_SCENE}/x.obj"}]})"),
              file + ": /shapes/0/file: expected a path with no variable other than a leading \"${GIBENCH_SCENES}/\", got "
                     "\"${GIBENCH_SCENE}/x.obj\"");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "quad", "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]}]})"),
              file + ": /shapes/0/vertices: expected 4 corners whose triangles 0-1-2 and 0-2-3 have non-zero area, got "
                     "[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "triangles", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 3]]}]})"),
              file + ": /shapes/0/indices: expected an array of [i, j, k] vertex indices, each in [0, 3), got [0,1,3]");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "sphere", "radius": 0}]})"),
              file + ": /shapes/0/radius: expected a number > 0, got 0");
    EXPECT_EQ(errorOf(folder, R"({"lights": [{"type": "sun", "direction": [0, 0, 0], "irradiance": 1}]})"),
              file + ": /lights/0/direction: expected a non-zero direction, got [0, 0, 0]");
    EXPECT_EQ(errorOf(folder, R"({"shape": []})"),
              file + ": /shape: unknown key for scene (known: camera, default_albedo, materials, shapes, lights)");
}

TEST(SceneLoaderErrors, MissingMapKdNamesTheMtlAndTheTexture) {
    TempFolder folder;
    folder.write("m.mtl", "newmtl painted\nKd 0.5 0.5 0.5\nmap_Kd tex/gone.png\n");
    folder.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl painted\nf 1/1 2/1 3/1\n");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "obj", "file": "m.obj"}]})"),
              (folder.path() / "m.mtl").string() + ": material \"painted\": map_Kd: cannot read image \"" +
                  (folder.path() / "tex" / "gone.png").string() + "\": No such file or directory");
}

TEST(SceneLoaderErrors, TexturedMaterialOnAMeshWithoutUvs) {
    TempFolder folder;
    writePng(folder.path() / "t.png", {10, 20, 30}, 1);
    EXPECT_EQ(errorOf(folder, R"({"materials": {"t": {"type": "diffuse", "albedo_texture": "t.png"}},
                                  "shapes": [{"type": "sphere", "material": "t"}]})"),
              (folder.path() / "scene.json").string() +
                  ": /shapes/0/material: mesh \"/shapes/0\" has no uvs for the albedo texture of material \"t\"");
}

// ---- Numbers a float cannot hold, and what they would break (issue 8) ---------------------------

TEST(SceneLoaderErrors, UvsThatDoNotFitAFloatAreRefusedAtLoad) {
    TempFolder folder;
    writePng(folder.path() / "t.png", {10, 20, 30}, 1);
    EXPECT_EQ(errorOf(folder, R"({"materials": {"t": {"type": "diffuse", "albedo_texture": "t.png"}},
        "shapes": [{"type": "triangles", "material": "t", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]],
                    "uvs": [[1e39, 0], [1, 0], [0, 1]]}]})"),
              (folder / "scene.json").string() + ": /shapes/0/uvs: expected an array of 3 [u, v] pairs, one per vertex, got "
                  "[[1e+39,0],[1,0],[0,1]] (1e+39 at [0][0] is too large for a float, whose magnitude is at most 3.4e38)");
    folder.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 1e39 0\nf 1/1 2/1 3/1\n");
    EXPECT_EQ(errorOf(folder, R"({"materials": {"t": {"type": "diffuse", "albedo_texture": "t.png"}},
        "shapes": [{"type": "obj", "file": "m.obj", "material": "t"}]})"),
              (folder / "scene.json").string() + ": /shapes/0/file: " + (folder / "m.obj").string() +
                  ":4: vt: expected a number, got \"1e39\" (too large for a float, whose magnitude is at most 3.4e38)");
}

TEST(SceneLoaderErrors, ValuesThatBecomeInfinityOrZeroAsFloatsNameTheirKey) {
    TempFolder folder;
    const std::string file = (folder.path() / "scene.json").string();
    const std::string tooLarge = " is too large for a float, whose magnitude is at most 3.4e38)";
    EXPECT_EQ(errorOf(folder, R"({"materials": {"m": {"type": "diffuse", "emission": 1e39}}})"),
              file + ": /materials/m/emission: expected a number >= 0 or an array of 3 such numbers, got 1e+39 (1e+39" + tooLarge);
    EXPECT_EQ(errorOf(folder, R"({"lights": [{"type": "sun", "direction": [0, -1, 0], "irradiance": [1, 1e39, 1]}]})"),
              file + ": /lights/0/irradiance: expected a number >= 0 or an array of 3 such numbers, got [1,1e+39,1] (1e+39" + tooLarge);
    EXPECT_EQ(errorOf(folder, R"({"lights": [{"type": "environment_map", "file": "sky.exr", "scale": 1e39}]})"),
              file + ": /lights/0/scale: expected a number >= 0, got 1e+39 (too large for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "triangles", "vertices": [[1e39, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]]}]})"),
              file + ": /shapes/0/vertices: expected an array of [x, y, z] points, got [[1e+39,0,0],[1,0,0],[0,1,0]] (1e+39 at [0][0]" +
                  tooLarge);
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "sphere", "radius": 1e39}]})"),
              file + ": /shapes/0/radius: expected a number, got 1e+39 (too large for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "sphere", "radius": 1e-46}]})"), file + ": /shapes/0/radius: expected a number > 0, got 1e-46");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"translate": [1e39, 0, 0]}}]})"),
              file + ": /shapes/0/transform/translate: expected an array of 3 numbers, got [1e+39,0,0] (1e+39" + tooLarge);
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"scale": 1e-46}}]})"),
              file + ": /shapes/0/transform/scale: expected a non-zero number or an array of 3 non-zero numbers, got 1e-46 (1e-46 is 0 as a "
                     "float)");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"scale": [1, 1e39, 1]}}]})"),
              file + ": /shapes/0/transform/scale: expected a non-zero number or an array of 3 non-zero numbers, got [1,1e+39,1] (1e+39" +
                  tooLarge);
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"matrix": [[1, 0, 0, 1e39], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}}]})"),
              file + ": /shapes/0/transform/matrix: expected 4 rows of 4 numbers with the last row [0, 0, 0, 1], got "
                     "[[1,0,0,1e+39],[0,1,0,0],[0,0,1,0],[0,0,0,1]] (1e+39" + tooLarge);
}

TEST(SceneLoaderErrors, ShapesBeyondWhatEmbreeTracesOrCollapsedToZeroAreaAreRefused) {
    TempFolder folder;
    const std::string file = (folder.path() / "scene.json").string();
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "sphere", "subdivisions": 0, "radius": 1e30}]})"),
              file + ": /shapes/0: mesh \"/shapes/0\": expected vertices within +-9.22e+17 after the transform (Embree drops geometry "
                     "beyond), got [-5.25731e+29, 8.50651e+29, 0]");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"scale": 1e30, "translate": [0, 0, 0]}}]})"),
              file + ": /shapes/0: mesh \"/shapes/0\": expected vertices within +-9.22e+17 after the transform (Embree drops geometry "
                     "beyond), got [-1e+30, 1e+30, 1e+30]");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"scale": 1e-30}}]})"),
              file + ": /shapes/0: expected a shape with triangles of non-zero area, got all 12 degenerate (zero area as floats) after "
                     "its transform");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "triangles", "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]], "indices": [[0, 1, 2]]}]})"),
              file + ": /shapes/0: expected a shape with triangles of non-zero area, got all 1 degenerate (zero area as floats) after "
                     "its transform");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "triangles", "vertices": [[0, 0, 0]], "indices": []}]})"),
              file + ": /shapes/0/indices: expected an array of [i, j, k] vertex indices, each in [0, 1), at least one, got []");
    // A tiny but normal scale keeps unit normals.
    const Scene small = loadText(folder, R"({"shapes": [{"type": "sphere", "subdivisions": 0, "transform": {"scale": [1e-15, 1, 1]}}]})");
    for (const vec3& n : small.meshes.at(0).normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
}

TEST(SceneLoader, SceneFarFromTheOriginIsStoredRelativeToAWorldOriginNearIt) {
    TempFolder folder;
    // A box 1e7 units out and a sphere whose centre float would round to a metre there.
    const Scene scene = loadText(folder, R"({"shapes": [{"type": "box", "transform": {"translate": [1e7, -2e7, 3e7]}},
        {"type": "sphere", "center": [10000001.25, -2e7, 3e7], "radius": 0.25, "subdivisions": 1}],
        "camera": {"eye": [10000010, -2e7, 30000000], "target": [1e7, -2e7, 3e7]}})");
    EXPECT_EQ(scene.worldOrigin, glm::dvec3(1e7, -2e7, 3e7));
    for (const vec3& p : scene.meshes.at(0).positions) EXPECT_EQ(glm::abs(p), vec3(1.0f));
    for (const vec3& p : scene.meshes.at(1).positions) EXPECT_NEAR(glm::length(p - vec3(1.25f, 0, 0)), 0.25f, 1e-6f);
    const CameraPose pose = scene.camera->poseAt(0.0f).relativeTo(scene.worldOrigin);
    EXPECT_EQ(pose.eye, vec3(10, 0, 0));
    // Near the origin, the origin stays where the file has it.
    EXPECT_EQ(loadText(folder, R"({"shapes": [{"type": "box", "transform": {"translate": [3, 0, 0]}}]})").worldOrigin, glm::dvec3(0.0));
}

TEST(SceneLoaderErrors, VerticesWhoseFloatsCannotResolveTheirShapeAreRefused) {
    TempFolder folder;
    const std::string file = (folder.path() / "scene.json").string();
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "triangles", "vertices": [[1e7, 0, 0], [1e7, 1, 0], [10000001, 0, 0]], "indices": [[0, 1, 2]]}]})"),
              file + ": /shapes/0/vertices: expected vertices whose floats resolve the shape to 1/4096 of its size 1, got coordinates "
                     "up to 1e+07; give them near the origin and place the shape with \"transform\"");
    folder.write("far.obj", "v 1e6 0 0\nv 1000010 0 0\nv 1e6 10 0\nf 1 2 3\n");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "obj", "file": "far.obj"}]})"),
              file + ": /shapes/0/file: expected vertices whose floats resolve the shape to 1/4096 of its size 10, got coordinates "
                     "up to 1.00001e+06; give them near the origin and place the shape with \"transform\"");
    // The same shape near the origin, placed by its transform, loads.
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "triangles", "vertices": [[0, 0, 0], [0, 1, 0], [1, 0, 0]], "indices": [[0, 1, 2]],
        "transform": {"translate": [1e7, 0, 0]}}]})"), "");
}

TEST(SceneLoaderErrors, LightPowerThatOverflowsAFloatNamesTheEmissionKey) {
    TempFolder folder;
    const std::string file = (folder.path() / "scene.json").string();
    // Each value fits a float; emission x area does not.
    EXPECT_EQ(errorOf(folder, R"({"materials": {"lamp": {"type": "diffuse", "emission": 3e38}},
        "shapes": [{"type": "quad", "material": "lamp", "transform": {"scale": 10}}]})"),
              file + ": /materials/lamp/emission: expected an emission whose light power (pi x area x luminance) on mesh \"/shapes/0\" "
                     "fits a float, got 1.88496e+41 W on a triangle of 200 m^2");
    // A huge emitter overflows the float area even with a modest emission.
    EXPECT_EQ(errorOf(folder, R"({"materials": {"lamp": {"type": "diffuse", "emission": 1}},
        "shapes": [{"type": "quad", "material": "lamp", "transform": {"scale": 1e10}}]})"),
              file + ": /materials/lamp/emission: expected an emission whose light power (pi x area x luminance) on mesh \"/shapes/0\" "
                     "fits a float, got 6.28319e+20 W on a triangle of 2e+20 m^2");
    folder.write("lamp.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1e38 1e38 1e38\n");
    folder.write("lamp.obj", "mtllib lamp.mtl\nv 0 0 0\nv 10 0 0\nv 0 10 0\nusemtl lamp\nf 1 2 3\n");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "obj", "file": "lamp.obj"}]})"),
              (folder / "lamp.mtl").string() + ": material \"lamp\": Ke: expected an emission whose light power (pi x area x luminance) on "
                                               "mesh \"\" fits a float, got 1.5708e+40 W on a triangle of 50 m^2");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"scale": 5e17}}],
        "lights": [{"type": "sun", "direction": [0, -1, 0], "irradiance": 1e20}]})"),
              file + ": /lights/0/irradiance: expected an irradiance whose power over the scene (irradiance x 2.35619e+36 m^2, the disc "
                     "of its bounding sphere) fits a float, got 2.35619e+56 W");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "box", "transform": {"scale": 5e17}}],
        "lights": [{"type": "environment", "radiance": 1e10}]})"),
              file + ": /lights/0/radiance: expected an environment whose power over the scene (4 pi x 2.35619e+36 m^2, the disc of its "
                     "bounding sphere, x radiance) and whose map rows fit a float, got 2.96088e+47 W");
}

TEST(SceneLoaderErrors, SceneFileThatIsADirectorySaysSo) {
    TempFolder folder;
    std::filesystem::create_directories(folder / "scene.json");
    try {
        loadSceneFile(folder / "scene.json");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), (folder / "scene.json").string() + ": cannot open file: is a directory, not a file");
    }
}

TEST(SceneLoaderErrors, FileNamedInAnObjThatIsNotUtf8IsRefused) {
    // JSON strings are UTF-8, but an OBJ may name its MTL in any bytes; the scene records it.
    TempFolder folder;
    folder.write("caf\xe9.mtl", "newmtl a\nKd 0.5 0.5 0.5\n");
    folder.write("m.obj", "mtllib caf\xe9.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
    EXPECT_EQ(errorOf(folder, R"({"shapes": [{"type": "obj", "file": "m.obj"}]})"),
              (folder / "caf").string() + "\\xe9.mtl: expected a file name in UTF-8 (results record it in JSON), got byte 0xe9 at offset " +
                  std::to_string((folder / "caf").string().size()));
}

}  // namespace
}  // namespace gibench
