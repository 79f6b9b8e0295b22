#include "experiments/reference.h"

#include "support/temp_folder.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

RunConfig configWithReference(const TempFolder& dir, const std::string& name, const Json& reference) {
    const Json config = {{"experiment", "ref"},
                         {"scene", std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"},
                         {"camera", {{"resolution", {8, 8}}}},
                         {"method", {{"name", "path_traced"}}},
                         {"reference", reference},
                         {"output", {{"root", (dir / "results").string()}}}};
    return loadRunConfig(dir.write(name, config.dump()));
}

TEST(Reference, TheSamplerIsPartOfTheKeyAndReachesThePathTracer) {
    TempFolder dir;
    const RunConfig independent = configWithReference(dir, "a.json", {{"spp", 4}, {"sampler", "independent"}});
    const RunConfig sobol = configWithReference(dir, "b.json", {{"spp", 4}});
    EXPECT_EQ(independent.reference.sampler, "independent");
    EXPECT_EQ(sobol.reference.sampler, "sobol") << "path_traced's default";
    EXPECT_NE(referenceKey(independent), referenceKey(sobol));
    EXPECT_EQ(sobol.resolved["reference"]["sampler"], "sobol");

    // The rendered references differ: the setting reaches the renderer, not only the key.
    ensureReference(independent, false, false);
    ensureReference(sobol, false, false);
    const LayeredImage a = *loadReference(independent), b = *loadReference(sobol);
    EXPECT_NE(a.find("total")->image.data, b.find("total")->image.data);
}

TEST(Reference, AnUnknownSamplerOrASamplerBesideAFileIsAnError) {
    TempFolder dir;
    try {
        configWithReference(dir, "bad.json", {{"sampler", "halton"}});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "bad.json").string() +
                                             ": /reference/sampler: expected one of \"independent\", \"sobol\", got \"halton\"");
    }
    const auto image = dir.write("ref.exr", "not read: the error comes first");
    try {
        configWithReference(dir, "file.json", {{"file", image.string()}, {"sampler", "sobol"}});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "file.json").string() + ": /reference/sampler: a reference \"file\" takes no rendering settings");
    }
}

}  // namespace
}  // namespace gibench
