// The `gibench` executable as a user meets it: exact error texts, exit codes, what lands on disk.

#include "support/gibench_cli.h"
#include "support/render_helpers.h"
#include "support/temp_folder.h"
#include "support/hostile_images.h"

#include "core/image/image.h"
#include "core/util/hash.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <limits>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace gibench {
namespace {

using test::gibench;
using test::Outcome;

std::string cornellScene() { return std::string(GIBENCH_SOURCE_DIR) + "/configs/scenes/cornell_box.json"; }

std::filesystem::path writeConfig(const std::filesystem::path& dir, const std::string& name, const Json& config) {
    const std::filesystem::path file = dir / name;
    std::ofstream(file) << config.dump(2);
    return file;
}

Json smallRun(const std::filesystem::path& results) {
    return {{"experiment", "cli"},
            {"scene", cornellScene()},
            {"camera", {{"resolution", {16, 16}}}},
            {"method", {{"name", "path_traced"}, {"spp", 4}}},
            {"output", {{"root", results.string()}}}};
}

std::string readFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(Cli, MisspeltKeyIsAnErrorNamingFilePointerAndKnownKeys) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["method"]["spp_"] = 4;
    const auto file = writeConfig(dir.path(), "bad.json", config);
    const Outcome o = gibench("run " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + file.string() +
                            ": /method/spp_: unknown key for method \"path_traced\" (known: spp, max_depth, rr_depth, accumulate, sampler)\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, WrongTypeIsAnErrorWithTheExpectedType) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["method"]["spp"] = "4";
    const auto file = writeConfig(dir.path(), "bad.json", config);
    const Outcome o = gibench("run " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + file.string() + ": /method/spp: expected an integer in [1, 16777216], got \"4\"\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, MissingObjIsAnErrorNamingTheShapeAndThePath) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["scene"] = {{"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}}}, {"shapes", {{{"type", "obj"}, {"file", "missing.obj"}}}}};
    const auto file = writeConfig(dir.path(), "bad.json", config);
    const Outcome o = gibench("run " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + file.string() + ": /scene/shapes/0/file: cannot read OBJ \"" + (dir.path() / "missing.obj").string() +
                            "\": No such file or directory\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, UnknownMethodListsTheRegisteredOnes) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["method"] = {{"name", "path_tracer"}};
    const auto file = writeConfig(dir.path(), "bad.json", config);
    const Outcome o = gibench("run " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output.rfind("error: " + file.string() + ": /method/name: expected one of \"path_traced\"", 0), 0u) << o.output;
}

TEST(Cli, RunWritesACompleteResultFolder) {
    TempFolder dir;
    const auto file = writeConfig(dir.path(), "small.json", smallRun(dir.path() / "results"));
    const Outcome o = gibench("run --quiet " + file.string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const auto run = dir.path() / "results" / "cli" / "small";
    for (const char* f : {"manifest.json", "metrics.json", "frames.jsonl", "image.exr", "image.png"})
        EXPECT_TRUE(std::filesystem::exists(run / f)) << f;
    const Json manifest = Json::parse(readFile(run / "manifest.json"));
    EXPECT_EQ(manifest["config"]["method"]["max_depth"], 1024);  // defaults are filled in
    EXPECT_EQ(manifest["config"]["camera"]["resolution"], Json({16, 16}));
    EXPECT_EQ(manifest["scene"]["files"][0]["sha256"].get<std::string>().size(), 64u);
    EXPECT_TRUE(manifest["timings"]["stages_seconds"].contains("path_trace"));
    // Nothing else is left in the experiment folder: no staging leftovers.
    int entries = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path() / "results" / "cli")) ++entries;
    EXPECT_EQ(entries, 1);
}

TEST(Cli, OneAndTwoThreadsWriteBitIdenticalImages) {
    TempFolder dir;
    const auto file = writeConfig(dir.path(), "det.json", smallRun(dir.path() / "results"));
    ASSERT_EQ(gibench("run --quiet --threads 1 --results " + (dir.path() / "one").string() + " " + file.string()).exitCode, 0);
    ASSERT_EQ(gibench("run --quiet --threads 2 --results " + (dir.path() / "two").string() + " " + file.string()).exitCode, 0);
    const std::string a = readFile(dir.path() / "one" / "cli" / "det" / "image.exr");
    const std::string b = readFile(dir.path() / "two" / "cli" / "det" / "image.exr");
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "EXR files differ between 1 and 2 threads";
}

TEST(Cli, RunsFindTheirReferenceAndCompareGivesZeroOnIdenticalImages) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["reference"] = {{"spp", 16}};
    const auto file = writeConfig(dir.path(), "ref.json", config);
    const Outcome rendered = gibench("reference --quiet " + file.string());
    ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
    EXPECT_EQ(rendered.output.rfind("rendered ", 0), 0u) << rendered.output;
    EXPECT_EQ(gibench("reference --quiet " + file.string()).output.rfind("reference up to date: ", 0), 0u);

    ASSERT_EQ(gibench("run --quiet " + file.string()).exitCode, 0);
    const Json metrics = Json::parse(readFile(dir.path() / "results" / "cli" / "ref" / "metrics.json"));
    ASSERT_TRUE(metrics["reference"]["found"].get<bool>());
    const double relmse = metrics["error"]["total"]["relmse"];
    EXPECT_GT(relmse, 0.0);  // 4 spp against an independent 16 spp image
    EXPECT_TRUE(std::isfinite(relmse));
    EXPECT_EQ(metrics["error"]["indirect"]["nonfinite_pixels"], 0);

    const std::string image = (dir.path() / "results" / "cli" / "ref" / "image.exr").string();
    const Outcome same = gibench("compare " + image + " " + image);
    ASSERT_EQ(same.exitCode, 0) << same.output;
    const Json zero = Json::parse(same.output);
    EXPECT_EQ(zero["metrics"]["mse"], 0.0);
    EXPECT_EQ(zero["metrics"]["relmse"], 0.0);
    EXPECT_EQ(zero["metrics"]["ssim"], 1.0);
}

TEST(Cli, AnExternalReferenceIsComparedOnEveryLayerItHasAndRecordedByItsHash) {
    // A run of the same config is its own perfect reference: every layer's error is exactly 0.
    TempFolder dir;
    const auto first = writeConfig(dir.path(), "first.json", smallRun(dir.path() / "results"));
    ASSERT_EQ(gibench("run --quiet " + first.string()).exitCode, 0);
    const std::filesystem::path image = dir.path() / "results" / "cli" / "first" / "image.exr";
    Json config = smallRun(dir.path() / "results");
    config["reference"] = {{"file", image.string()}};
    const auto second = writeConfig(dir.path(), "second.json", config);
    const Outcome o = gibench("run --quiet " + second.string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const Json metrics = Json::parse(readFile(dir.path() / "results" / "cli" / "second" / "metrics.json"));
    for (const char* layer : {"total", "direct", "indirect", "albedo", "normal"}) {
        ASSERT_TRUE(metrics["error"].contains(layer)) << layer << " " << metrics.dump();
        EXPECT_EQ(metrics["error"][layer]["mse"], 0.0) << layer;
    }
    EXPECT_FALSE(metrics["error"].contains("variance"));
    const Json manifest = Json::parse(readFile(dir.path() / "results" / "cli" / "second" / "manifest.json"));
    EXPECT_EQ(manifest["reference"]["sha256"], sha256File(image));
}

TEST(Cli, AnExternalReferenceOfAnotherSizeOrMissingIsAnErrorNamingIt) {
    TempFolder dir;
    Json small = smallRun(dir.path() / "results");
    small["camera"]["resolution"] = {8, 4};
    ASSERT_EQ(gibench("run --quiet " + writeConfig(dir.path(), "small.json", small).string()).exitCode, 0);
    const std::filesystem::path image = dir.path() / "results" / "cli" / "small" / "image.exr";

    Json config = smallRun(dir.path() / "results");
    config["reference"] = {{"file", image.string()}};
    const Outcome sized = gibench("run --quiet " + writeConfig(dir.path(), "sized.json", config).string());
    EXPECT_EQ(sized.exitCode, 2);
    EXPECT_EQ(sized.output, "error: " + image.string() + ": reference is 8x4, the run renders 16x16\n");

    config["reference"] = {{"file", (dir.path() / "nothing.exr").string()}};
    const auto missingConfig = writeConfig(dir.path(), "missing.json", config);
    const Outcome missing = gibench("run --quiet " + missingConfig.string());
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_EQ(missing.output, "error: " + missingConfig.string() + ": /reference/file: reference image \"" + (dir.path() / "nothing.exr").string() +
                                 "\" does not exist\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results" / "cli" / "missing"));
}

// Every entry under `folder`, recursively, as paths relative to it.
std::vector<std::string> everything(const std::filesystem::path& folder) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::recursive_directory_iterator(folder))
        names.push_back(std::filesystem::relative(e.path(), folder).string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(Cli, AnImageHeaderClaimingTooManyPixelsIsAnErrorNamingFileAndSize) {
    TempFolder dir;
    const auto file = dir.write("huge.png", test::kHugeHeaderPng);
    const Outcome o = gibench("compare " + file.string() + " " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + file.string() +
                            ": cannot read image: the header claims 100000x100000 pixels of 3 channels, 30000000000 values, more than the "
                            "1073741824 (4 GiB of floats) gibench reads\n");
}

TEST(Cli, ACorruptPngPrintsOnlyGibenchsMessage) {
    TempFolder dir;
    writePng(dir / "good.png", Image(4, 4, 3, 0.5f));
    std::string bytes = readFile(dir / "good.png");
    bytes[40] = char(bytes[40] ^ 0xff);  // the type of the chunk after IHDR
    const auto file = dir.write("corrupt.png", bytes);
    const Outcome o = gibench("compare " + file.string() + " " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    const std::string prefix = "error: " + file.string() + ": cannot read image: ";
    EXPECT_EQ(o.output.substr(0, prefix.size()), prefix) << o.output;
    EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
}

TEST(Cli, AnOverlongRunNameIsAnErrorSayingWhatIsAllowed) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    const std::string name(300, 'r');
    config["run"] = name;
    const auto file = writeConfig(dir.path(), "long.json", config);
    const Outcome o = gibench("run --quiet " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + file.string() +
                            ": /run: expected a folder name of 1 to 200 ASCII letters, digits, '_', '-' or '.', not starting with '.', got \"" +
                            name + "\" (300 bytes)\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, AnOutputRootUnderARegularFileIsAnErrorNamingKeyAndPath) {
    TempFolder dir;
    const auto blocker = dir.write("file", "not a folder");
    const auto file = writeConfig(dir.path(), "small.json", smallRun(blocker / "results"));
    const Outcome o = gibench("run --quiet " + file.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + file.string() + ": /output/root: expected a folder gibench can create or write into, got \"" +
                            (blocker / "results").string() + "\" (\"" + blocker.string() + "\" is a file, not a folder)\n");

    const Outcome option = gibench("run --quiet --results " + (blocker / "elsewhere").string() + " " + file.string());
    EXPECT_EQ(option.exitCode, 2);
    EXPECT_EQ(option.output, "error: --results: expected a folder gibench can create or write into, got \"" +
                                 (blocker / "elsewhere").string() + "\" (\"" + blocker.string() + "\" is a file, not a folder)\n");
    EXPECT_EQ(everything(dir.path()), (std::vector<std::string>{"file", "small.json"}));
}

TEST(Cli, AnErrorMapIntoAMissingFolderIsAnErrorNamingTheOption) {
    TempFolder dir;
    const auto file = writeConfig(dir.path(), "small.json", smallRun(dir.path() / "results"));
    ASSERT_EQ(gibench("run --quiet " + file.string()).exitCode, 0);
    const std::string image = (dir.path() / "results" / "cli" / "small" / "image.exr").string();
    const auto map = dir.path() / "missing" / "map.exr";
    const Outcome o = gibench("compare --error-map " + map.string() + " " + image + " " + image);
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: --error-map: expected a file in an existing folder, got \"" + map.string() + "\" (no folder \"" +
                            (dir.path() / "missing").string() + "\")\n");
}

TEST(Cli, AResultsFolderThatIsNotUtf8IsRefusedBeforeRenderingAndLeavesNothing) {
    // The manifest records the results root; JSON holds only UTF-8.
    TempFolder dir;
    const std::string root = (dir.path() / "caf\xe9").string();  // Latin-1 "café"
    Json config = smallRun(dir.path() / "unused");
    config["reference"] = {{"spp", 4}};
    const auto file = writeConfig(dir.path(), "small.json", config);
    const std::string expected = "error: --results: " + dir.path().string() +
                                 "/caf\\xe9: expected a file name in UTF-8 (results record it in JSON), got byte 0xe9 at offset " +
                                 std::to_string(root.size() - 1) + "\n";
    for (const std::string command : {"run", "reference"}) {
        const Outcome o = gibench(command + " --quiet --results " + root + " " + file.string());
        EXPECT_EQ(o.exitCode, 2) << command;
        EXPECT_EQ(o.output, expected) << command;
    }
    EXPECT_EQ(everything(dir.path()), std::vector<std::string>{"small.json"});
}

TEST(Cli, AConfigFileNameThatIsNotUtf8IsRefusedBeforeRenderingAndLeavesNoTemporaryReference) {
    // Issue 8: the manifest records the config's path, so such a name failed after the render,
    // and `gibench reference` left references/.tmp-<key>.exr behind.
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["reference"] = {{"spp", 4}};
    const auto file = writeConfig(dir.path(), "caf\xe9.json", config);  // Latin-1 "café"
    for (const std::string command : {"run", "reference"}) {
        const Outcome o = gibench(command + " --quiet " + file.string());
        EXPECT_EQ(o.exitCode, 2) << command;
        EXPECT_NE(o.output.find("expected a file name in UTF-8"), std::string::npos) << command << ": " << o.output;
    }
    EXPECT_EQ(everything(dir.path()), std::vector<std::string>{"caf\xe9.json"});
}

TEST(Cli, AReferenceWithNonFinitePixelsIsRefusedNamingFileChannelPixelAndCount) {
    TempFolder dir;
    LayeredImage image(16, 16);
    Image& total = image.add("total", {"R", "G", "B"});
    for (float& v : total.data) v = 0.5f;
    total.at(3, 2, 2) = std::numeric_limits<float>::quiet_NaN();
    total.at(9, 9, 0) = std::numeric_limits<float>::infinity();
    writeExr(dir.path() / "ref.exr", image);
    Json config = smallRun(dir.path() / "results");
    config["reference"] = {{"file", (dir.path() / "ref.exr").string()}};
    const Outcome o = gibench("run --quiet " + writeConfig(dir.path(), "nan.json", config).string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + (dir.path() / "ref.exr").string() +
                            ": channel B: expected finite values, got nan at pixel (3, 2) (x from the left, y from the top); 2 values are not "
                            "finite\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, AReferenceWithoutRgbChannelsIsRefusedListingTheChannelsFound) {
    TempFolder dir;
    LayeredImage image(16, 16);
    image.add("depth", {"Z"});
    image.add("normal", {"X", "Y", "Z"});
    writeExr(dir.path() / "depth.exr", image);
    Json config = smallRun(dir.path() / "results");
    config["reference"] = {{"file", (dir.path() / "depth.exr").string()}};
    const Outcome o = gibench("run --quiet " + writeConfig(dir.path(), "depth.json", config).string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_EQ(o.output, "error: " + (dir.path() / "depth.exr").string() +
                            ": expected channels R, G, B (or Y), the radiance runs are measured on, found depth.Z, normal.X, normal.Y, "
                            "normal.Z\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, ThreadsOutsideTheirRangeAreAnErrorNamingTheOption) {
    TempFolder dir;
    const auto file = writeConfig(dir.path(), "small.json", smallRun(dir.path() / "results"));
    for (const std::string threads : {"100000", "-5", "1025"}) {
        for (const std::string command : {"run", "reference"}) {
            const Outcome o = gibench(command + " --quiet --threads " + threads + " " + file.string());
            EXPECT_EQ(o.exitCode, 2) << command << " " << threads;
            EXPECT_EQ(o.output, "error: --threads: expected an integer in [0, 1024] (0 = every core), got " + threads + "\n") << command;
        }
    }
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, AnErrorInAMethodsPrepareLeavesNoFolderBehind) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["method"] = {{"name", "dense_grid"}, {"max_cells", 1}};
    const Outcome o = gibench("run --quiet " + writeConfig(dir.path(), "tiny.json", config).string());
    EXPECT_EQ(o.exitCode, 2) << o.output;
    EXPECT_NE(o.output.find("/method/max_cells: "), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results"));
}

TEST(Cli, TheNextRunCleansWhatAKilledRunLeftInItsExperimentFolder) {
    TempFolder dir;
    const pid_t child = fork();
    if (child == 0) _exit(0);
    waitpid(child, nullptr, 0);  // a PID no process has now
    const std::string tag = std::to_string(child) + "-0";
    const auto experiment = dir.path() / "results" / "cli";
    dir.write("results/cli/.staging-killed-" + tag + "/frames.jsonl", "{}\n");
    dir.write("results/cli/.old-replaced-" + tag + "/manifest.json", "{}");
    dir.write("results/cli/.staging-replaced-" + tag + "/manifest.json", "{}");
    const auto file = writeConfig(dir.path(), "small.json", smallRun(dir.path() / "results"));
    ASSERT_EQ(gibench("run --quiet " + file.string()).exitCode, 0);
    EXPECT_EQ(everything(experiment), (std::vector<std::string>{"replaced", "replaced/manifest.json", "small", "small/frames.jsonl",
                                                                "small/image.exr", "small/image.png", "small/manifest.json",
                                                                "small/metrics.json"}));
}

// --set (issue 10 item 1): the values land in the run and its manifest, typed like the file's.
TEST(Cli, SetOverridesKeysOfTheConfigAndTheManifestRecordsThem) {
    TempFolder dir;
    const auto file = writeConfig(dir.path(), "small.json", smallRun(dir.path() / "results"));
    const Outcome o = gibench("run --quiet " + file.string() + " --set method.spp=2 --set camera.resolution=[8,6] --set run=overridden" +
                              " --set method.sampler=independent");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const auto run = dir.path() / "results" / "cli" / "overridden";
    const Json manifest = Json::parse(readFile(run / "manifest.json"));
    EXPECT_EQ(manifest["config"]["method"]["spp"], 2);
    EXPECT_EQ(manifest["config"]["method"]["sampler"], "independent");
    EXPECT_EQ(manifest["config"]["camera"]["resolution"], Json({8, 6}));
    EXPECT_EQ(manifest["config_overrides"],
              Json({"method.spp=2", "camera.resolution=[8,6]", "run=overridden", "method.sampler=independent"}));
    EXPECT_EQ(readLayeredImage(run / "image.exr").width, 8);
    // Without overrides the list is there, empty.
    ASSERT_EQ(gibench("run --quiet " + file.string()).exitCode, 0);
    EXPECT_EQ(Json::parse(readFile(dir.path() / "results" / "cli" / "small" / "manifest.json"))["config_overrides"], Json::array());
}

TEST(Cli, ABadOverrideIsAnErrorNamingItAndLeavesNothing) {
    TempFolder dir;
    const auto file = writeConfig(dir.path(), "small.json", smallRun(dir.path() / "results"));
    const Outcome type = gibench("run --quiet " + file.string() + " --set method.spp=many");
    EXPECT_EQ(type.exitCode, 2) << type.output;
    EXPECT_NE(type.output.find("/method/spp: "), std::string::npos) << type.output;
    EXPECT_NE(type.output.find("error: /method/spp was set on the command line: --set method.spp=many"), std::string::npos) << type.output;
    const Outcome unknown = gibench("run --quiet " + file.string() + " --set method.spp_per_pixel=4");
    EXPECT_EQ(unknown.exitCode, 2);
    EXPECT_NE(unknown.output.find("/method/spp_per_pixel: unknown key"), std::string::npos) << unknown.output;
    EXPECT_NE(unknown.output.find("--set method.spp_per_pixel=4"), std::string::npos) << unknown.output;
    const Outcome malformed = gibench("run --quiet " + file.string() + " --set method.spp");
    EXPECT_EQ(malformed.exitCode, 2);
    EXPECT_NE(malformed.output.find("error: --set \"method.spp\": expected KEY=VALUE"), std::string::npos) << malformed.output;
    const Outcome through = gibench("run --quiet " + file.string() + " --set scene.camera=1");
    EXPECT_EQ(through.exitCode, 2);
    EXPECT_NE(through.output.find("not an object"), std::string::npos) << through.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "results" / "cli")) << "no folder for a run that never started";
}

// A render-time budget stops the run after the frame that reaches it; metrics.json says so and
// records the checkpoints.
TEST(Cli, ABudgetStopsTheRunAfterTheFrameThatReachesIt) {
    TempFolder dir;
    Json config = smallRun(dir.path() / "results");
    config["frames"] = 100000;
    config["method"]["spp"] = 1;
    config["budget"] = {{"seconds", 0.05}};
    config["checkpoints"] = {{"frames", {1, 2}}, {"seconds", {0.01, 1000.0}}};
    const auto file = writeConfig(dir.path(), "budget.json", config);
    const Outcome o = gibench("run --quiet " + file.string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const auto run = dir.path() / "results" / "cli" / "budget";
    const Json metrics = Json::parse(readFile(run / "metrics.json"));
    EXPECT_EQ(metrics["stopped_by"], "budget");
    const int frames = metrics["frames"].get<int>();
    ASSERT_GT(frames, 1) << "a 16x16 frame of one path per pixel takes well under the 50 ms budget";
    EXPECT_LT(frames, 100000);
    std::ifstream records(run / "frames.jsonl");
    std::vector<Json> lines;
    for (std::string line; std::getline(records, line);) lines.push_back(Json::parse(line));
    ASSERT_EQ(int(lines.size()), frames) << "one record per rendered frame";
    EXPECT_GE(metrics["seconds"].get<double>(), 0.05);
    EXPECT_LT(lines[lines.size() - 2]["cumulative_seconds"].get<double>(), 0.05) << "the frame before the last had not reached the budget";
    EXPECT_EQ(metrics["checkpoints"]["frames"][1]["frame"], 1);
    EXPECT_TRUE(metrics["checkpoints"]["seconds"][1]["frame"].is_null()) << "1000 s were not reached";
    const Json manifest = Json::parse(readFile(run / "manifest.json"));
    EXPECT_EQ(manifest["config"]["budget"]["seconds"], 0.05);
    EXPECT_EQ(manifest["config"]["frames"], 100000) << "the most frames, as configured";
    // Without a budget the run renders its frames.
    config.erase("budget");
    config["frames"] = 3;
    config.erase("checkpoints");
    ASSERT_EQ(gibench("run --quiet " + writeConfig(dir.path(), "frames.json", config).string()).exitCode, 0);
    const Json plain = Json::parse(readFile(dir.path() / "results" / "cli" / "frames" / "metrics.json"));
    EXPECT_EQ(plain["stopped_by"], "frames");
    EXPECT_EQ(plain["frames"], 3);
    EXPECT_EQ(plain["checkpoints"]["frames"].size(), 3u) << "1, 2 and 3";
}

TEST(Cli, MethodsListsEveryParameterFromTheCode) {
    const Outcome o = gibench("methods --json");
    ASSERT_EQ(o.exitCode, 0);
    const Json methods = Json::parse(o.output);
    ASSERT_FALSE(methods.empty());
    EXPECT_EQ(methods[0]["name"], "path_traced");
    EXPECT_EQ(methods[0]["parameters"][0]["name"], "spp");
    EXPECT_EQ(methods[0]["parameters"][0]["default"], 16);
}

}  // namespace
}  // namespace gibench
