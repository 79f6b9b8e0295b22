#include "experiments/compare.h"

#include "core/image/flip.h"
#include "core/image/image.h"
#include "core/image/metrics.h"
#include "core/util/error.h"

#include "support/temp_folder.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace gibench {
namespace {

// A frame with layers total, direct (RGB) and depth (Z), values shifted by `phase`.
LayeredImage frame(int w, int h, float phase) {
    LayeredImage image(w, h);
    image.add("total", {"R", "G", "B"});
    image.add("direct", {"R", "G", "B"});
    image.add("depth", {"Z"});
    std::vector<float>& total = image.find("total")->image.data;
    std::vector<float>& direct = image.find("direct")->image.data;
    for (std::size_t k = 0; k < total.size(); ++k) {
        total[k] = 0.5f + 0.4f * std::sin(0.7f * float(k) + phase);
        direct[k] = 0.5f * total[k];
    }
    return image;
}

std::string errorOf(const std::function<void()>& run) {
    try {
        run();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Compare, FileAgainstItselfHasNoError) {
    TempFolder dir;
    const auto file = dir / "a.exr";
    writeExr(file, frame(8, 6, 0.0f));
    for (const std::string layer : {"total", "direct"}) {
        const Json r = compareImages(file, file, layer, std::nullopt);
        EXPECT_EQ(r["test"], file.string());
        EXPECT_EQ(r["reference"], file.string());
        EXPECT_EQ(r["layer"], layer);
        EXPECT_EQ(r["width"], 8);
        EXPECT_EQ(r["height"], 6);
        EXPECT_FALSE(r.contains("error_map"));
        const Json& m = r["metrics"];
        for (const char* key : {"mse", "rmse", "relmse", "smape", "mape", "mse_robust", "relmse_robust", "smape_robust", "mape_robust"})
            EXPECT_EQ(m[key], 0.0) << layer << " " << key;
        EXPECT_EQ(m["psnr"], kMaxPsnrDb) << layer;
        EXPECT_EQ(m["ssim"], 1.0) << layer;
        EXPECT_EQ(m["nonfinite_pixels"], 0) << layer;
    }
}

TEST(Compare, MetricsAreThoseOfTheChosenLayer) {
    TempFolder dir;
    const LayeredImage a = frame(8, 6, 0.0f), b = frame(8, 6, 0.3f);
    writeExr(dir / "a.exr", a);
    writeExr(dir / "b.exr", b);
    const Json r = compareImages(dir / "a.exr", dir / "b.exr", "direct", std::nullopt);
    Json expected = toJson(computeMetrics(a.find("direct")->image, b.find("direct")->image));
    expected["flip_hdr"] = flipStatistics(hdrFlip(a.find("direct")->image, b.find("direct")->image)).mean;
    EXPECT_EQ(r["metrics"], expected);
    EXPECT_EQ(r["flip"]["kind"], "hdr");
    EXPECT_EQ(r["flip"]["mean"], expected["flip_hdr"]);
}

TEST(Compare, MissingLayerNamesTheFileAndTheLayersThere) {
    TempFolder dir;
    const auto file = dir / "a.exr";
    writeExr(file, frame(4, 4, 0.0f));
    // Layers come back total first, then in OpenEXR's (alphabetical) channel order.
    EXPECT_EQ(errorOf([&] { compareImages(file, file, "albedo", std::nullopt); }),
              file.string() + ": no layer \"albedo\" (layers: total, depth, direct)");
}

TEST(Compare, LayerWithFewerThanThreeChannelsIsAnInputError) {
    TempFolder dir;
    const auto file = dir / "a.exr";
    writeExr(file, frame(4, 4, 0.0f));
    EXPECT_EQ(errorOf([&] { compareImages(file, file, "depth", std::nullopt); }),
              file.string() + ": layer \"depth\": expected at least 3 channels, got 1 (Z)");
}

TEST(Compare, SizeMismatchNamesBothFilesAndSizes) {
    TempFolder dir;
    writeExr(dir / "small.exr", frame(4, 3, 0.0f));
    writeExr(dir / "big.exr", frame(8, 6, 0.0f));
    EXPECT_EQ(errorOf([&] { compareImages(dir / "small.exr", dir / "big.exr", "total", std::nullopt); }),
              (dir / "small.exr").string() + ": expected the size of reference " + (dir / "big.exr").string() + " (8x6), got 4x3");
}

TEST(Compare, UnreadableReferenceIsNamed) {
    TempFolder dir;
    writeExr(dir / "a.exr", frame(4, 4, 0.0f));
    const std::string e = errorOf([&] { compareImages(dir / "a.exr", dir / "missing.exr", "total", std::nullopt); });
    EXPECT_EQ(e.rfind((dir / "missing.exr").string() + ": cannot read image: ", 0), 0u) << e;
}

TEST(Compare, NonFiniteInputIsRefusedNamingFileChannelPixelAndCount) {
    TempFolder dir;
    LayeredImage broken = frame(8, 6, 0.0f);
    Image& total = broken.find("total")->image;
    total.at(2, 1, 1) = std::numeric_limits<float>::quiet_NaN();
    total.at(7, 1, 0) = std::numeric_limits<float>::infinity();
    total.at(0, 5, 2) = -std::numeric_limits<float>::infinity();
    writeExr(dir / "broken.exr", broken);
    writeExr(dir / "good.exr", frame(8, 6, 0.3f));
    const std::string expected = (dir / "broken.exr").string() +
                                 ": channel G: expected finite values, got nan at pixel (2, 1) (x from the left, y from the top); "
                                 "3 values are not finite";
    EXPECT_EQ(errorOf([&] { compareImages(dir / "broken.exr", dir / "good.exr", "total", dir / "map.exr"); }), expected);
    EXPECT_EQ(errorOf([&] { compareImages(dir / "good.exr", dir / "broken.exr", "total", dir / "map.exr"); }), expected);
    EXPECT_FALSE(std::filesystem::exists(dir / "map.exr"));
}

TEST(Compare, ErrorMapOfFiniteImagesHoldsOnlyFiniteValues) {
    TempFolder dir;
    LayeredImage bright = frame(8, 6, 0.0f);
    for (float& v : bright.find("total")->image.data) v *= 1e30f;
    writeExr(dir / "bright.exr", bright);
    writeExr(dir / "dim.exr", frame(8, 6, 0.3f));
    compareImages(dir / "bright.exr", dir / "dim.exr", "total", dir / "map.exr");
    for (const Layer& layer : readLayeredImage(dir / "map.exr").layers)
        for (std::size_t k = 0; k < layer.image.data.size(); ++k)
            ASSERT_TRUE(std::isfinite(layer.image.data[k])) << layer.name << " value " << k << ": " << layer.image.data[k];
}

TEST(Compare, ErrorMapIntoAMissingFolderIsRefusedBeforeReadingNamingOptionAndPath) {
    TempFolder dir;
    const auto map = dir / "missing" / "map.exr";
    // The images do not exist either: the error map's folder is checked first.
    EXPECT_EQ(errorOf([&] { compareImages(dir / "a.exr", dir / "b.exr", "total", map); }),
              "--error-map: expected a file in an existing folder, got \"" + map.string() + "\" (no folder \"" +
                  (dir / "missing").string() + "\")");
    EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
}

TEST(Compare, AFileNameThatIsNotUtf8IsRefusedBeforeReading) {
    // The output names both files; JSON holds only UTF-8.
    TempFolder dir;
    const auto file = dir / "caf\xe9.exr";  // Latin-1 "café"
    writeExr(file, frame(4, 4, 0.0f));
    writeExr(dir / "good.exr", frame(4, 4, 0.0f));
    EXPECT_EQ(errorOf([&] { compareImages(dir / "good.exr", file, "total", std::nullopt); }),
              dir.path().string() + "/caf\\xe9.exr: expected a file name in UTF-8 (results record it in JSON), got byte 0xe9 at offset " +
                  std::to_string(file.string().size() - 5));
}

TEST(Compare, ErrorMapHoldsOneGreyLayerPerKind) {
    TempFolder dir;
    const LayeredImage a = frame(8, 6, 0.0f), b = frame(8, 6, 0.3f);
    writeExr(dir / "a.exr", a);
    writeExr(dir / "b.exr", b);
    const auto mapFile = dir / "errors.exr";
    const Json r = compareImages(dir / "a.exr", dir / "b.exr", "total", mapFile);
    EXPECT_EQ(r["error_map"], mapFile.string());

    const LayeredImage maps = readLayeredImage(mapFile);
    const std::pair<const char*, ErrorMapKind> kinds[] = {
        {"squared_error", ErrorMapKind::SquaredError}, {"relmse", ErrorMapKind::RelMse}, {"smape", ErrorMapKind::Smape}};
    EXPECT_EQ(maps.layers.size(), std::size(kinds) + 1);
    const Layer* flip = maps.find("flip");
    ASSERT_NE(flip, nullptr);
    EXPECT_EQ(flip->image.data, hdrFlip(a.find("total")->image, b.find("total")->image).data);
    for (const auto& [name, kind] : kinds) {
        const Layer* layer = maps.find(name);
        ASSERT_NE(layer, nullptr) << name;
        EXPECT_EQ(layer->channelNames, std::vector<std::string>{"Y"}) << name;
        EXPECT_EQ(layer->image.data, errorMap(a.find("total")->image, b.find("total")->image, kind).data) << name;
    }
}

// A w×h PNG of 8-bit values `byte` (every channel), written with OpenImageIO as the test wants it.
void writeBytesPng(const std::filesystem::path& file, int w, int h, unsigned char byte, const std::string& colorSpace = "") {
    std::vector<unsigned char> bytes(std::size_t(w) * h * 3, byte);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    if (!colorSpace.empty()) spec.attribute("oiio:ColorSpace", colorSpace);
    if (colorSpace == "Gamma1.8") spec.attribute("oiio:Gamma", 1.8f);
    const auto out = OIIO::ImageOutput::create("png");
    ASSERT_TRUE(out && out->open(file.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, bytes.data()) && out->close());
}

LayeredImage flatExr(int w, int h, float value) {
    LayeredImage image(w, h);
    for (float& v : image.add("total", {"R", "G", "B"}).data) v = value;
    return image;
}

TEST(Compare, PngValuesAreDecodedFromSrgb) {
    // sRGB 188/255 is ((188/255 + 0.055) / 1.055)^2.4 = 0.5029 linear, not 0.737.
    TempFolder dir;
    writeBytesPng(dir / "grey.png", 8, 8, 188);
    const double linear = std::pow((188.0 / 255.0 + 0.055) / 1.055, 2.4);
    EXPECT_NEAR(linear, 0.503, 0.001);
    writeExr(dir / "linear.exr", flatExr(8, 8, float(linear)));
    const Json mixed = compareImages(dir / "grey.png", dir / "linear.exr", "total", std::nullopt);
    EXPECT_NEAR(mixed["metrics"]["mean"].get<double>(), linear, 1e-6);
    EXPECT_NEAR(mixed["metrics"]["mse"].get<double>(), 0.0, 1e-12);
    // A mix of display and radiance files is measured as radiance.
    EXPECT_EQ(mixed["flip"]["kind"], "hdr");
    EXPECT_TRUE(mixed["metrics"].contains("flip_hdr"));
    EXPECT_LT(mixed["metrics"]["flip_hdr"].get<double>(), 1e-3);
}

TEST(Compare, TwoPngsGetLdrFlip) {
    TempFolder dir;
    writeBytesPng(dir / "a.png", 8, 8, 188);
    writeBytesPng(dir / "b.png", 8, 8, 60);
    const Json r = compareImages(dir / "a.png", dir / "b.png", "total", std::nullopt);
    EXPECT_EQ(r["flip"]["kind"], "ldr");
    EXPECT_FALSE(r["metrics"].contains("flip_hdr"));
    const double expected = flipStatistics(ldrFlip(Image(8, 8, 3, float(srgbDecode(188 / 255.0))), Image(8, 8, 3, float(srgbDecode(60 / 255.0))))).mean;
    EXPECT_NEAR(r["metrics"]["flip_ldr"].get<double>(), expected, 1e-6);
    EXPECT_GT(expected, 0.3);
}

TEST(Compare, AFileInAnotherColourSpaceIsRefused) {
    TempFolder dir;
    writeBytesPng(dir / "gamma.png", 4, 4, 100, "Gamma1.8");
    writeExr(dir / "ok.exr", flatExr(4, 4, 0.5f));
    EXPECT_EQ(errorOf([&] { compareImages(dir / "ok.exr", dir / "gamma.png", "total", std::nullopt); }),
              (dir / "gamma.png").string() +
                  ": expected linear or sRGB values, got colour space \"Gamma1.8\" (oiio:ColorSpace); compare reads linear files (EXR, "
                  "HDR, float TIFF) and sRGB ones (PNG, JPEG)");
}

TEST(Compare, FailAboveParsesKnownMetricsAndRefusesTheRest) {
    const MetricLimit l = parseMetricLimit("relmse=0.01");
    EXPECT_EQ(l.metric, "relmse");
    EXPECT_EQ(l.limit, 0.01);
    EXPECT_EQ(parseMetricLimit("flip_ldr=0.05").metric, "flip_ldr");
    std::string names;
    for (const std::string& n : comparisonMetricNames()) names += (names.empty() ? "" : ", ") + n;
    for (const std::string bad : {"relmse", "relmse=", "relmse=-1", "relmse=nan", "relmse=inf", "relmse=0.1x", "relmsee=0.1", "=1"})
        EXPECT_EQ(errorOf([&] { parseMetricLimit(bad); }),
                  "--fail-above: expected METRIC=VALUE, VALUE a finite number >= 0 and METRIC one of " + names + ", got \"" + bad + "\"");
}

TEST(Compare, ExceededLimitsNameTheMetricAndTheMargin) {
    const Json comparison = {{"metrics", {{"relmse", 0.03}, {"mse", 0.001}, {"flip_hdr", 0.2}}}};
    EXPECT_EQ(exceededLimits(comparison, {{"relmse", 0.01}, {"mse", 0.01}, {"flip_hdr", 0.2}}),
              std::vector<std::string>{"relmse = 0.03 is above --fail-above relmse=0.01 by 0.02"});
    EXPECT_EQ(errorOf([&] { exceededLimits(comparison, {{"flip_ldr", 0.1}}); }),
              "--fail-above flip_ldr: this comparison has no such metric (FLIP is flip_ldr when both files are sRGB, flip_hdr otherwise)");
}

}  // namespace
}  // namespace gibench
