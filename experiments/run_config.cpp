#include "experiments/run_config.h"

#include "core/config/input_file.h"
#include "core/scene/scene_loader.h"
#include "core/util/error.h"
#include "core/util/text_format.h"
#include "methods/path_traced/path_traced.h"
#include "methods/registry.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <stdexcept>
#include <unistd.h>

namespace gibench {

const ParamTable kRunParams = {
    {"experiment", ParamType::String, "default", "experiment name: results/<experiment>/<run>/"},
    {"run", ParamType::String, "", "run name (default: the config file's name)"},
    {"scene", ParamType::Json, nullptr, "scene file (relative to the config) or an inline scene object"},
    {"camera", ParamType::Json, Json::object(), "keys overriding the scene's camera"},
    {"frames", ParamType::Int, 1, "frames to render", 1, 1 << 20},
    {"seed", ParamType::Int, 1, "seed of every random stream of the run", 0, 9.0e15},
    {"threads", ParamType::Int, 0, "worker threads (0 = every core)", 0, 1024},
    {"prune_stages", ParamType::Bool, true, "leave out the stages the scene has no use for (false: run every stage; same image, more time)"},
    {"events", ParamType::Json, Json::array(), "scene changes at given frames: emission scaled, a sun turned, a shape moved (scene_events.h)"},
    {"method", ParamType::Json, nullptr, "{\"name\": method, ...its parameters}"},
    optionalKey({"reference", ParamType::Json, Json(), "reference image: {\"file\": path} or path tracer settings"}),
    {"output", ParamType::Json, Json::object(), "where and what to write"},
    optionalKey({"budget", ParamType::Json, Json(), "{\"seconds\": s}: stop once the frames' render time reaches s (\"frames\" stays the most)"}),
    {"checkpoints", ParamType::Json, Json::object(), "{\"frames\": [...], \"seconds\": [...]}: where metrics.json records the error (checkpoints.h)"},
};

const ParamTable kOutputParams = {
    {"root", ParamType::String, "results", "folder holding every experiment (relative to the config file; the default and --results: to the working directory)"},
    {"image_every", ParamType::Int, 0, "also write frame_NNNN.exr every k frames (0: the last frame only)", 0, 1 << 20},
    {"png", ParamType::Bool, true, "write a tone-mapped PNG beside the final EXR"},
};

// path_traced's row of `name` with another meaning: one default, one list of choices, one range.
static ParamSpec pathTracedRow(const std::string& name, const std::string& meaning) {
    for (const ParamSpec& spec : pathTracedParams())
        if (spec.name == name) {
            ParamSpec row = spec;
            row.meaning = meaning;
            return row;
        }
    throw std::logic_error("path_traced has no parameter \"" + name + "\"");
}

const ParamTable kReferenceParams = {
    optionalKey({"file", ParamType::String, Json(), "an external reference EXR (Mitsuba, pbrt, Cycles, ...) instead of rendering one"}),
    {"spp", ParamType::Int, 4096, "samples per pixel of the rendered reference", 1, 1 << 24},
    {"max_depth", ParamType::Int, 1024, "path depth of the rendered reference (pbrt convention)", 0, 65536},
    {"rr_depth", ParamType::Int, 3, "Russian roulette start depth of the rendered reference", 1, 65536},
    {"seed", ParamType::Int, 0x5eed, "seed of the rendered reference (independent of the run's)", 0, 9.0e15},
    pathTracedRow("sampler", "random numbers of the rendered reference (path_traced's \"sampler\")"),
};

// Experiment and run names are folder names: results/<experiment>/<run>/ and, beside it, the
// staging folder ".staging-<run>-PID-N" (output_dir.h), which must stay within the 255 bytes a
// file name may have.
constexpr std::size_t kMaxNameBytes = 200;

bool isNameCharacter(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; }

static bool validName(const std::string& s) {
    if (s.empty() || s.size() > kMaxNameBytes || s[0] == '.') return false;
    return std::all_of(s.begin(), s.end(), isNameCharacter);
}

// What validName() allows, and what `name` is, for the message.
static std::string nameRule(const std::string& name, const std::string& origin) {
    return "expected a folder name of 1 to " + std::to_string(kMaxNameBytes) +
           " ASCII letters, digits, '_', '-' or '.', not starting with '.', got \"" + name + "\" (" + std::to_string(name.size()) +
           " bytes" + origin + ")";
}

// `--results` or the config's output.root must name a folder gibench can create or write into: a
// path under a regular file, or a folder it may not write, would fail only when the results are
// written. `where` is the message's prefix ("--results: " or "FILE: /output/root: ").
static void checkOutputFolder(const std::filesystem::path& folder, const std::string& where) {
    std::error_code error;
    for (std::filesystem::path p = folder; !p.empty(); p = p.parent_path()) {
        const std::filesystem::file_status status = std::filesystem::status(p, error);
        if (std::filesystem::exists(status)) {
            if (!std::filesystem::is_directory(status))
                throw InputError(where + "expected a folder gibench can create or write into, got \"" + folder.string() + "\" (\"" +
                                 p.string() + "\" is a file, not a folder)");
            if (access(p.c_str(), W_OK | X_OK) != 0)
                throw InputError(where + "expected a folder gibench can create or write into, got \"" + folder.string() + "\" (\"" +
                                 p.string() + "\" is not writable)");
            return;
        }
        if (p == p.parent_path()) return;
    }
}

static std::shared_ptr<Scene> readScene(Params& root, const std::filesystem::path& configFile) {
    const Json value = root.getJson("scene");
    if (value.is_string()) {
        const std::filesystem::path path = configFile.parent_path() / value.get<std::string>();
        if (!std::filesystem::exists(path)) root.fail("scene", "scene file \"" + path.string() + "\" does not exist");
        return std::make_shared<Scene>(loadSceneFile(path));
    }
    if (value.is_object()) {
        Params block(value, root.file(), "/scene", "scene", nullptr);
        return std::make_shared<Scene>(loadScene(block));
    }
    root.fail("scene", "expected a scene file name or a scene object, got " + value.dump());
}

int checkThreadsOption(int threads) {
    const ParamSpec& row = *std::find_if(kRunParams.begin(), kRunParams.end(), [](const ParamSpec& p) { return p.name == "threads"; });
    if (threads < row.min || threads > row.max)
        throw InputError("--threads: expected an integer in [" + formatCount(row.min) + ", " + formatCount(row.max) +
                         "] (0 = every core), got " + std::to_string(threads));
    return threads;
}

namespace {

RunConfig readRunConfig(const std::filesystem::path& file, const RunOverrides& overrides) {
    RunConfig config;
    config.file = file;
    Json json = loadJsonFile(file);
    if (!overrides.keys.empty() && !json.is_object()) throw InputError(file.string() + ": /: expected an object for run config");
    applyConfigOverrides(json, overrides.keys);
    for (const ConfigOverride& o : overrides.keys) config.overrides.push_back(o.text);
    Params root(std::move(json), file.string(), "", "run config", &kRunParams);

    config.experiment = root.getString("experiment");
    if (!validName(config.experiment)) root.fail("experiment", nameRule(config.experiment, ""));
    config.run = root.getString("run");
    const bool runFromFileName = config.run.empty();
    if (runFromFileName) config.run = file.stem().string();
    if (!validName(config.run)) root.fail("run", nameRule(config.run, runFromFileName ? ", the config file's name" : ""));
    config.frames = int(root.getInt("frames"));
    config.seed = uint64_t(root.getInt("seed"));
    config.threads = int(root.getInt("threads"));
    config.pruneStages = root.getBool("prune_stages");
    config.budgetSeconds = readBudgetSeconds(root);
    config.checkpoints = readCheckpoints(root, config.frames);
    if (overrides.threads) {
        config.threads = checkThreadsOption(*overrides.threads);
    }

    // The method first: a misspelt parameter should not wait for a large scene to load.
    Params methodBlock = root.child("method", nullptr, "method");
    if (!root.has("method")) root.fail("", "missing key \"method\" for run config");
    config.methodName = methodBlock.discriminator("name", methodNames());
    const MethodInfo* info = findMethod(config.methodName);
    Params methodParams = methodBlock.withTable(info->parameters, "method \"" + config.methodName + "\"");
    config.method = info->create(methodParams);
    methodParams.finish();
    config.methodResolved = methodParams.resolved();
    config.methodResolved["name"] = config.methodName;

    Params output = root.child("output", &kOutputParams, "output");
    // A root the config names is relative to the config's folder, like its scene; the default
    // and --results are relative to the working directory.
    config.outputRoot = output.getString("root");
    if (output.has("root") && config.outputRoot.is_relative()) config.outputRoot = (file.parent_path() / config.outputRoot).lexically_normal();
    if (overrides.outputRoot) config.outputRoot = *overrides.outputRoot;
    const std::string rootWhere = overrides.outputRoot ? "--results: " : output.where("root");
    if (overrides.outputRoot) {
        // The manifest records it; a root from the config file is UTF-8 already (parsed JSON).
        try {
            checkUtf8Path(*overrides.outputRoot);
        } catch (const InputError& e) {
            throw InputError(rootWhere + e.what());
        }
    }
    checkOutputFolder(config.outputRoot, rootWhere);
    checkOutputFolder(config.outputRoot / config.experiment, rootWhere);
    config.imageEvery = int(output.getInt("image_every"));
    config.png = output.getBool("png");
    output.finish();

    if (root.has("reference")) {
        Params ref = root.child("reference", &kReferenceParams, "reference");
        ReferenceSpec& spec = config.reference;
        if (ref.has("file")) {
            spec.kind = ReferenceSpec::Kind::External;
            spec.file = file.parent_path() / ref.getString("file");
            for (const char* key : {"spp", "max_depth", "rr_depth", "seed", "sampler"})
                if (ref.has(key)) ref.fail(key, "a reference \"file\" takes no rendering settings");
            if (!std::filesystem::exists(spec.file)) ref.fail("file", "reference image \"" + spec.file.string() + "\" does not exist");
        } else {
            spec.kind = ReferenceSpec::Kind::Rendered;
            spec.spp = int(ref.getInt("spp"));
            spec.maxDepth = int(ref.getInt("max_depth"));
            spec.russianRouletteDepth = int(ref.getInt("rr_depth"));
            spec.seed = uint64_t(ref.getInt("seed"));
            spec.sampler = ref.getString("sampler");
        }
        ref.finish();
        spec.resolved = ref.resolved();
    }

    const auto start = std::chrono::steady_clock::now();
    config.scene = readScene(root, file);
    config.sceneLoadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // The run's camera keys are laid over the scene's, so a config can change one of them.
    Json camera = config.scene->description.contains("camera") ? config.scene->description["camera"] : Json::object();
    const Json cameraOverride = root.getJson("camera");
    if (!cameraOverride.is_object()) root.fail("camera", "expected an object, got " + cameraOverride.dump());
    if (camera.empty() && cameraOverride.empty()) root.fail("camera", "the scene has no camera and the config gives none");
    camera.merge_patch(cameraOverride);
    Params cameraParams(camera, file.string(), "/camera", "camera", &kCameraParams);
    config.camera = parseCamera(cameraParams, config.scene->worldOrigin);

    config.events = parseSceneEvents(root, *config.scene, config.frames);
    if (!config.events.empty() && config.reference.kind == ReferenceSpec::Kind::External)
        root.fail("events", "a run whose scene changes is measured against a rendered reference per segment, not one \"file\"");

    root.finish();

    Json resolvedCamera = cameraParams.resolved();
    config.resolved = root.resolved();
    config.resolved["run"] = config.run;
    config.resolved["threads"] = config.threads;
    config.resolved["camera"] = resolvedCamera;
    config.resolved["method"] = config.methodResolved;
    config.resolved["events"] = eventsUpTo(config.events, config.frames);
    config.resolved["output"] = output.resolved();
    config.resolved["output"]["root"] = config.outputRoot.string();
    config.resolved["budget"] = config.budgetSeconds ? Json{{"seconds", *config.budgetSeconds}} : Json();
    config.resolved["checkpoints"] = config.checkpoints.resolved;
    if (config.reference.kind != ReferenceSpec::Kind::None) config.resolved["reference"] = config.reference.resolved;
    return config;
}

}  // namespace

RunConfig loadRunConfig(const std::filesystem::path& file, const RunOverrides& overrides) {
    try {
        return readRunConfig(file, overrides);
    } catch (const InputError& e) {
        if (overrides.keys.empty()) throw;
        throw InputError(withOverrideOrigins(e.what(), overrides.keys));
    }
}

}  // namespace gibench
