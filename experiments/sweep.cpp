#include "experiments/sweep.h"

#include "core/util/error.h"

#include <algorithm>
#include <filesystem>

namespace gibench {

const ParamTable kSweepParams = {
    {"base", ParamType::String, nullptr, "the run config the sweep varies (relative to the sweep file)"},
    {"experiment", ParamType::String, "", "the runs' experiment (default: the base config's)"},
    {"grid", ParamType::Json, Json::object(), "axes combined in every way: {key: [values]}"},
    {"zip", ParamType::Json, Json::object(), "axes varied together: {key: [values]}, all of one length"},
    {"render_references", ParamType::Bool, false, "render each missing reference once before the runs (else a missing one is an error)"},
    {"slurm", ParamType::Json, Json::object(), "how `--backend slurm` submits the sweep (docs/slurm.md)"},
};

namespace {

struct Axis {
    std::string key;
    std::vector<Json> values;
};

std::vector<Axis> readAxes(Params& sweep, const std::string& name) {
    const Json block = sweep.getJson(name);
    if (!block.is_object()) sweep.fail(name, "expected an object {key: [values]}, got " + block.dump());
    std::vector<Axis> axes;
    for (const auto& [key, values] : block.items()) {
        const std::string where = sweep.where(name) + key + ": ";
        try {
            parseConfigOverride(key + "=0");
        } catch (const InputError& e) {
            throw InputError(where + "not a key --set could name (" + std::string(e.what()) + ")");
        }
        if (!values.is_array() || values.empty()) throw InputError(where + "expected a non-empty array of values, got " + values.dump());
        axes.push_back({key, std::vector<Json>(values.begin(), values.end())});
    }
    return axes;
}

// A value as part of a run name: a string as it is (a .json file by its stem: a scene's name), an
// object by its "name" then its other keys and values (a method block: "mamba-facing-true"), an
// array as its elements joined by 'x' ([128, 128]: 128x128), anything else as JSON; each run of
// characters a name cannot hold becomes one '-'.
std::string nameText(const Json& value) {
    std::string text;
    if (value.is_string()) {
        text = value.get<std::string>();
        const std::filesystem::path file(text);
        if (file.extension() == ".json") text = file.stem().string();
    } else if (value.is_object() && value.contains("name")) {
        text = nameText(value["name"]);
        for (const auto& [key, v] : value.items())
            if (key != "name") text += "-" + key + "-" + nameText(v);
    } else if (value.is_array()) {
        for (const Json& v : value) {
            if (!text.empty()) text += 'x';
            text += nameText(v);
        }
    } else {
        text = value.dump();
    }
    std::string out;
    for (const char c : text) {
        if (isNameCharacter(c))
            out += c;
        else if (out.empty() || out.back() != '-')
            out += '-';
    }
    return out;
}

// An axis in a run name: its key's last part, or the one before a last "name" ("method.name":
// "method", so that it reads like the axis "method" whose blocks are named by their "name").
std::string axisLabel(const std::string& key) {
    const std::size_t dot = key.rfind('.');
    if (dot == std::string::npos) return key;
    if (key.compare(dot + 1, std::string::npos, "name") != 0) return key.substr(dot + 1);
    const std::size_t before = key.rfind('.', dot - 1);
    return key.substr(before == std::string::npos ? 0 : before + 1, dot - (before == std::string::npos ? 0 : before + 1));
}

ConfigOverride overrideOf(const std::string& key, const Json& value, const std::string& source) {
    ConfigOverride o = parseConfigOverride(key + "=0");
    o.value = value;
    o.text = key + "=" + value.dump();
    o.source = source;
    return o;
}

}  // namespace

Sweep loadSweep(const std::filesystem::path& file) {
    Sweep sweep;
    sweep.file = file;
    Params root(loadJsonFile(file), file.string(), "", "sweep", &kSweepParams);
    sweep.base = file.parent_path() / root.getString("base");
    const std::string experiment = root.getString("experiment");
    const std::vector<Axis> grid = readAxes(root, "grid"), zip = readAxes(root, "zip");
    sweep.renderReferences = root.getBool("render_references");
    if (root.has("slurm")) sweep.slurm = root.getJson("slurm");
    if (!sweep.slurm.is_null() && !sweep.slurm.is_object()) root.fail("slurm", "expected an object, got " + sweep.slurm.dump());
    root.finish();
    if (grid.empty() && zip.empty()) root.fail("", "expected at least one axis under \"grid\" or \"zip\"");
    for (const Axis& a : zip)
        if (a.values.size() != zip.front().values.size())
            root.fail("zip", "expected axes of one length, got " + std::to_string(zip.front().values.size()) + " values of \"" + zip.front().key +
                                 "\" and " + std::to_string(a.values.size()) + " of \"" + a.key + "\"");
    const bool namesRun = std::any_of(grid.begin(), grid.end(), [](const Axis& a) { return a.key == "run"; }) ||
                          std::any_of(zip.begin(), zip.end(), [](const Axis& a) { return a.key == "run"; });

    // An axis of one value names no run apart, so it is left out of the names (unless all are).
    const auto single = [](const Axis& a) { return a.values.size() == 1; };
    const bool allSingle = std::all_of(grid.begin(), grid.end(), single) && std::all_of(zip.begin(), zip.end(), single);

    // Grid index digits, the first axis most significant, then the zipped index.
    constexpr std::size_t kMaxPoints = 100000;
    const std::size_t zipCount = zip.empty() ? 1 : zip.front().values.size();
    std::size_t count = zipCount;
    const auto checkCount = [&] {
        if (count > kMaxPoints) root.fail("", "the axes make more than " + std::to_string(kMaxPoints) + " runs");
    };
    checkCount();
    for (const Axis& a : grid) {
        count *= a.values.size();  // cannot overflow: at most kMaxPoints times an array held in memory
        checkCount();
    }
    for (std::size_t index = 0; index < count; ++index) {
        SweepPoint point;
        std::vector<std::pair<const Axis*, const Json*>> chosen;
        point.index = index;
        point.axes = Json::object();
        std::size_t rest = index;
        const std::size_t zipIndex = rest % zipCount;
        rest /= zipCount;
        std::vector<std::size_t> digits(grid.size());
        for (std::size_t g = grid.size(); g-- > 0;) {
            digits[g] = rest % grid[g].values.size();
            rest /= grid[g].values.size();
        }
        for (std::size_t g = 0; g < grid.size(); ++g) chosen.push_back({&grid[g], &grid[g].values[digits[g]]});
        for (const Axis& a : zip) chosen.push_back({&a, &a.values[zipIndex]});
        for (const auto& [axis, value] : chosen) {
            point.keys.push_back(overrideOf(axis->key, *value, "by the sweep's axis \"" + axis->key + "\" to " + value->dump()));
            point.axes[axis->key] = *value;
            if (!namesRun && (axis->values.size() > 1 || allSingle)) {
                if (!point.name.empty()) point.name += '_';
                point.name.append(axisLabel(axis->key)).append("-").append(nameText(*value));
            }
        }
        if (namesRun) {
            const auto run = std::find_if(point.keys.begin(), point.keys.end(), [](const ConfigOverride& o) { return o.pointer() == "/run"; });
            point.name = run->value.is_string() ? run->value.get<std::string>() : run->value.dump();
        } else {
            point.keys.push_back(overrideOf("run", point.name, "by the sweep: the run's name from its axes"));
        }
        if (!experiment.empty()) point.keys.push_back(overrideOf("experiment", experiment, "by the sweep's \"experiment\""));
        sweep.points.push_back(std::move(point));
    }
    std::vector<std::string> names;
    for (const SweepPoint& p : sweep.points) names.push_back(p.name);
    std::sort(names.begin(), names.end());
    const auto twice = std::adjacent_find(names.begin(), names.end());
    if (twice != names.end()) root.fail("", "two runs would be named \"" + *twice + "\": give \"run\" an axis of distinct names");
    return sweep;
}

RunConfig loadSweepPoint(const Sweep& sweep, const SweepPoint& point, const RunOverrides& extra) {
    const Json provenance = {{"file", std::filesystem::absolute(sweep.file).lexically_normal().string()}, {"index", point.index}, {"axes", point.axes}};
    try {
        RunOverrides overrides = extra;
        overrides.keys.insert(overrides.keys.end(), point.keys.begin(), point.keys.end());
        RunConfig config = loadRunConfig(sweep.base, overrides);
        config.sweep = provenance;
        return config;
    } catch (const InputError& e) {
        throw InputError(sweep.file.string() + ": run \"" + point.name + "\":\n" + e.what());
    }
}

}  // namespace gibench
