#include "experiments/compare.h"

#include "core/image/image.h"
#include "core/image/metrics.h"
#include "core/util/error.h"

#include "support/temp_folder.h"

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
    EXPECT_EQ(r["metrics"], toJson(computeMetrics(a.find("direct")->image, b.find("direct")->image)));
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
    EXPECT_EQ(maps.layers.size(), std::size(kinds));
    for (const auto& [name, kind] : kinds) {
        const Layer* layer = maps.find(name);
        ASSERT_NE(layer, nullptr) << name;
        EXPECT_EQ(layer->channelNames, std::vector<std::string>{"Y"}) << name;
        EXPECT_EQ(layer->image.data, errorMap(a.find("total")->image, b.find("total")->image, kind).data) << name;
    }
}

}  // namespace
}  // namespace gibench
