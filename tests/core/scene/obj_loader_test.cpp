#include "core/scene/obj_loader.h"

#include "core/util/error.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

std::string errorOf(const std::filesystem::path& obj) {
    try {
        readObj(obj, "scene.json: /shapes/0/file: ");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

const char* kMtl =
    "newmtl lamp\n"
    "Kd 0.5 0.25 0.125\n"
    "Ke 17 12 4\n"
    "Ks 0.9 0.9 0.9\n"
    "map_Kd tex/lamp.png\n";

// Group "bare" comes before any usemtl and has no normals or uvs; group "lit" is a quad with
// both, one of its normals zero.
const char* kObj =
    "mtllib lamp.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 2\nvn 0 0 0\n"
    "g bare\n"
    "f 1 2 3\n"
    "g lit\n"
    "usemtl lamp\n"
    "f 1/1/1 2/2/1 3/3/2 4/4/1\n";

TEST(ObjLoader, ReadsGroupsMaterialsNormalsAndUvs) {
    TempFolder folder;
    folder.write("lamp.mtl", kMtl);
    const auto obj = folder.write("model.obj", kObj);
    const ObjModel model = readObj(obj, "");

    ASSERT_EQ(model.files.size(), 2u);
    EXPECT_EQ(model.files[0], obj);
    EXPECT_EQ(model.files[1], folder.path() / "lamp.mtl");

    ASSERT_EQ(model.materials.size(), 1u);
    const ObjMaterial& lamp = model.materials[0];
    EXPECT_EQ(lamp.name, "lamp");
    EXPECT_EQ(lamp.diffuse, Color(0.5f, 0.25f, 0.125f));
    EXPECT_EQ(lamp.emission, Color(17, 12, 4));
    EXPECT_EQ(lamp.diffuseTexture, folder.path() / "tex" / "lamp.png");
    EXPECT_EQ(lamp.mtlFile, folder.path() / "lamp.mtl");

    ASSERT_EQ(model.meshes.size(), 2u);
    const Mesh& bare = model.meshes[0];
    EXPECT_EQ(bare.name, "bare");
    EXPECT_EQ(bare.triangleCount(), 1u);
    EXPECT_TRUE(bare.normals.empty());
    EXPECT_TRUE(bare.uvs.empty());
    EXPECT_EQ(bare.materials, std::vector<uint32_t>{kNoObjMaterial});

    const Mesh& lit = model.meshes[1];
    EXPECT_EQ(lit.name, "lit");
    EXPECT_EQ(lit.triangleCount(), 2u);
    EXPECT_EQ(lit.positions.size(), 4u) << "shared corners are one vertex";
    ASSERT_EQ(lit.normals.size(), 4u);
    ASSERT_EQ(lit.uvs.size(), 4u);
    EXPECT_EQ(lit.materials, (std::vector<uint32_t>{0, 0}));
    for (std::size_t i = 0; i < lit.positions.size(); ++i) {
        // Every normal is unit length, the zero one repaired to the faces' normal.
        EXPECT_EQ(lit.normals[i], vec3(0, 0, 1)) << "vertex " << i;
        EXPECT_EQ(lit.uvs[i], vec2(lit.positions[i])) << "vertex " << i;
    }
    for (const uvec3& t : lit.indices) {
        const vec3 front = glm::cross(lit.positions[t.y] - lit.positions[t.x], lit.positions[t.z] - lit.positions[t.x]);
        EXPECT_GT(front.z, 0.0f) << "triangulation keeps the counter-clockwise winding";
    }
}

TEST(ObjLoader, MissingObjNamesItAndTheReason) {
    TempFolder folder;
    const auto obj = folder.path() / "missing.obj";
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: cannot read OBJ \"" + obj.string() + "\": No such file or directory");
}

TEST(ObjLoader, MissingMtlIsAnErrorNotADefaultMaterial) {
    TempFolder folder;
    const auto obj = folder.write("model.obj", kObj);
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: cannot read MTL \"" + (folder.path() / "lamp.mtl").string() +
                                "\" named by \"" + obj.string() + "\": No such file or directory");
}

TEST(ObjLoader, SyntaxErrorNamesTheObjAndGivesTinyobjloadersMessage) {
    TempFolder folder;
    const auto obj = folder.write("broken.obj", "v 0 0 0\nv 1 0 0\nf 0 1 2\n");
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: invalid OBJ \"" + obj.string() +
                                "\": Failed parse `f' line(e.g. zero value for face index. line 3.)");
}

TEST(ObjLoader, WarningsAreErrorsSinceDataWouldBeDropped) {
    TempFolder folder;
    folder.write("lamp.mtl", kMtl);
    const auto obj = folder.write("model.obj", "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamb\nf 1 2 3\n");
    EXPECT_EQ(errorOf(obj),
              "scene.json: /shapes/0/file: invalid OBJ \"" + obj.string() + "\": material [ 'lamb' ] not found in .mtl");
}

}  // namespace
}  // namespace gibench
