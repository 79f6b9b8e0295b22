// gibench: one executable for every experiment step.
//   gibench run CONFIG          render a config's frames, write results/<experiment>/<run>/
//                               (--set KEY=VALUE changes a key of the config: config_overrides.h)
//   gibench reference CONFIG    render (or reuse) the config's high-spp reference image
//   gibench compare A B         error metrics between two images, as JSON
//   gibench sweep FILE          every run of a sweep file (--dry-run lists and checks them, --jobs N)
//   gibench methods             every registered method and its parameters (--json, --markdown)
// Bad input prints "error: ..." lines and exits with code 2.

#include "core/config/params.h"
#include "core/util/error.h"
#include "experiments/compare.h"
#include "experiments/json_output.h"
#include "experiments/parameter_docs.h"
#include "experiments/reference.h"
#include "experiments/run.h"
#include "experiments/run_config.h"
#include "experiments/stress.h"
#include "experiments/sweep_runner.h"
#include "methods/registry.h"

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

using namespace gibench;

namespace {

void printError(const std::string& message) {
    std::istringstream lines(message);
    for (std::string line; std::getline(lines, line);) std::fprintf(stderr, "error: %s\n", line.c_str());
}

void printMethods(bool asJson) {
    Json all = Json::array();
    for (const MethodInfo& m : methodRegistry())
        all.push_back({{"name", m.name}, {"summary", m.summary}, {"parameters", describeTable(m.parameters)}});
    if (asJson) {
        std::cout << all.dump(2) << "\n";
        return;
    }
    for (const Json& m : all) {
        std::cout << m["name"].get<std::string>() << ": " << m["summary"].get<std::string>() << "\n";
        for (const Json& p : m["parameters"]) {
            std::string line = "  " + p["name"].get<std::string>() + " (" + p["type"].get<std::string>() + ", default " +
                               p["default"].dump() + "): " + p["meaning"].get<std::string>();
            if (p.contains("range")) line += " [range " + p["range"].dump() + "]";
            if (p.contains("choices")) line += " [one of " + p["choices"].dump() + "]";
            std::cout << line << "\n";
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"gibench: global-illumination caches measured against a path-traced ground truth"};
    app.require_subcommand(1);

    std::string config;
    std::optional<int> threads;
    std::optional<std::string> resultsRoot;
    bool quiet = false, force = false, asJson = false, asMarkdown = false;
    std::string imageA, imageB, layer = "total";
    std::optional<std::string> errorMap;

    CLI::App* run = app.add_subcommand("run", "render a config's frames and write its results");
    run->add_option("config", config, "run config (JSON)")->required();
    run->add_option("--threads", threads, "worker threads (default: the config's, 0 = every core)");
    run->add_option("--results", resultsRoot, "results root folder (default: the config's output.root)");
    run->add_flag("--quiet", quiet, "no progress line");
    std::vector<std::string> setTexts;
    run->add_option("--set", setTexts, "KEY=VALUE: set a config key (dotted path, JSON value), e.g. method.spp=64; repeatable");

    CLI::App* reference = app.add_subcommand("reference", "render (or reuse) the config's reference image");
    reference->add_option("config", config, "run config (JSON) with a \"reference\" block")->required();
    reference->add_option("--threads", threads, "worker threads (0 = every core)");
    reference->add_option("--results", resultsRoot, "results root folder (default: the config's output.root)");
    reference->add_flag("--force", force, "render again even when the reference exists");
    reference->add_flag("--quiet", quiet, "no progress line");
    reference->add_option("--set", setTexts, "KEY=VALUE: set a config key, as for run; repeatable");

    CLI::App* compare = app.add_subcommand("compare", "error metrics of image A against reference B, as JSON");
    compare->add_option("test", imageA, "image to measure")->required();
    compare->add_option("reference", imageB, "reference image")->required();
    compare->add_option("--layer", layer, "layer to compare (total, direct, indirect, ...)");
    compare->add_option("--error-map", errorMap, "also write per-pixel error maps to this EXR");

    std::string stressCases = defaultStressCases().string();
    std::vector<std::string> stressMethods;
    std::optional<std::string> stressJsonFile;
    CLI::App* stress = app.add_subcommand("stress", "render the stress cases by every method and print the table (exit 1 on a failure)");
    stress->add_option("--cases", stressCases, "folder of stress cases (default: configs/stress)");
    stress->add_option("--method", stressMethods, "only these methods (repeatable)");
    stress->add_option("--json", stressJsonFile, "also write the rows as JSON to this file");
    stress->add_option("--threads", threads, "worker threads (0 = every core)");
    stress->add_flag("--quiet", quiet, "no progress lines");

    std::string sweepFile;
    bool dryRun = false;
    CLI::App* sweep = app.add_subcommand("sweep", "run every point of a sweep file, resumably (exit 1 if any failed)");
    sweep->add_option("file", sweepFile, "sweep file (JSON): a base config and its axes")->required();
    sweep->add_flag("--dry-run", dryRun, "check every point and list the runs, render nothing");
    sweep->add_option("--threads", threads, "worker threads per run (default: the config's, 0 = every core)");
    sweep->add_flag("--quiet", quiet, "no progress lines within runs");
    int jobs = 1;
    std::optional<std::size_t> sweepIndex;
    sweep->add_option("--jobs", jobs, "runs at a time, each in its own process (threads per run default: cores / jobs)")->check(CLI::Range(1, 256));
    sweep->add_option("--index", sweepIndex, "run only this point (0-based, as --dry-run lists them): what a Slurm array task runs");

    CLI::App* methods = app.add_subcommand("methods", "list every method and its parameters");
    methods->add_flag("--json", asJson, "as JSON");
    methods->add_flag("--markdown", asMarkdown, "as the Markdown parameter reference (docs/parameters.md)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }

    try {
        RunOverrides overrides{threads, resultsRoot ? std::optional<std::filesystem::path>(*resultsRoot) : std::nullopt, {}};
        for (const std::string& text : setTexts) overrides.keys.push_back(parseConfigOverride(text));
        if (*run) {
            RunConfig runConfig = loadRunConfig(config, overrides);
            const RunResult result = executeRun(runConfig, !quiet);
            std::printf("wrote %s/ (image.exr, %smetrics.json, frames.jsonl, manifest.json)\n", result.directory.string().c_str(),
                        runConfig.png ? "image.png, " : "");
            if (!result.metrics["error"].is_null()) std::printf("error vs reference: %s\n", result.metrics["error"].dump().c_str());
        } else if (*reference) {
            RunConfig runConfig = loadRunConfig(config, overrides);
            if (runConfig.reference.kind != ReferenceSpec::Kind::Rendered)
                throw InputError(config + ": /reference: expected path tracer settings (spp, max_depth, ...) to render a reference");
            const int n = runConfig.threads > 0 ? runConfig.threads : tbb::info::default_concurrency();
            tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism, std::size_t(n));
            // One reference per segment of a scene that changes (scene_events.h).
            for (const int segment : segmentStarts(runConfig.events)) {
                const ReferenceOutcome outcome = ensureReference(runConfig, force, !quiet, segment);
                const std::string of = runConfig.events.empty() ? "" : " (frames from " + std::to_string(segment) + " on)";
                if (outcome.rendered)
                    std::printf("rendered %s%s in %.1f s\n", outcome.image.string().c_str(), of.c_str(), outcome.seconds);
                else
                    std::printf("reference up to date: %s%s\n", outcome.image.string().c_str(), of.c_str());
            }
        } else if (*compare) {
            std::cout << dumpFinite(compareImages(imageA, imageB, layer,
                                                  errorMap ? std::optional<std::filesystem::path>(*errorMap) : std::nullopt),
                                    2)
                      << "\n";
        } else if (*stress) {
            const int n = threads && checkThreadsOption(*threads) > 0 ? *threads : tbb::info::default_concurrency();
            tbb::global_control threadLimit(tbb::global_control::max_allowed_parallelism, std::size_t(n));
            const std::vector<StressRow> rows = runStressSuite(stressCases, stressMethods, !quiet);
            std::cout << stressTable(rows);
            if (stressJsonFile) {
                std::ofstream out(*stressJsonFile);
                if (!(out << dumpFinite(stressJson(rows), 2) << "\n")) throw InputError("--json: cannot write \"" + *stressJsonFile + "\"");
            }
            const auto failed = std::count_if(rows.begin(), rows.end(), [](const StressRow& r) { return !r.passed; });
            std::printf("%zu of %zu case x method rows passed\n", rows.size() - std::size_t(failed), rows.size());
            if (failed > 0) return 1;
        } else if (*sweep) {
            if (threads) checkThreadsOption(*threads);
            if (runSweep(loadSweep(sweepFile), {threads, jobs, sweepIndex, dryRun, !quiet}) > 0) return 1;
        } else if (*methods) {
            if (asMarkdown)
                std::cout << parameterReferenceMarkdown();
            else
                printMethods(asJson);
        }
    } catch (const InputError& e) {
        printError(e.what());
        return 2;
    } catch (const std::exception& e) {
        printError(std::string("internal: ") + e.what());
        return 1;
    }
    return 0;
}
