// What a new user types first (issue 10 item 9): `gibench keys` lists every config key from the
// tables that read them, `--version` names the code, a misspelt subcommand is named as such.

#include "support/gibench_cli.h"
#include "experiments/checkpoints.h"
#include "experiments/parameter_docs.h"
#include "experiments/run_config.h"
#include "experiments/slurm_backend.h"
#include "experiments/sweep.h"
#include "methods/registry.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <set>
#include <sys/wait.h>

namespace gibench {
namespace {

using test::gibench;
using test::Outcome;

TEST(Keys, EveryKeyOfEveryTableIsListedUnderItsDottedPath) {
    std::set<std::string> listed;
    for (const Json& row : parameterReferenceJson()) {
        for (const char* field : {"section", "key", "type", "default", "allowed", "meaning"}) EXPECT_TRUE(row.contains(field)) << row.dump();
        EXPECT_FALSE(row["meaning"].get<std::string>().empty()) << row.dump();
        listed.insert(row["key"].get<std::string>());
    }
    for (const ParamSpec& spec : kRunParams) EXPECT_TRUE(listed.count(spec.name)) << spec.name;
    for (const ParamSpec& spec : kSweepParams) EXPECT_TRUE(listed.count(spec.name)) << spec.name;
    for (const ParamSpec& spec : kSlurmParams) EXPECT_TRUE(listed.count("slurm." + spec.name)) << spec.name;
    for (const auto& [prefix, table] : {std::pair{"reference.", &kReferenceParams}, {"output.", &kOutputParams}, {"budget.", &kBudgetParams},
                                        {"checkpoints.", &kCheckpointParams}})
        for (const ParamSpec& spec : *table) EXPECT_TRUE(listed.count(prefix + spec.name)) << prefix << spec.name;
    EXPECT_TRUE(listed.count("camera.resolution"));
    for (const MethodInfo& method : methodRegistry())
        for (const ParamSpec& spec : method.parameters) EXPECT_TRUE(listed.count("method." + spec.name)) << method.name << "." << spec.name;
}

TEST(Keys, AKeyThatMayBeLeftOutWithoutADefaultIsNotCalledRequired) {
    bool sawReference = false;
    for (const Json& row : parameterReferenceJson())
        if (row["key"] == "reference") {
            sawReference = true;
            EXPECT_EQ(row["default"], nullptr);
        }
    EXPECT_TRUE(sawReference);
    const std::string markdown = parameterReferenceMarkdown();
    EXPECT_NE(markdown.find("| `reference` | json | none |"), std::string::npos);
    EXPECT_NE(markdown.find("| `scene` | json | required |"), std::string::npos);
}

TEST(Cli, VersionNamesTheVersionAndTheCommit) {
    const Outcome o = gibench("--version");
    EXPECT_EQ(o.exitCode, 0);
    EXPECT_EQ(o.output.rfind("gibench 0.", 0), 0u) << o.output;
    EXPECT_NE(o.output.find("(commit "), std::string::npos) << o.output;
}

TEST(Cli, AnUnknownSubcommandIsNamedWithTheKnownOnes) {
    const Outcome o = gibench("swep configs/sweeps/x.json");
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output.rfind("error: unknown subcommand \"swep\" (one of run, reference, compare, stress, sweep,", 0), 0u) << o.output;
    const Outcome none = gibench("");
    EXPECT_EQ(none.exitCode, 2);
    EXPECT_NE(none.output.find("SUBCOMMAND"), std::string::npos) << "no subcommand: the usage, with every subcommand";
    EXPECT_NE(none.output.find("keys"), std::string::npos);
}

}  // namespace
}  // namespace gibench
