// Bad JSON input as loadJsonFile() and Params see it: deep nesting, numbers a float cannot hold,
// paths that are not JSON files (issue 8).

#include "core/config/params.h"

#include "core/util/error.h"
#include "support/temp_folder.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>

namespace gibench {
namespace {

const ParamTable kTable = {
    {"frames", ParamType::Int, 1, "frames", 1, 1 << 20},
    {"count", ParamType::Int, 0, "any integer"},
    {"ratio", ParamType::Float, 0.5, "a fraction", 0.0, 1.0},
    {"scale", ParamType::Float, 1.0, "any number"},
    {"albedo", ParamType::Color, 0.8, "reflectance", 0.0, kInfinity},
    {"eye", ParamType::Vec3, Json(), "position"},
};

std::string nested(int depth, const std::string& inner = "0") { return std::string(depth, '[') + inner + std::string(depth, ']'); }

std::string errorOf(const std::string& json, const std::function<void(Params&)>& read) {
    try {
        Params p(Json::parse(json), "cfg.json", "", "run config", &kTable);
        read(p);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string loadError(const std::filesystem::path& file) {
    try {
        loadJsonFile(file);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(JsonInput, ErrorAboutAValueNested100000DeepQuotesASummary) {
    // nlohmann parses and destroys this without recursion; dump() would recurse 100000 levels.
    EXPECT_EQ(errorOf(R"({"frames": )" + nested(100000) + "}", [](Params& p) { p.getInt("frames"); }),
              "cfg.json: /frames: expected an integer in [1, 1048576], got an array of 1 value nested more than 4 levels deep");
    EXPECT_EQ(errorOf(nested(100000), [](Params&) {}),
              "cfg.json: /: expected an object for run config, got an array of 1 value nested more than 4 levels deep");
}

TEST(JsonInput, ErrorQuotesAShallowValueCutTo120Characters) {
    std::string many = "[";
    for (int i = 0; i < 1000; ++i) many += (i ? ",1" : "1");
    many += "]";
    EXPECT_EQ(errorOf(R"({"frames": [[1, 2]]})", [](Params& p) { p.getInt("frames"); }),
              "cfg.json: /frames: expected an integer in [1, 1048576], got [[1,2]]");
    EXPECT_EQ(errorOf(R"({"frames": )" + many + "}", [](Params& p) { p.getInt("frames"); }),
              "cfg.json: /frames: expected an integer in [1, 1048576], got " + many.substr(0, 120) + "...");
}

TEST(JsonInput, FileNestedDeeperThan100LevelsIsRefusedWithItsPosition) {
    TempFolder folder;
    EXPECT_EQ(loadError(folder.write("deep.json", "{\n  \"frames\": " + nested(100000) + "\n}\n")),
              (folder / "deep.json").string() + ":2:112: expected arrays and objects nested at most 100 levels deep, got more");
    // The object is level 1, so 99 arrays inside it are the most allowed.
    EXPECT_EQ(loadJsonFile(folder.write("ok.json", "{\"frames\": " + nested(99) + "}"))["frames"].size(), 1u);
    // Brackets inside strings are text.
    EXPECT_EQ(loadJsonFile(folder.write("text.json", "{\"name\": \"" + nested(200) + "\"}"))["name"], nested(200));
}

TEST(JsonInput, NumbersThatDoNotFitAFloatAreErrorsNotInfinity) {
    EXPECT_EQ(errorOf(R"({"albedo": 1e39})", [](Params& p) { p.getColor("albedo"); }),
              "cfg.json: /albedo: expected a number >= 0 or an array of 3 such numbers, got 1e+39 (1e+39 is too large for a "
              "float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorOf(R"({"albedo": [1, 1e39, 0]})", [](Params& p) { p.getColor("albedo"); }),
              "cfg.json: /albedo: expected a number >= 0 or an array of 3 such numbers, got [1,1e+39,0] (1e+39 is too large "
              "for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorOf(R"({"scale": -1e39})", [](Params& p) { p.getFloat("scale"); }),
              "cfg.json: /scale: expected a number, got -1e+39 (too large for a float, whose magnitude is at most 3.4e38)");
    EXPECT_EQ(errorOf(R"({"eye": [1e39, 0, 0]})", [](Params& p) { p.getVec3("eye"); }),
              "cfg.json: /eye: expected an array of 3 numbers, got [1e+39,0,0] (1e+39 is too large for a float, whose magnitude "
              "is at most 3.4e38)");
    EXPECT_EQ(errorOf(R"({"count": 1e300})", [](Params& p) { p.getInt("count"); }),
              "cfg.json: /count: expected an integer, got 1e+300");
    Params infinite(Json{{"scale", std::numeric_limits<double>::infinity()}}, "cfg.json", "", "run config", &kTable);
    try {
        infinite.getFloat("scale");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "cfg.json: /scale: expected a number, got a number beyond the range of a double");
    }
    // The largest float and numbers that round to 0 or a subnormal are values a float holds.
    Params p(Json::parse(R"({"scale": 3.4e38, "ratio": 1e-46})"), "cfg.json", "", "run config", &kTable);
    EXPECT_EQ(p.getFloat("scale"), 3.4e38f);
    EXPECT_EQ(p.getFloat("ratio"), 0.0f);
}

TEST(JsonInput, NumberBeyondADoubleInAFileIsAnInputErrorWithItsPosition) {
    TempFolder folder;
    // nlohmann throws out_of_range, not parse_error, for this.
    EXPECT_EQ(loadError(folder.write("big.json", "{\n  \"scale\": 1e400\n}\n")),
              (folder / "big.json").string() + ":2:12: expected numbers within the range of a double, got 1e400");
}

TEST(JsonInput, DirectoryIsNamedAsOneNotAsEmptyJson) {
    TempFolder folder;
    std::filesystem::create_directories(folder / "scene.json");
    EXPECT_EQ(loadError(folder / "scene.json"), (folder / "scene.json").string() + ": cannot open file: is a directory, not a file");
    EXPECT_EQ(loadError(folder / "missing.json"), (folder / "missing.json").string() + ": cannot open file: No such file or directory");
}

TEST(JsonInput, FileNameThatIsNotUtf8IsRefusedWhenRead) {
    TempFolder folder;
    const auto file = folder.write("run\xff.json", "{}");
    EXPECT_EQ(loadError(file), (folder / "run").string() + "\\xff.json: expected a file name in UTF-8 (results record it in JSON), "
                               "got byte 0xff at offset " + std::to_string((folder / "run").string().size()));
    // Well-formed UTF-8 beyond ASCII is a fine name.
    EXPECT_EQ(loadJsonFile(folder.write("r\xc3\xa9sum\xc3\xa9.json", "{}")), Json::object());
    // Overlong forms and surrogates are not UTF-8.
    EXPECT_NE(loadError(folder.write("a\xc0\xaf.json", "{}")).find("got byte 0xc0"), std::string::npos);
    EXPECT_NE(loadError(folder.write("a\xed\xa0\x80.json", "{}")).find("got byte 0xed"), std::string::npos);
}

}  // namespace
}  // namespace gibench
