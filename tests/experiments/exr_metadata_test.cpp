// The provenance every EXR of a run and every reference carries in its header (results/README.md).

#include "support/temp_folder.h"

#include "core/config/params.h"
#include "core/image/image.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace gibench {
namespace {

OIIO::ImageSpec headerOf(const std::filesystem::path& file) {
    const auto in = OIIO::ImageInput::open(file.string());
    EXPECT_TRUE(in) << file;
    return in ? in->spec() : OIIO::ImageSpec();
}

Json readJson(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return Json::parse(s.str());
}

TEST(ExrMetadata, WriterStoresStringIntAndFloatAttributesAndNoneByDefault) {
    TempFolder dir;
    LayeredImage image(2, 2);
    image.add("total", {"R", "G", "B"});
    writeExr(dir / "plain.exr", image);
    writeExr(dir / "tagged.exr", image, {{"gibench:method", "mamba"}, {"gibench:frames", 7}, {"gibench:scale", 0.25f}});
    EXPECT_EQ(headerOf(dir / "plain.exr").find_attribute("gibench:method"), nullptr);
    const OIIO::ImageSpec spec = headerOf(dir / "tagged.exr");
    EXPECT_EQ(spec.get_string_attribute("gibench:method"), "mamba");
    EXPECT_EQ(spec.get_int_attribute("gibench:frames"), 7);
    EXPECT_EQ(spec.get_float_attribute("gibench:scale"), 0.25f);
    EXPECT_EQ(readLayeredImage(dir / "tagged.exr").layers.size(), 1u);
}

TEST(ExrMetadata, RunAndReferenceImagesNameTheirMethodSamplesSeedCommitAndConfig) {
    TempFolder dir;
    const Json config = {{"experiment", "meta"},
                         {"run", "small"},
                         {"scene", std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"},
                         {"camera", {{"resolution", {8, 8}}}},
                         {"method", {{"name", "path_traced"}, {"spp", 2}}},
                         {"frames", 2},
                         {"seed", 5},
                         {"reference", {{"spp", 4}}},
                         {"output", {{"root", (dir / "results").string()}, {"image_every", 1}}}};
    std::ofstream(dir / "small.json") << config.dump();
    const std::string gibench = std::string(GIBENCH_EXE) + " ";
    ASSERT_EQ(std::system((gibench + "reference --quiet " + (dir / "small.json").string() + " >/dev/null").c_str()), 0);
    ASSERT_EQ(std::system((gibench + "run --quiet " + (dir / "small.json").string() + " >/dev/null").c_str()), 0);

    const std::filesystem::path run = dir / "results" / "meta" / "small";
    const Json manifest = readJson(run / "manifest.json");
    const OIIO::ImageSpec spec = headerOf(run / "image.exr");
    EXPECT_EQ(spec.get_string_attribute("gibench:method"), "path_traced");
    EXPECT_EQ(spec.get_int_attribute("gibench:frames"), 2);
    EXPECT_EQ(spec.get_int_attribute("gibench:spp"), 2);
    EXPECT_EQ(spec.get_string_attribute("gibench:seed"), "5");
    EXPECT_EQ(spec.get_string_attribute("gibench:commit"), manifest["gibench"]["commit"].get<std::string>());
    EXPECT_EQ(spec.get_string_attribute("gibench:run_id"), manifest["run_id"].get<std::string>());
    const OIIO::ImageSpec first = headerOf(run / "frame_0000.exr");
    EXPECT_EQ(first.get_int_attribute("gibench:frames"), 1) << "a frame's image says how many frames made it";
    EXPECT_EQ(first.get_string_attribute("gibench:run_id"), manifest["run_id"].get<std::string>());

    const std::filesystem::path reference = manifest["reference"]["image"].get<std::string>();
    const OIIO::ImageSpec ref = headerOf(reference);
    EXPECT_EQ(ref.get_string_attribute("gibench:method"), "path_traced");
    EXPECT_EQ(ref.get_int_attribute("gibench:spp"), 4);
    EXPECT_EQ(ref.get_string_attribute("gibench:reference_key"), manifest["reference"]["key"].get<std::string>());
    EXPECT_EQ(ref.get_string_attribute("gibench:commit"), manifest["gibench"]["commit"].get<std::string>());
}

}  // namespace
}  // namespace gibench
