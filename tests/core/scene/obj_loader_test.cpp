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

// ---- Input tinyobjloader reads silently wrong (issue 8) ----------------------------------------

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(ObjLoader, NonFiniteOrNonNumericCoordinatesNameTheLine) {
    TempFolder folder;
    const std::string where = "scene.json: /shapes/0/file: ";
    auto errorFor = [&](const std::string& text) { return errorOf(folder.write("m.obj", text)); };
    const std::string obj = (folder / "m.obj").string();
    EXPECT_EQ(errorFor("v 0 0 0\nv nan nan nan\nv 0 1 0\nf 1 2 3\n"), where + obj + ":2: v: expected a number, got \"nan\"");
    EXPECT_EQ(errorFor("v 0 0 0\nv 1e39 1 0\nv 0 1 0\nf 1 2 3\n"),
              where + obj + ":2: v: expected a number, got \"1e39\" (too large for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorFor("v 0 0 0\r\nv 1e400 1 0\r\nv 0 1 0\r\nf 1 2 3\r\n"),
              where + obj + ":2: v: expected a number, got \"1e400\" (too large for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorFor(kTriangle + "vt 1e39 0\nf 1/1 2/1 3/1\n"),
              where + obj + ":4: vt: expected a number, got \"1e39\" (too large for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorFor(kTriangle + "vn 0 0 inf\nf 1//1 2//1 3//1\n"), where + obj + ":4: vn: expected a number, got \"inf\"");
    EXPECT_EQ(errorFor("v 0 0\n"), where + obj + ":1: v: expected 3 numbers, got 2");
    EXPECT_EQ(errorFor("v 0x10 0 0\n"), where + obj + ":1: v: expected a number, got \"0x10\"");
}

TEST(ObjLoader, NonFiniteMtlColourNamesTheMtlLine) {
    TempFolder folder;
    folder.write("m.mtl", "newmtl a\nKd nan 0.5 0.5\n");
    const auto obj = folder.write("m.obj", "mtllib m.mtl\n" + kTriangle + "usemtl a\nf 1 2 3\n");
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: " + (folder / "m.mtl").string() + ":2: Kd: expected a number, got \"nan\"");
    folder.write("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\nKe 1e39 0 0\n");
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: " + (folder / "m.mtl").string() +
                                ":3: Ke: expected a number, got \"1e39\" (too large for a float, whose magnitude is at most 3.4e38)");
    // tinyobjloader would read "Kd 0.5" as (0.5, 0, 0), not grey.
    folder.write("m.mtl", "newmtl a\nKd 0.5\n");
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: " + (folder / "m.mtl").string() + ":2: Kd: expected 3 numbers, got 1");
}

TEST(ObjLoader, FileWithoutUsableTrianglesSaysWhy) {
    TempFolder folder;
    auto invalid = [&](const std::string& name) { return "scene.json: /shapes/0/file: invalid OBJ \"" + (folder / name).string() + "\": "; };
    EXPECT_EQ(errorOf(folder.write("empty.obj", "")), invalid("empty.obj") + "no faces");
    EXPECT_EQ(errorOf(folder.write("points.obj", kTriangle + "# no faces\n")), invalid("points.obj") + "no faces");
    EXPECT_EQ(errorOf(folder.write("flat.obj", kTriangle + "v 2 0 0\nf 1 2 4\nf 1 1 2\n")),
              invalid("flat.obj") + "all 2 triangles are degenerate (zero area)");
    EXPECT_EQ(errorOf(folder.write("garbage.obj", std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10))),
              invalid("garbage.obj") + "not a text OBJ file (byte 0x7f at offset 0)");
    EXPECT_EQ(errorOf(folder.write("nul.obj", std::string("v 0 0 0\n\0", 9))), invalid("nul.obj") + "not a text OBJ file (byte 0x00 at offset 8)");
}

TEST(ObjLoader, FaceIndexOutOfRangeNamesTheLineAndTheIndex) {
    TempFolder folder;
    const std::string prefix = "scene.json: /shapes/0/file: " + (folder / "m.obj").string();
    EXPECT_EQ(errorOf(folder.write("m.obj", kTriangle + "f -1 -2 -99\n")),
              prefix + ":4: f: index -99 of \"-99\" is out of range (3 \"v\" lines before it)");
    EXPECT_EQ(errorOf(folder.write("m.obj", kTriangle + "vt 0 0\nf 1/1 2/2 3/1\n")),
              prefix + ":5: f: index 2 is out of range (1 \"vt\" lines in the file)");
    EXPECT_EQ(errorOf(folder.write("m.obj", kTriangle + "f 1 2 3.5\n")),
              prefix + ":4: f: expected vertex indices such as 1, 1/2 or 1/2/3, got \"3.5\"");
    // The most negative index: negating it was undefined behaviour (fuzz_obj, under UBSan).
    EXPECT_EQ(errorOf(folder.write("m.obj", kTriangle + "f -9223372036854775808 1 2\n")),
              prefix + ":4: f: index -9223372036854775808 of \"-9223372036854775808\" is out of range (3 \"v\" lines before it)");
    // Relative indices within range, and a face before the vertices it names, are fine.
    EXPECT_EQ(readObj(folder.write("m.obj", kTriangle + "f -3 -2 -1\n"), "").meshes.at(0).triangleCount(), 1u);
    EXPECT_EQ(readObj(folder.write("m.obj", "f 1 2 3\n" + kTriangle), "").meshes.at(0).triangleCount(), 1u);
}

TEST(ObjLoader, MtllibMustNameAnMtlFileAndSaysWhichLineDoesNot) {
    TempFolder folder;
    const auto obj = folder.write("sub/m.obj", "mtllib ../../../../../../../../etc/passwd\n" + kTriangle + "f 1 2 3\n");
    EXPECT_EQ(errorOf(obj), "scene.json: /shapes/0/file: " + obj.string() + ":1: mtllib: expected an .mtl file, got \"/etc/passwd\"");
    std::filesystem::create_directories(folder / "dir.mtl");
    const auto dirObj = folder.write("d.obj", "mtllib dir.mtl\n" + kTriangle + "f 1 2 3\n");
    EXPECT_EQ(errorOf(dirObj), "scene.json: /shapes/0/file: cannot read MTL \"" + (folder / "dir.mtl").string() + "\" named by \"" +
                                   dirObj.string() + "\": is a directory, not a file");
}

TEST(ObjLoader, ObjThatIsADirectorySaysSo) {
    TempFolder folder;
    std::filesystem::create_directories(folder / "model.obj");
    EXPECT_EQ(errorOf(folder / "model.obj"),
              "scene.json: /shapes/0/file: cannot read OBJ \"" + (folder / "model.obj").string() + "\": is a directory, not a file");
}

}  // namespace
}  // namespace gibench
