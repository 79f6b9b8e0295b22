#include "core/image/image.h"

#include "core/util/error.h"

#include <OpenImageIO/imageio.h>
#include "support/temp_folder.h"
#include "support/hostile_images.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <limits>
#include <utility>
#include <random>

namespace gibench {
namespace {


// Writes `pixels` with the given channel names through OpenImageIO directly, as another program would.
void writeRaw(const std::filesystem::path& file, int w, int h, const std::vector<std::string>& names, const std::vector<float>& pixels) {
    OIIO::ImageSpec spec(w, h, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    const auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close())
        << OIIO::geterror();
}

std::vector<std::string> channelNamesInFile(const std::filesystem::path& file) {
    const auto in = OIIO::ImageInput::open(file.string());
    return in ? in->spec().channelnames : std::vector<std::string>{};
}

TEST(Image, AddCreatesZeroFilledLayersThatFindReturns) {
    LayeredImage image(4, 3);
    Image& direct = image.add("direct", {"R", "G", "B"});
    EXPECT_EQ(direct.width, 4);
    EXPECT_EQ(direct.height, 3);
    EXPECT_EQ(direct.channels, 3);
    for (float v : direct.data) EXPECT_EQ(v, 0.0f);
    image.add("depth", {"Z"});
    ASSERT_NE(image.find("direct"), nullptr);
    EXPECT_EQ(image.find("depth")->channelNames, std::vector<std::string>{"Z"});
    EXPECT_EQ(image.find("albedo"), nullptr);
    EXPECT_THROW(image.add("direct", {"R"}), std::invalid_argument);
}

// The frame loop starts each frame with clearLayersKeepingMemory(): the next frame's add()s must
// get what a new image's would, zero-filled layers of the image's size whatever the last frame
// left in the memory, only without allocating it again.
TEST(Image, LayersAddedAfterAClearKeepingMemoryAreZeroFilledAndReuseIt) {
    LayeredImage image(5, 3);
    Image& total = image.add("total", {"R", "G", "B"});
    std::fill(total.data.begin(), total.data.end(), 7.0f);
    Image& depth = image.add("depth", {"Z"});
    std::fill(depth.data.begin(), depth.data.end(), -1.0f);
    const float* memory[] = {total.data.data(), depth.data.data()};

    image.clearLayersKeepingMemory();
    EXPECT_TRUE(image.layers.empty());
    EXPECT_EQ(image.find("total"), nullptr);
    Image& rgb = image.add("direct", {"R", "G", "B"});
    Image& single = image.add("coverage", {"Y"});
    Image& fresh = image.add("normal", {"X", "Y", "Z"});  // more layers than were dropped
    for (const Image* i : {&rgb, &single, &fresh}) {
        EXPECT_EQ(i->width, 5);
        EXPECT_EQ(i->height, 3);
        EXPECT_EQ(i->data.size(), std::size_t(15 * i->channels));
        EXPECT_TRUE(std::all_of(i->data.begin(), i->data.end(), [](float v) { return v == 0.0f; }));
    }
    EXPECT_EQ(single.channels, 1);
    EXPECT_TRUE(rgb.data.data() == memory[0] || rgb.data.data() == memory[1]) << "a dropped layer's memory was not reused";
    EXPECT_TRUE(single.data.data() == memory[0] || single.data.data() == memory[1]);
}

// addOverwritten() hands out a layer of the same shape in the same reused memory, only not
// cleared: the single-channel layer in the memory of a three-channel one keeps its first values.
TEST(Image, LayersAddedToBeOverwrittenReuseMemoryWithoutClearingIt) {
    LayeredImage image(5, 3);
    Image& total = image.add("total", {"R", "G", "B"});
    std::fill(total.data.begin(), total.data.end(), 7.0f);
    const float* memory = total.data.data();
    image.clearLayersKeepingMemory();
    Image& depth = image.addOverwritten("depth", {"Z"});
    EXPECT_EQ(depth.channels, 1);
    EXPECT_EQ(depth.width, 5);
    EXPECT_EQ(depth.height, 3);
    EXPECT_EQ(depth.data.size(), 15u);
    EXPECT_EQ(depth.data.data(), memory);
    EXPECT_TRUE(std::all_of(depth.data.begin(), depth.data.end(), [](float v) { return v == 7.0f; }));
    Image& fresh = image.addOverwritten("normal", {"X", "Y", "Z"});  // no memory left to reuse
    EXPECT_EQ(fresh.data.size(), 45u);
    EXPECT_THROW(image.addOverwritten("depth", {"Z"}), std::invalid_argument);
}

TEST(Image, MultiLayerExrRoundTripIsBitExact) {
    TempFolder dir;
    LayeredImage written(5, 3);
    written.add("total", {"R", "G", "B"});
    written.add("direct", {"R", "G", "B"});
    written.add("normal", {"X", "Y", "Z"});
    written.add("depth", {"Z"});
    // Values a lossy or half-float path would change: subnormals, -0, extremes, inf, NaN.
    const float specials[] = {0.1f, -0.0f, 1e-42f, 3.4e38f, -7.25f, std::numeric_limits<float>::infinity(),
                              std::numeric_limits<float>::quiet_NaN(), 1.0f / 3.0f};
    std::size_t i = 0;
    for (auto& l : written.layers)
        for (float& v : l.image.data) {
            v = specials[i % std::size(specials)] * float(1 + i % 5);
            ++i;
        }

    writeExr(dir / "frame.exr", written);
    const LayeredImage read = readLayeredImage(dir / "frame.exr");
    ASSERT_EQ(read.width, 5);
    ASSERT_EQ(read.height, 3);
    ASSERT_EQ(read.layers.size(), written.layers.size());
    for (const auto& w : written.layers) {
        const Layer* r = read.find(w.name);
        ASSERT_NE(r, nullptr) << "layer " << w.name;
        EXPECT_EQ(r->channelNames, w.channelNames) << "layer " << w.name;
        ASSERT_EQ(r->image.data.size(), w.image.data.size()) << "layer " << w.name;
        for (std::size_t k = 0; k < w.image.data.size(); ++k)
            EXPECT_EQ(std::bit_cast<std::uint32_t>(r->image.data[k]), std::bit_cast<std::uint32_t>(w.image.data[k]))
                << "layer " << w.name << " value " << k << ": wrote " << w.image.data[k] << ", read " << r->image.data[k];
    }
}

TEST(Image, TotalIsStoredAsPlainRgbAndOtherLayersAsNameDotChannel) {
    TempFolder dir;
    LayeredImage image(2, 2);
    image.add("total", {"R", "G", "B"});
    image.add("direct", {"R", "G", "B"});
    image.add("depth", {"Z"});
    writeExr(dir / "frame.exr.tmp", image);  // not a known extension: still OpenEXR

    std::vector<std::string> names = channelNamesInFile(dir / "frame.exr.tmp");
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "depth.Z", "direct.B", "direct.G", "direct.R"}));
}

TEST(Image, PlainRgbaExrReadsAsTotalWithoutAlpha) {
    TempFolder dir;
    writeRaw(dir / "rgba.exr", 2, 1, {"R", "G", "B", "A"}, {0.1f, 0.2f, 0.3f, 1.0f, 4.0f, 5.0f, 6.0f, 0.5f});
    const LayeredImage image = readLayeredImage(dir / "rgba.exr");
    ASSERT_EQ(image.layers.size(), 1u);
    EXPECT_EQ(image.layers[0].name, "total");
    EXPECT_EQ(image.layers[0].channelNames, (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_EQ(image.layers[0].image.data, (std::vector<float>{0.1f, 0.2f, 0.3f, 4.0f, 5.0f, 6.0f}));
}

TEST(Image, RgbaPngKeepsColourAsStoredNotPremultiplied) {
    TempFolder dir;
    const auto file = dir / "rgba.png";
    OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    const std::uint8_t bytes[] = {255, 102, 0, 51};
    const auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, bytes) && out->close())
        << OIIO::geterror();

    const LayeredImage image = readLayeredImage(file);
    ASSERT_NE(image.find("total"), nullptr);
    // Premultiplied by alpha 51/255 = 0.2, red would read as 51 instead of 255.
    const std::vector<float>& rgb = image.find("total")->image.data;
    ASSERT_EQ(rgb.size(), 3u);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(std::lround(rgb[c] * 255.0f), int(bytes[c])) << "channel " << c;
}

TEST(Image, SingleChannelYImageReadsAsGreyTotal) {
    TempFolder dir;
    writeRaw(dir / "grey.exr", 2, 1, {"Y"}, {0.25f, 2.0f});
    const LayeredImage image = readLayeredImage(dir / "grey.exr");
    ASSERT_EQ(image.layers.size(), 1u);
    EXPECT_EQ(image.layers[0].name, "total");
    EXPECT_EQ(image.layers[0].image.data, (std::vector<float>{0.25f, 0.25f, 0.25f, 2.0f, 2.0f, 2.0f}));
}

TEST(Image, MissingFileIsAnInputErrorStartingWithThePath) {
    TempFolder dir;
    const std::string file = (dir / "missing.exr").string();
    try {
        readLayeredImage(file);
        FAIL() << "no error for " << file;
    } catch (const InputError& e) {
        const std::string text = e.what();
        const std::string prefix = file + ": cannot read image: ";
        EXPECT_EQ(text.substr(0, prefix.size()), prefix) << text;
        EXPECT_GT(text.size(), prefix.size()) << "no reason given: " << text;
    }
}

std::string readBytes(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The InputError readLayeredImage(file) throws, and what reached standard error meanwhile.
std::pair<std::string, std::string> readError(const std::filesystem::path& file) {
    std::string message;
    ::testing::internal::CaptureStderr();
    try {
        readLayeredImage(file);
    } catch (const InputError& e) {
        message = e.what();
    } catch (const std::exception& e) {
        message = std::string("not an InputError: ") + e.what();
    }
    return {message, ::testing::internal::GetCapturedStderr()};
}

TEST(Image, HeaderClaimingMoreThanTheLimitIsAnInputErrorNamingFileAndSize) {
    TempFolder dir;
    const auto file = dir.write("huge.png", test::kHugeHeaderPng);
    const auto [message, printed] = readError(file);
    EXPECT_EQ(message, file.string() + ": cannot read image: the header claims 100000x100000 pixels of 3 channels, 30000000000 values, "
                                       "more than the 1073741824 (4 GiB of floats) gibench reads");
    EXPECT_EQ(printed, "");
}

TEST(Image, AWideOneRowImageIsReadWithMemoryForItsOwnRowsOnly) {
    // 16777218 x 1 half RGB pixels are 200 MB as floats; the image library's own conversion
    // allocated 256 rows of them, 25.8 GB, more than this 24 GB machine gives, and the read ended
    // in std::bad_alloc (an internal error). Read in the file's formats and converted here, it
    // takes 1.6 GB at its peak.
    TempFolder dir;
    const auto file = dir.write("wide.exr", test::exrClaiming(dir.path() / "base.exr", (1 << 24) + 2, 1));
    const LayeredImage image = readLayeredImage(file);
    EXPECT_EQ(image.width, (1 << 24) + 2);
    EXPECT_EQ(image.height, 1);
}

TEST(Image, CorruptPngIsAnInputErrorAndTheLibraryPrintsNothing) {
    TempFolder dir;
    writePng(dir / "good.png", Image(4, 4, 3, 0.5f));
    std::string bytes = readBytes(dir / "good.png");
    // The type of the chunk after IHDR (signature 8 bytes, IHDR 25): no chunk libpng knows.
    bytes[40] = char(bytes[40] ^ 0xff);
    const auto file = dir.write("corrupt.png", bytes);
    const auto [message, printed] = readError(file);
    const std::string prefix = file.string() + ": cannot read image: ";
    EXPECT_EQ(message.substr(0, prefix.size()), prefix) << message;
    EXPECT_GT(message.size(), prefix.size()) << "no reason given: " << message;
    EXPECT_EQ(printed, "") << "the image library printed on its own";
}

TEST(Image, TruncatedOrGarbledExrIsAnInputErrorNamingTheFile) {
    TempFolder dir;
    LayeredImage image(16, 16);
    for (float& v : image.add("total", {"R", "G", "B"}).data) v = 0.25f;
    writeExr(dir / "whole.exr", image);
    const std::string bytes = readBytes(dir / "whole.exr");
    std::string garbled = bytes;
    for (std::size_t k = garbled.size() / 2; k < garbled.size(); k += 3) garbled[k] = char(garbled[k] ^ 0xa5);
    const std::pair<std::string, std::string> broken[] = {{"header.exr", bytes.substr(0, 40)},
                                                          {"half.exr", bytes.substr(0, bytes.size() / 2)},
                                                          {"garbled.exr", garbled}};
    for (const auto& [name, content] : broken) {
        const auto file = dir.write(name, content);
        const auto [message, printed] = readError(file);
        const std::string prefix = file.string() + ": cannot read image: ";
        EXPECT_EQ(message.substr(0, prefix.size()), prefix) << name << ": " << message;
        EXPECT_GT(message.size(), prefix.size()) << name << ": no reason given";
        EXPECT_EQ(printed, "") << name;
    }
}

TEST(Image, PngHoldsExposedClampedSrgbBytes) {
    TempFolder dir;
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    Image rgb(4, 1, 3);
    const std::vector<float> values = {0.0f, 1.0f, 0.5f, 0.002f, 0.2f, nan, -3.0f, 7.0f, inf, 0.05f, 0.0031308f, 0.25f};
    rgb.data = values;
    // sRGB(v) = 12.92 v for v <= 0.0031308, else 1.055 v^(1/2.4) - 0.055; byte = floor(255 s + 0.5):
    //   0 -> 0; 1 -> 255; 0.5 -> 0.735357 * 255 = 187.52 -> 188; 0.002 -> 0.02584 * 255 = 6.59 -> 7;
    //   0.2 -> 0.484529 * 255 = 123.55 -> 124; NaN -> 0; -3 -> 0; 7 and inf clamp to 1 -> 255;
    //   0.05 -> 0.247801 * 255 = 63.19 -> 63; 0.0031308 -> 0.040450 * 255 = 10.31 -> 10;
    //   0.25 -> 0.537098 * 255 = 136.96 -> 137.
    const int expected[] = {0, 255, 188, 7, 124, 0, 0, 255, 255, 63, 10, 137};
    writePng(dir / "shot.png", rgb);
    // Exposure +1 doubles every value: 0.25 now shows as 0.5 -> 188, 0.5 as 1 -> 255.
    writePng(dir / "brighter.png.tmp", rgb, 1.0f);

    const LayeredImage shot = readLayeredImage(dir / "shot.png");
    ASSERT_NE(shot.find("total"), nullptr);
    const Image& bytes = shot.find("total")->image;
    ASSERT_EQ(bytes.data.size(), values.size());
    for (std::size_t k = 0; k < values.size(); ++k)
        EXPECT_EQ(std::lround(bytes.data[k] * 255.0f), expected[k]) << "value " << values[k];

    const LayeredImage brighterFile = readLayeredImage(dir / "brighter.png.tmp");
    ASSERT_NE(brighterFile.find("total"), nullptr);
    const Image& brighter = brighterFile.find("total")->image;
    EXPECT_EQ(std::lround(brighter.data[2] * 255.0f), 255) << "0.5 at exposure +1";
    EXPECT_EQ(std::lround(brighter.data[11] * 255.0f), 188) << "0.25 at exposure +1";
}

}  // namespace
}  // namespace gibench
