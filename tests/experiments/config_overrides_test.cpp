// `--set KEY=VALUE` (issue 10 item 1): typed, checked like the file, recorded in the manifest.

#include "experiments/config_overrides.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

namespace gibench {
namespace {

std::string errorOf(const std::string& text) {
    try {
        parseConfigOverride(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ConfigOverride, AKeyIsADottedPathAndAValueIsJsonOrElseAString) {
    const ConfigOverride spp = parseConfigOverride("method.spp=64");
    EXPECT_EQ(spp.path, (std::vector<std::string>{"method", "spp"}));
    EXPECT_EQ(spp.pointer(), "/method/spp");
    EXPECT_EQ(spp.value, Json(64));
    EXPECT_TRUE(spp.value.is_number_integer());
    EXPECT_EQ(parseConfigOverride("camera.resolution=[128,128]").value, Json({128, 128}));
    EXPECT_EQ(parseConfigOverride("method.sampler=sobol").value, Json("sobol"));
    EXPECT_EQ(parseConfigOverride("run=\"123\"").value, Json("123")) << "a string that reads as JSON, quoted";
    EXPECT_EQ(parseConfigOverride("run=123").value, Json(123));
    EXPECT_EQ(parseConfigOverride("output.png=false").value, Json(false));
    EXPECT_EQ(parseConfigOverride("method.fine_cell_size=0.25").value, Json(0.25));
    EXPECT_EQ(parseConfigOverride("scene=a=b.json").value, Json("a=b.json")) << "the first '=' ends the key";
}

TEST(ConfigOverride, MalformedTextIsAnErrorNamingSetAndWhatWasExpected) {
    EXPECT_NE(errorOf("frames").find("--set \"frames\": expected KEY=VALUE"), std::string::npos) << errorOf("frames");
    for (const char* bad : {"=1", ".frames=1", "frames.=1", "method..spp=1", "method spp=1", "méthode=1"})
        EXPECT_NE(errorOf(bad).find("expected a key of dot-separated names"), std::string::npos) << bad << ": " << errorOf(bad);
    EXPECT_NE(errorOf("frames=").find("expected a value after '='"), std::string::npos);
    EXPECT_NE(errorOf("run=\xff").find("expected UTF-8"), std::string::npos) << errorOf("run=\xff");
    EXPECT_NE(errorOf(std::string(65, 'a') + "=1").find("1 to 64"), std::string::npos);
}

TEST(ConfigOverride, OverridesCreateMissingObjectsAndRefuseToDescendIntoOtherValues) {
    Json config = {{"frames", 1}, {"method", {{"name", "path_traced"}, {"spp", 4}}}, {"scene", "s.json"}};
    applyConfigOverrides(config, {parseConfigOverride("method.spp=64"), parseConfigOverride("camera.resolution=[8,8]"),
                                  parseConfigOverride("frames=2"), parseConfigOverride("frames=3")});
    EXPECT_EQ(config["method"]["spp"], 64);
    EXPECT_EQ(config["method"]["name"], "path_traced") << "the rest of the block stays";
    EXPECT_EQ(config["camera"]["resolution"], Json({8, 8}));
    EXPECT_EQ(config["frames"], 3) << "a later override wins";
    try {
        applyConfigOverrides(config, {parseConfigOverride("scene.camera.fov=40")});
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--set \"scene.camera.fov=40\": \"scene\" holds \"s.json\", not an object"), std::string::npos)
            << e.what();
    }
}

TEST(ConfigOverride, AnErrorAboutAnOverriddenKeyNamesTheOverride) {
    const std::vector<ConfigOverride> overrides = {parseConfigOverride("method.spp=abc"), parseConfigOverride("frames=2")};
    const std::string message = withOverrideOrigins("run.json: /method/spp: expected an integer", overrides);
    EXPECT_NE(message.find("/method/spp was set on the command line: --set method.spp=abc"), std::string::npos) << message;
    EXPECT_EQ(message.find("frames=2"), std::string::npos) << "only the override the message is about";
    const std::string inside = withOverrideOrigins("run.json: /camera/resolution/0: expected a positive integer",
                                                   {parseConfigOverride("camera.resolution=[0,4]")});
    EXPECT_NE(inside.find("--set camera.resolution=[0,4]"), std::string::npos) << inside;
    EXPECT_EQ(withOverrideOrigins("run.json: /framesx: unknown key", overrides), "run.json: /framesx: unknown key")
        << "a pointer that merely starts like an overridden one is another key";
    EXPECT_EQ(withOverrideOrigins("run.json: /checkpoints/frames: expected", overrides), "run.json: /checkpoints/frames: expected")
        << "nor one that merely ends like it";
}

}  // namespace
}  // namespace gibench
