// gibench: one executable for every experiment step.
//   gibench run CONFIG          render a config's frames, write results/<experiment>/<run>/
//                               (--set KEY=VALUE changes a key of the config: config_overrides.h)
//   gibench reference CONFIG    render (or reuse) the config's high-spp reference image
//   gibench compare A B         error metrics between two images, as JSON (with FLIP;
//                               --fail-above METRIC=VALUE exits 1 when a metric is above VALUE)
//   gibench sweep FILE          every run of a sweep file (--dry-run lists and checks them, --jobs N,
//                               --backend slurm submits them as one job array: slurm_backend.h)
//   gibench collect DIR         whether every run a sweep submitted is done (collect.h)
//   gibench report DIR          figures, tables and an HTML page of a results folder (report_command.h)
//   gibench methods             every registered method and its parameters (--json)
//   gibench keys                every config key: type, default, range, meaning (docs/parameters.md; --json)
// Bad input prints "error: ..." lines and exits with code 2.

#include "core/config/params.h"
#include "core/util/error.h"
#include "experiments/collect.h"
#include "experiments/compare.h"
#include "experiments/json_output.h"
#include "experiments/manifest.h"
#include "experiments/parameter_docs.h"
#include "experiments/reference.h"
#include "experiments/report_command.h"
#include "experiments/run.h"
#include "experiments/run_config.h"
#include "experiments/slurm_backend.h"
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

// The version and the commit of the sources (as the manifest records it: "gibench" there).
std::string versionText() {
    const Json git = gitInfo();
    std::string text = std::string("gibench ") + GIBENCH_VERSION + " (commit " + git["commit"].get<std::string>();
    if (git["dirty"] == true) text += ", with uncommitted changes";
    return text + ")";
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
    bool quiet = false, force = false, asJson = false;
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
    compare->add_option("--error-map", errorMap, "also write per-pixel error maps (and FLIP) to this EXR");
    std::vector<std::string> failAboveTexts;
    compare->add_option("--fail-above", failAboveTexts, "METRIC=VALUE: exit 1 when the metric is above VALUE, e.g. relmse=0.01; repeatable");

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
    sweep->add_flag("--quiet", quiet, "no progress lines");
    sweep->add_option("--set", setTexts, "KEY=VALUE: set a key of every run (before the axes), as for run; repeatable");
    sweep->add_option("--results", resultsRoot, "results root folder of every run (default: the configs' output.root)");
    int jobs = 1;
    std::optional<std::size_t> sweepIndex;
    sweep->add_option("--jobs", jobs, "runs at a time, each in its own process (threads per run default: cores / jobs)")->check(CLI::Range(1, 256));
    sweep->add_option("--index", sweepIndex, "run only this point (0-based, as --dry-run lists them): what a Slurm array task runs");
    std::string backend = "local";
    bool waitForJob = false;
    sweep->add_option("--backend", backend, "local: run here; slurm: submit one job array (the sweep file's \"slurm\" block)")
        ->check(CLI::IsMember({"local", "slurm"}));
    sweep->add_flag("--wait", waitForJob, "with --backend slurm: wait for the job array, then collect");

    std::string collectDir;
    std::optional<std::string> collectExperiment;
    CLI::App* collect = app.add_subcommand("collect", "check that every run a submitted sweep expects is done (exit 1 if not)");
    collect->add_option("dir", collectDir, "the sweep's experiment folder (or the results root, with --experiment)")->required();
    collect->add_option("--experiment", collectExperiment, "the experiment folder's name within DIR");

    std::string reportDir;
    std::optional<std::string> reportOut;
    CLI::App* reportCommand = app.add_subcommand("report", "figures, tables and an HTML page of a results folder (analysis/report.py)");
    reportCommand->add_option("dir", reportDir, "results root, experiment folder or run")->required();
    reportCommand->add_option("--out", reportOut, "report folder (default DIR/report)");

    CLI::App* methods = app.add_subcommand("methods", "list every method and its parameters");
    methods->add_flag("--json", asJson, "as JSON");

    CLI::App* keys = app.add_subcommand("keys", "every config key (run, camera, reference, output, budget, sweep, methods) with type, default, range and meaning");
    keys->add_flag("--json", asJson, "as JSON, one row per key");

    app.set_version_flag("--version", versionText, "the version and the commit of the sources");
    if (argc == 1) {
        std::cerr << app.help();
        return 2;
    }
    // CLI11 reports a misspelt subcommand as "A subcommand is required".
    const std::vector<CLI::App*> subcommands = app.get_subcommands([](const CLI::App*) { return true; });
    if (argv[1][0] != '-' && std::none_of(subcommands.begin(), subcommands.end(), [&](const CLI::App* sub) { return sub->get_name() == argv[1]; })) {
        std::string names;
        for (const CLI::App* sub : subcommands) names += (names.empty() ? "" : ", ") + sub->get_name();
        printError("unknown subcommand \"" + std::string(argv[1]) + "\" (one of " + names + ")");
        return 2;
    }

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
            if (runConfig.reference.kind == ReferenceSpec::Kind::None)
                throw InputError(config + ": /reference: expected path tracer settings (spp, max_depth, ...) to render a reference");
            if (runConfig.reference.kind == ReferenceSpec::Kind::External) {
                // Nothing to render, which is not an error: scripts call this for every config.
                std::printf("external reference: %s\n", runConfig.reference.file.string().c_str());
                return 0;
            }
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
            std::vector<MetricLimit> limits;
            for (const std::string& text : failAboveTexts) limits.push_back(parseMetricLimit(text));
            const Json comparison =
                compareImages(imageA, imageB, layer, errorMap ? std::optional<std::filesystem::path>(*errorMap) : std::nullopt);
            const std::vector<std::string> exceeded = exceededLimits(comparison, limits);
            std::cout << dumpFinite(comparison, 2) << std::endl;
            for (const std::string& line : exceeded) std::fprintf(stderr, "fail: %s\n", line.c_str());
            if (!exceeded.empty()) return 1;
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
            if (backend == "slurm") {
                // A task's threads are the slurm block's cpus_per_task; --index is what a task runs.
                for (const auto& [given, option] : {std::pair{bool(threads), "--threads"}, {sweepIndex.has_value(), "--index"}, {jobs != 1, "--jobs"}})
                    if (given) throw InputError(std::string(option) + ": not with --backend slurm (the sweep file's \"slurm\" block sets what each task gets)");
                return runSlurmSweep(loadSweep(sweepFile), {waitForJob, dryRun, overrides, !quiet});
            }
            if (waitForJob) throw InputError("--wait: only with --backend slurm");
            const Sweep localSweep = loadSweep(sweepFile);
            readSlurmSettings(localSweep.slurm, localSweep.file);  // checked whatever the backend, like every key
            if (runSweep(localSweep, {overrides, jobs, sweepIndex, dryRun, !quiet}) > 0) return 1;
        } else if (*collect) {
            return runCollect(collectDir, collectExperiment);
        } else if (*reportCommand) {
            return runReport(reportDir, reportOut ? std::optional<std::filesystem::path>(*reportOut) : std::nullopt);
        } else if (*methods) {
            printMethods(asJson);
        } else if (*keys) {
            if (asJson)
                std::cout << parameterReferenceJson().dump(2) << "\n";
            else
                std::cout << parameterReferenceMarkdown();
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
