#include "core/scene/texture_io.h"

#include "core/util/error.h"
#include "support/temp_folder.h"
#include "support/hostile_images.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdint>

namespace gibench {
namespace {

template <typename T>
void writeImage(const std::filesystem::path& file, int width, int height, int channels, OIIO::TypeDesc type, const std::vector<T>& data) {
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out) << OIIO::geterror();
    OIIO::ImageSpec spec(width, height, channels, type);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // store colours as given, not divided by alpha
    ASSERT_TRUE(out->open(file.string(), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(type, data.data())) << out->geterror();
    out->close();
}

TEST(TextureIo, SrgbCurveMatchesTheStandardAtKnownPoints) {
    EXPECT_FLOAT_EQ(srgbToLinear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(1.0f), 1.0f);
    EXPECT_NEAR(srgbToLinear(0.04045f), 0.04045f / 12.92f, 1e-7f);  // the linear segment's end
    EXPECT_NEAR(srgbToLinear(0.5f), 0.2140411f, 1e-6f);
}

TEST(TextureIo, EightBitRgbaIsDecodedWithTheSrgbCurveAndLosesAlpha) {
    TempFolder folder;
    const auto file = folder.path() / "rgba.png";
    // 2x1 pixels: (128, 0, 255, alpha 77) (255, 64, 0, alpha 255).
    writeImage<uint8_t>(file, 2, 1, 4, OIIO::TypeDesc::UINT8, {128, 0, 255, 77, 255, 64, 0, 255});
    const Texture t = loadTexture(file);
    ASSERT_EQ(t.width, 2);
    ASSERT_EQ(t.height, 1);
    ASSERT_EQ(t.texels.size(), 2u);
    EXPECT_NEAR(t.texels[0].x, srgbToLinear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(t.texels[0].y, 0.0f, 1e-6f);
    EXPECT_NEAR(t.texels[0].z, 1.0f, 1e-6f);
    EXPECT_NEAR(t.texels[1].y, srgbToLinear(64.0f / 255.0f), 1e-6f);
}

TEST(TextureIo, GreyBecomesRgbAndRowsStartAtTheTop) {
    TempFolder folder;
    const auto file = folder.path() / "grey.png";
    writeImage<uint8_t>(file, 1, 2, 1, OIIO::TypeDesc::UINT8, {255, 128});
    const Texture t = loadTexture(file);
    ASSERT_EQ(t.texels.size(), 2u);
    EXPECT_EQ(t.texels[0], Color(1.0f));
    const float grey = srgbToLinear(128.0f / 255.0f);
    EXPECT_NEAR(t.texels[1].x, grey, 1e-6f);
    EXPECT_NEAR(t.texels[1].y, grey, 1e-6f);
    EXPECT_NEAR(t.texels[1].z, grey, 1e-6f);
}

TEST(TextureIo, FloatExrIsKeptLinear) {
    TempFolder folder;
    const auto file = folder.path() / "radiance.exr";
    writeImage<float>(file, 1, 1, 3, OIIO::TypeDesc::FLOAT, {0.5f, 2.0f, 17.0f});
    const Texture t = loadTexture(file);
    ASSERT_EQ(t.texels.size(), 1u);
    EXPECT_EQ(t.texels[0], Color(0.5f, 2.0f, 17.0f));
}

TEST(TextureIo, MissingFileNamesItAndTheReason) {
    TempFolder folder;
    const auto file = folder.path() / "missing.png";
    try {
        loadTexture(file);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot read image \"" + file.string() + "\": No such file or directory");
    }
}

TEST(TextureIo, DirectoryIsNamedAsOne) {
    TempFolder folder;
    const auto dir = folder.path() / "albedo.png";
    std::filesystem::create_directories(dir);
    try {
        loadTexture(dir);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "cannot read image \"" + dir.string() + "\": is a directory, not a file");
    }
}

// A 68-byte PNG whose header claims 100000 × 100000 RGB pixels: refused naming the file before
// 30 GB of texels are allocated (this was std::bad_alloc, an internal error).
TEST(TextureIo, AHeaderClaimingMoreThanTheImageLimitIsAnInputErrorNamingTheFile) {
    TempFolder folder;
    const auto file = folder.write("huge.png", test::kHugeHeaderPng);
    std::string message;
    try {
        loadTexture(file);
    } catch (const InputError& e) {
        message = e.what();
    } catch (const std::exception& e) {
        message = std::string("not an InputError: ") + e.what();
    }
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("the header claims 100000x100000 pixels of 3 channels, more than the 1073741824 values"), std::string::npos)
        << message;
}

}  // namespace
}  // namespace gibench
