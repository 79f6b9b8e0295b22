#include "core/config/params.h"

#include "core/util/error.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <stdexcept>

namespace gibench {
namespace {

const ParamTable kTable = {
    {"spp", ParamType::Int, 16, "samples per pixel", 1, 1 << 20},
    {"ratio", ParamType::Float, 0.5, "a fraction", 0.0, 1.0},
    {"albedo", ParamType::Color, 0.8, "reflectance", 0.0, 1.0},
    {"mode", ParamType::String, "fast", "how", -INFINITY, INFINITY, {"fast", "slow"}},
    {"eye", ParamType::Vec3, nullptr, "position"},
};

std::string errorOf(const Json& block, const std::function<void(Params&)>& read) {
    try {
        Params p(block, "cfg.json", "/method", "method \"demo\"", &kTable);
        read(p);
        p.finish();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Params, DefaultsFillMissingKeysAndResolvedListsThem) {
    Params p(Json{{"eye", {1, 2, 3}}}, "cfg.json", "/method", "method \"demo\"", &kTable);
    EXPECT_EQ(p.getInt("spp"), 16);
    EXPECT_FLOAT_EQ(p.getFloat("ratio"), 0.5f);
    EXPECT_EQ(p.getColor("albedo"), Color(0.8f));
    EXPECT_EQ(p.getVec3("eye"), vec3(1, 2, 3));
    p.finish();
    const Json r = p.resolved();
    EXPECT_EQ(r["spp"], 16);
    EXPECT_EQ(r["mode"], "fast");
    EXPECT_EQ(r["eye"], Json({1, 2, 3}));
}

TEST(Params, UnknownKeyNamesFilePointerAndKnownKeys) {
    const std::string e = errorOf(Json{{"eye", {0, 0, 0}}, {"sp", 4}}, [](Params& p) {
        p.getInt("spp");
        p.getVec3("eye");
    });
    EXPECT_EQ(e, "cfg.json: /method/sp: unknown key for method \"demo\" (known: spp, ratio, albedo, mode, eye)");
}

TEST(Params, EveryUnknownKeyIsListedAtOnce) {
    const std::string e = errorOf(Json{{"a", 1}, {"b", 2}}, [](Params&) {});
    EXPECT_NE(e.find("/method/a: unknown key"), std::string::npos);
    EXPECT_NE(e.find("\ncfg.json: /method/b: unknown key"), std::string::npos);
}

TEST(Params, WrongTypeAndRangeAreErrorsNotClamps) {
    EXPECT_EQ(errorOf(Json{{"spp", "64"}}, [](Params& p) { p.getInt("spp"); }),
              "cfg.json: /method/spp: expected an integer in [1, 1048576], got \"64\"");
    EXPECT_EQ(errorOf(Json{{"spp", -3}}, [](Params& p) { p.getInt("spp"); }),
              "cfg.json: /method/spp: expected an integer in [1, 1048576], got -3");
    EXPECT_EQ(errorOf(Json{{"ratio", 1.5}}, [](Params& p) { p.getFloat("ratio"); }),
              "cfg.json: /method/ratio: expected a number in [0, 1], got 1.5");
    EXPECT_EQ(errorOf(Json{{"mode", "medium"}}, [](Params& p) { p.getString("mode"); }),
              "cfg.json: /method/mode: expected one of \"fast\", \"slow\", got \"medium\"");
    EXPECT_EQ(errorOf(Json{{"albedo", {1, 2}}}, [](Params& p) { p.getColor("albedo"); }),
              "cfg.json: /method/albedo: expected a number in [0, 1] or an array of 3 such numbers, got [1,2]");
}

TEST(Params, MissingRequiredKeyIsNamed) {
    EXPECT_EQ(errorOf(Json::object(), [](Params& p) { p.getVec3("eye"); }),
              "cfg.json: /method: missing key \"eye\" for method \"demo\"");
}

TEST(Params, ResolvedConfigurationReadsBackToTheSameValues) {
    Params p(Json{{"spp", 7}, {"eye", {1, 0, 0}}, {"mode", "slow"}}, "a.json", "", "demo", &kTable);
    p.getInt("spp");
    Params q(p.resolved(), "b.json", "", "demo", &kTable);
    EXPECT_EQ(q.getInt("spp"), 7);
    EXPECT_EQ(q.getString("mode"), "slow");
    EXPECT_FLOAT_EQ(q.getFloat("ratio"), 0.5f);
    EXPECT_EQ(q.getVec3("eye"), vec3(1, 0, 0));
}

TEST(Params, GetEnumMapsEveryChoiceOfTheRowToItsValue) {
    enum class Mode { Fast, Slow };
    const EnumChoices<Mode> choices = {{"fast", Mode::Fast}, {"slow", Mode::Slow}};
    const ParamTable table = {{"mode", ParamType::String, "fast", "how", -INFINITY, INFINITY, choiceNames(choices)}};
    EXPECT_EQ(table[0].choices, (std::vector<std::string>{"fast", "slow"}));
    for (const auto& [name, value] : choices) {
        Params p(Json{{"mode", name}}, "cfg.json", "/method", "demo", &table);
        EXPECT_EQ(p.getEnum("mode", choices), value) << name;
    }
    Params bad(Json{{"mode", "medium"}}, "cfg.json", "/method", "demo", &table);
    try {
        bad.getEnum("mode", choices);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "cfg.json: /method/mode: expected one of \"fast\", \"slow\", got \"medium\"");
    }
}

TEST(Params, JoinedTablesKeepBothInOrderAndRejectARepeatedKey) {
    const ParamTable extra = {{"depth", ParamType::Int, 3, "depth", 0, 10}};
    const ParamTable joined = joinTables(kTable, extra, "demo");
    ASSERT_EQ(joined.size(), kTable.size() + 1);
    EXPECT_EQ(joined.front().name, "spp");
    EXPECT_EQ(joined.back().name, "depth");
    try {
        joinTables(kTable, {{"ratio", ParamType::Float, 0.1, "again"}}, "pipeline and store \"x\"");
        FAIL() << "expected a logic_error";
    } catch (const std::logic_error& e) {
        EXPECT_EQ(std::string(e.what()), "pipeline and store \"x\": two parameter tables declare key \"ratio\"");
    }
}

TEST(Params, JsonSyntaxErrorGivesLineAndColumn) {
    const auto file = std::filesystem::temp_directory_path() / "gibench_params_bad.json";
    {
        std::ofstream out(file);
        out << "{\n  \"a\": 1,\n  \"b\": ,\n}\n";
    }
    try {
        loadJsonFile(file);
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(file.string() + ":3:", 0), 0u) << e.what();
    }
    std::filesystem::remove(file);
}

}  // namespace
}  // namespace gibench
