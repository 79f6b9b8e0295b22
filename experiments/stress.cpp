#include "experiments/stress.h"

#include "core/image/finite_values.h"
#include "core/image/metrics.h"
#include "core/render/prepared_scene.h"
#include "core/scene/scene_loader.h"
#include "core/util/error.h"
#include "core/util/text_format.h"
#include "methods/registry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>

namespace gibench {
namespace {

const ParamTable kCaseParams = {
    {"about", ParamType::String, nullptr, "what the case checks and why its expectation holds"},
    {"scene", ParamType::Json, nullptr, "scene file (relative to the case file) or an inline scene"},
    {"camera", ParamType::Json, Json::object(), "camera keys laid over the scene's"},
    {"place", ParamType::Json, Json(), "{scale, translate} given to every shape (which must have no transform) and to the camera"},
    {"frames", ParamType::Int, 4, "frames rendered; the last one is measured", 1, 4096},
    {"seed", ParamType::Int, 1, "the renders' seed", 0},
    {"methods", ParamType::Json, Json(), "{method: {parameters}}; default: every method with its defaults"},
    {"expect", ParamType::Json, nullptr, "what the render must show (kExpectParams)"},
};

const ParamTable kExpectParams = {
    {"mean", ParamType::Float, Json(), "the exact mean radiance of \"total\" over the image (path_traced within 5 standard errors; "
                                       "other methods report their bias)"},
    {"same_as", ParamType::String, Json(), "a case (file name without .json) whose render by the same method this must match"},
    {"refused", ParamType::String, Json(), "the scene must be refused with a message containing this text"},
    {"tolerance", ParamType::Float, 0.005, "for same_as: |mean ratio - 1| allowed", 0.0, 1.0},
};

const ParamTable kPlaceParams = {
    {"scale", ParamType::Float, 1.0, "factor on every coordinate"},
    {"translate", ParamType::Vec3, Json::array({0, 0, 0}), "offset added after scaling"},
};

struct Expectation {
    enum class Kind { Finite, Mean, SameAs, Refused } kind = Kind::Finite;
    double mean = 0.0;
    std::string sameAs;
    std::string refused;
    double tolerance = 0.005;
};

struct Case {
    std::string name;
    std::filesystem::path file;
    Json json;
};

double meanOf(const Image& image) {
    double sum = 0.0;
    for (const float v : image.data) sum += v;
    return image.data.empty() ? 0.0 : sum / double(image.data.size());
}

// The standard error of meanOf(total) from the per-pixel variance of the mean.
double standardErrorOfMean(const Image& variance) {
    double sum = 0.0;
    for (const float v : variance.data) sum += v;
    return std::sqrt(sum) / double(std::max<std::size_t>(variance.data.size(), 1));
}

uint64_t fireflies(const Image& total) {
    std::vector<float> lum;
    lum.reserve(total.pixelCount());
    for (std::size_t p = 0; p < total.pixelCount(); ++p)
        lum.push_back(luminance(Color(total.data[3 * p], total.data[3 * p + 1], total.data[3 * p + 2])));
    if (lum.empty()) return 0;
    std::vector<float> sorted = lum;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const float median = sorted[sorted.size() / 2];
    if (!(median > 0.0f)) return 0;
    return uint64_t(std::count_if(lum.begin(), lum.end(), [&](float l) { return l > 100.0f * median; }));
}

Expectation readExpectation(Params& p) {
    Expectation e;
    const int given = int(p.has("mean")) + int(p.has("same_as")) + int(p.has("refused"));
    if (given > 1) p.fail("", "expected at most one of \"mean\", \"same_as\" and \"refused\"");
    if (p.has("mean")) {
        e.kind = Expectation::Kind::Mean;
        e.mean = p.getFloat("mean");
    } else if (p.has("same_as")) {
        e.kind = Expectation::Kind::SameAs;
        e.sameAs = p.getString("same_as");
    } else if (p.has("refused")) {
        e.kind = Expectation::Kind::Refused;
        e.refused = p.getString("refused");
    }
    e.tolerance = p.getFloat("tolerance");
    p.finish();
    return e;
}

// Gives every shape of `scene` and the camera `camera` the placement {scale, translate}.
void place(Params& p, Json& scene, Json& camera) {
    const double scale = p.getFloat("scale");
    const vec3 offset = p.getVec3("translate");
    p.finish();
    for (Json& shape : scene["shapes"]) {
        if (shape.contains("transform")) p.fail("", "expected shapes without their own \"transform\" (place replaces it)");
        shape["transform"] = {{"scale", scale}, {"translate", {offset.x, offset.y, offset.z}}};
    }
    auto move = [&](Json& pose) {
        for (const char* key : {"eye", "target"})
            if (pose.contains(key) && pose[key].is_array())
                for (std::size_t i = 0; i < pose[key].size() && i < 3; ++i) pose[key][i] = pose[key][i].get<double>() * scale + offset[int(i)];
    };
    move(camera);
    if (camera.contains("path"))
        for (Json& key : camera["path"]) move(key);
}

class SuiteRunner {
public:
    SuiteRunner(std::vector<std::string> onlyMethods, bool showProgress)
        : m_onlyMethods(std::move(onlyMethods)), m_showProgress(showProgress) {}

    void run(const Case& c) {
        Params p(c.json, c.file.string(), "", "stress case", &kCaseParams);
        p.getString("about");
        Params expectParams = p.child("expect", &kExpectParams, "expect");
        const Expectation expect = readExpectation(expectParams);
        const int frames = int(p.getInt("frames"));
        const uint64_t seed = uint64_t(p.getInt("seed"));
        Json methods = p.has("methods") ? p.getJson("methods") : Json();
        if (methods.is_null()) {
            methods = Json::object();
            for (const std::string& name : methodNames()) methods[name] = Json::object();
        }
        if (!methods.is_object()) p.fail("methods", "expected an object {method: {parameters}}");

        Json sceneJson = p.getJson("scene");
        std::filesystem::path sceneFile = c.file;
        if (sceneJson.is_string()) {
            sceneFile = c.file.parent_path() / sceneJson.get<std::string>();
            sceneJson = loadJsonFile(sceneFile);
        }
        Json camera = sceneJson.value("camera", Json::object());
        camera.merge_patch(p.getJson("camera"));
        if (p.has("place")) {
            Params placement = p.child("place", &kPlaceParams, "place");
            place(placement, sceneJson, camera);
        }
        p.finish();
        sceneJson.erase("camera");

        std::optional<PreparedScene> scene;
        CameraDesc cameraDesc;
        try {
            Params sceneParams(sceneJson, sceneFile.string(), "", "scene", nullptr);
            Scene loaded = loadScene(sceneParams);
            Params cameraParams(camera, c.file.string(), "/camera", "camera", &kCameraParams);
            cameraDesc = parseCamera(cameraParams, loaded.worldOrigin);
            scene.emplace(std::move(loaded));
        } catch (const InputError& e) {
            StressRow row;
            row.caseName = c.name;
            row.method = "-";
            row.measure = "refused";
            row.note = e.what();
            row.passed = expect.kind == Expectation::Kind::Refused && row.note.find(expect.refused) != std::string::npos;
            if (!row.passed) row.note = "unexpected refusal: " + row.note;
            add(row);
            return;
        }
        if (expect.kind == Expectation::Kind::Refused) {
            StressRow row;
            row.caseName = c.name;
            row.method = "-";
            row.measure = "refused";
            row.note = "expected a refusal containing \"" + expect.refused + "\", but the scene loaded";
            add(row);
            return;
        }
        for (const auto& [method, params] : methods.items()) {
            if (!m_onlyMethods.empty() && std::find(m_onlyMethods.begin(), m_onlyMethods.end(), method) == m_onlyMethods.end()) continue;
            add(render(c, *scene, cameraDesc, method, params, frames, seed, expect));
        }
    }

    std::vector<StressRow> rows() && { return std::move(m_rows); }

private:
    void add(const StressRow& row) {
        if (m_showProgress)
            std::fprintf(stderr, "stress: %-28s %-12s %s\n", row.caseName.c_str(), row.method.c_str(), row.passed ? "ok" : "FAILED");
        m_rows.push_back(row);
    }

    StressRow render(const Case& c, const PreparedScene& scene, const CameraDesc& camera, const std::string& method, const Json& params,
                     int frames, uint64_t seed, const Expectation& expect) {
        StressRow row;
        row.caseName = c.name;
        row.method = method;
        const MethodInfo* info = findMethod(method);
        if (!info) throw InputError(c.file.string() + ": /methods/" + method + ": unknown method (known: " + joined(methodNames()) + ")");
        Params methodParams(params, c.file.string(), "/methods/" + method, "method \"" + method + "\"", &info->parameters);
        std::unique_ptr<Method> m = info->create(methodParams);
        methodParams.finish();

        const auto start = std::chrono::steady_clock::now();
        RunNotes notes;
        LayeredImage image;
        try {
            m->prepare(scene, camera.width, camera.height, notes);
            for (int f = 0; f < frames; ++f) {
                StageTimer timer;
                image = LayeredImage(camera.width, camera.height);
                m->renderFrame({scene, camera.poseAt(float(f)).relativeTo(scene.scene.worldOrigin), camera.width, camera.height, f, frames,
                                f > 0 && camera.poseAt(float(f)) != camera.poseAt(float(f - 1)), seed, timer, false},
                               image);
            }
        } catch (const InputError& e) {
            row.measure = "refused";
            row.note = e.what();
            return row;
        }
        row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        row.stats = m->frameStats();
        for (const Layer& layer : image.layers)
            if (findNonfinite(layer.image, layer.image.channels).count > 0) {
                row.finite = false;
                row.note = "non-finite values in layer \"" + layer.name + "\"";
            }
        const Image& total = image.find("total")->image;
        row.fireflies = fireflies(total);
        const double mean = meanOf(total);
        m_renders[{c.name, method}] = total;

        switch (expect.kind) {
            case Expectation::Kind::Finite:
                row.measure = "mean";
                row.value = mean;
                row.passed = row.finite;
                break;
            case Expectation::Kind::Mean: {
                row.value = mean;
                row.expected = expect.mean;
                row.compared = true;
                const Layer* variance = image.find("variance");
                if (variance) {
                    row.measure = "mean";
                    row.tolerance = 5.0 * standardErrorOfMean(variance->image) + 1e-6 * std::fabs(expect.mean);
                    row.passed = row.finite && std::fabs(mean - expect.mean) <= row.tolerance;
                } else {
                    row.measure = "mean (bias reported)";
                    row.passed = row.finite;
                }
                break;
            }
            case Expectation::Kind::SameAs: {
                const auto it = m_renders.find({expect.sameAs, method});
                if (it == m_renders.end()) {
                    row.note = "case \"" + expect.sameAs + "\" has no render by " + method;
                    break;
                }
                const double base = meanOf(it->second);
                row.measure = "mean ratio to " + expect.sameAs;
                row.value = base > 0.0 ? mean / base : (mean == 0.0 ? 1.0 : 0.0);
                row.expected = 1.0;
                row.compared = true;
                row.tolerance = expect.tolerance;
                row.passed = row.finite && std::fabs(row.value - 1.0) <= expect.tolerance;
                row.note = "relMSE " + formatNumber(computeMetrics(total, it->second).relMse);
                break;
            }
            case Expectation::Kind::Refused: break;
        }
        if (!row.passed && row.note.empty()) row.note = "outside the tolerance";
        return row;
    }

    static std::string joined(const std::vector<std::string>& names) {
        std::string out;
        for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
        return out;
    }

    std::vector<std::string> m_onlyMethods;
    bool m_showProgress;
    std::vector<StressRow> m_rows;
    std::map<std::pair<std::string, std::string>, Image> m_renders;  // (case, method) -> total
};

}  // namespace

std::filesystem::path defaultStressCases() { return std::filesystem::path(GIBENCH_SOURCE_DIR) / "configs" / "stress"; }

std::vector<StressRow> runStressSuite(const std::filesystem::path& folder, const std::vector<std::string>& onlyMethods,
                                      bool showProgress) {
    std::vector<Case> cases;
    std::error_code error;
    if (!std::filesystem::is_directory(folder, error)) throw InputError(folder.string() + ": expected a folder of stress cases (*.json)");
    for (const auto& entry : std::filesystem::directory_iterator(folder))
        if (entry.path().extension() == ".json") cases.push_back({entry.path().stem().string(), entry.path(), loadJsonFile(entry.path())});
    std::sort(cases.begin(), cases.end(), [](const Case& a, const Case& b) { return a.name < b.name; });
    // A case compared with another renders after it.
    auto dependsOnAnother = [](const Case& c) {
        return c.json.is_object() && c.json.contains("expect") && c.json["expect"].is_object() && c.json["expect"].contains("same_as");
    };
    std::stable_partition(cases.begin(), cases.end(), [&](const Case& c) { return !dependsOnAnother(c); });
    SuiteRunner runner(onlyMethods, showProgress);
    for (const Case& c : cases) runner.run(c);
    return std::move(runner).rows();
}

std::string stressTable(const std::vector<StressRow>& rows) {
    std::ostringstream out;
    out << "| case | method | result | measure | value | expected | tolerance | probes | refused inserts | fireflies | s | note |\n";
    out << "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const StressRow& r : rows) {
        auto stat = [&](const char* key) { return r.stats.is_object() && r.stats.contains(key) ? r.stats[key].dump() : std::string("-"); };
        const bool measured = r.measure != "refused";
        out << "| " << r.caseName << " | " << r.method << " | " << (r.passed ? "ok" : (r.finite ? "FAILED" : "NON-FINITE")) << " | "
            << r.measure << " | " << (measured ? formatNumber(r.value) : "-") << " | "
            << (r.compared ? formatNumber(r.expected) : "-") << " | "
            << (r.tolerance > 0 ? formatNumber(r.tolerance) : "-") << " | " << stat("probes") << " | " << stat("inserts_refused") << " | "
            << r.fireflies << " | " << formatNumber(r.seconds) << " | " << r.note << " |\n";
    }
    return out.str();
}

Json stressJson(const std::vector<StressRow>& rows) {
    Json out = Json::array();
    for (const StressRow& r : rows)
        out.push_back({{"case", r.caseName}, {"method", r.method}, {"passed", r.passed}, {"finite", r.finite}, {"measure", r.measure},
                       {"value", r.value}, {"expected", r.expected}, {"tolerance", r.tolerance}, {"stats", r.stats},
                       {"fireflies", r.fireflies}, {"seconds", r.seconds}, {"note", r.note}});
    return out;
}

}  // namespace gibench
