#include "experiments/scene_events.h"

#include "core/scene/world_limits.h"
#include "core/util/error.h"
#include "core/util/text_format.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace gibench {
namespace {

// The row every event has: when it happens.
const ParamSpec& frameRow() {
    static const ParamSpec row = {"frame", ParamType::Int, Json(), "first frame with the change", 1, 1 << 20};
    return row;
}

const ParamTable& emissionParams() {
    static const ParamTable table = {
        frameRow(),
        {"material", ParamType::String, Json(), "the emissive material whose emission changes"},
        {"scale", ParamType::Float, Json(), "its emission becomes scale × the loaded one (0: switched off)", 0.0, 1e6},
    };
    return table;
}

const ParamTable& sunParams() {
    static const ParamTable table = {
        frameRow(),
        {"sun", ParamType::Int, 0, "which of the scene's suns, in file order", 0, 1 << 20},
        {"direction", ParamType::Vec3, Json(), "the sun's new direction of travel (normalised)"},
        optionalKey({"irradiance", ParamType::Color, Json(), "its new irradiance in W/m² (default: unchanged)", 0.0, 1e30}),
    };
    return table;
}

const ParamTable& moveParams() {
    static const ParamTable table = {
        frameRow(),
        {"shape", ParamType::String, Json(), "the shape (mesh name, or the prefix of an OBJ shape's meshes) to move"},
        {"translate", ParamType::Vec3, Json(), "how far it moves from where it was loaded, in scene units"},
    };
    return table;
}

const std::map<std::string, std::pair<SceneEvent::Kind, const ParamTable& (*)()>>& eventTypes() {
    static const std::map<std::string, std::pair<SceneEvent::Kind, const ParamTable& (*)()>> types = {
        {"emission", {SceneEvent::Kind::Emission, &emissionParams}},
        {"sun", {SceneEvent::Kind::Sun, &sunParams}},
        {"move", {SceneEvent::Kind::Move, &moveParams}},
    };
    return types;
}

std::string namesOf(const std::vector<std::string>& names) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "\"" : ", \"") + n + "\"";
    return list.empty() ? "none" : list;
}

}  // namespace

std::vector<std::pair<std::string, const ParamTable*>> sceneEventTables() {
    std::vector<std::pair<std::string, const ParamTable*>> tables;
    for (const auto& [name, type] : eventTypes()) tables.push_back({name, &type.second()});
    return tables;
}

std::vector<SceneEvent> parseSceneEvents(Params& runConfig, const Scene& scene, int frames) {
    std::vector<SceneEvent> events;
    std::vector<std::string> typeNames;
    for (const auto& [name, type] : eventTypes()) typeNames.push_back(name);
    for (Params& block : runConfig.children("events", "event")) {
        const std::string typeName = block.discriminator("type", typeNames);
        const auto& [kind, table] = eventTypes().at(typeName);
        Params p = block.withTable(table(), "event \"" + typeName + "\"");
        SceneEvent e;
        e.kind = kind;
        e.frame = int(p.getInt("frame"));
        if (e.frame >= frames)
            p.fail("frame", "expected a frame the run renders, 1 to " + std::to_string(frames - 1) + " (\"frames\" is " + std::to_string(frames) +
                                "), got " + std::to_string(e.frame));
        switch (kind) {
            case SceneEvent::Kind::Emission: {
                const std::string name = p.getString("material");
                std::vector<std::string> emissive;
                for (const Material& m : scene.materials)
                    if (m.isEmissive()) emissive.push_back(m.name);
                const auto found = std::find_if(scene.materials.begin(), scene.materials.end(), [&](const Material& m) { return m.name == name; });
                if (found == scene.materials.end() || !found->isEmissive())
                    p.fail("material", "expected an emissive material of the scene (" + namesOf(emissive) + "), got \"" + name + "\"");
                e.material = std::size_t(found - scene.materials.begin());
                e.scale = p.getFloat("scale");
                if (!isFinite(found->emission * e.scale))
                    p.fail("scale", "expected an emission that fits a float, got " + formatNumber(e.scale) + " × " + formatNumber(maxComponent(found->emission)));
                break;
            }
            case SceneEvent::Kind::Sun: {
                const long long sun = p.getInt("sun");
                if (scene.suns.empty()) p.fail("sun", "expected a sun of the scene, which has none");
                if (std::size_t(sun) >= scene.suns.size())
                    p.fail("sun", "expected one of the scene's " + std::to_string(scene.suns.size()) + " suns, 0 to " +
                                      std::to_string(scene.suns.size() - 1) + ", got " + std::to_string(sun));
                e.sun = std::size_t(sun);
                const vec3 d = p.getVec3("direction");
                const float length = glm::length(d);
                if (!(length > 0.0f) || !std::isfinite(length)) p.fail("direction", "expected a nonzero direction");
                e.direction = d / length;
                if (p.has("irradiance")) e.irradiance = p.getColor("irradiance");
                break;
            }
            case SceneEvent::Kind::Move: {
                const std::string name = p.getString("shape");
                std::vector<std::string> meshNames;
                for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
                    const std::string& mesh = scene.meshes[m].name;
                    meshNames.push_back(mesh);
                    if (mesh == name || mesh.rfind(name + "/", 0) == 0) e.meshes.push_back(m);
                }
                if (e.meshes.empty()) p.fail("shape", "expected a shape of the scene (" + namesOf(meshNames) + "), got \"" + name + "\"");
                e.translate = p.getVec3("translate");
                for (const std::size_t m : e.meshes)
                    for (const vec3& v : scene.meshes[m].positions) {
                        const vec3 moved = v + e.translate;
                        if (!isFinite(moved) || glm::any(glm::greaterThan(glm::abs(moved), vec3(kMaxCoordinate))))
                            p.fail("translate", "expected the moved shape within ±" + formatNumber(kMaxCoordinate) +
                                                    " of the scene's origin, got a vertex at (" + formatNumber(moved.x) + ", " +
                                                    formatNumber(moved.y) + ", " + formatNumber(moved.z) + ")");
                    }
                break;
            }
        }
        p.finish();
        e.resolved = p.resolved();
        e.resolved["type"] = typeName;
        events.push_back(std::move(e));
    }
    std::stable_sort(events.begin(), events.end(), [](const SceneEvent& a, const SceneEvent& b) { return a.frame < b.frame; });
    return events;
}

std::vector<int> segmentStarts(const std::vector<SceneEvent>& events) {
    std::vector<int> starts = {0};
    for (const SceneEvent& e : events)
        if (e.frame != starts.back()) starts.push_back(e.frame);
    return starts;
}

Scene sceneOfSegment(const Scene& loaded, const std::vector<SceneEvent>& events, int segmentStart) {
    Scene scene = loaded;
    for (const SceneEvent& e : events) {
        if (e.frame > segmentStart) break;
        switch (e.kind) {
            case SceneEvent::Kind::Emission: scene.materials[e.material].emission = loaded.materials[e.material].emission * e.scale; break;
            case SceneEvent::Kind::Sun:
                scene.suns[e.sun].direction = e.direction;
                if (e.irradiance) scene.suns[e.sun].irradiance = *e.irradiance;
                break;
            case SceneEvent::Kind::Move:
                for (const std::size_t m : e.meshes)
                    for (std::size_t v = 0; v < scene.meshes[m].positions.size(); ++v)
                        scene.meshes[m].positions[v] = loaded.meshes[m].positions[v] + e.translate;
                break;
        }
    }
    return scene;
}

Json eventsUpTo(const std::vector<SceneEvent>& events, int segmentStart) {
    Json applied = Json::array();
    for (const SceneEvent& e : events)
        if (e.frame <= segmentStart) applied.push_back(e.resolved);
    return applied;
}

Json changesUpTo(const std::vector<SceneEvent>& events, int segmentStart) {
    std::map<std::string, Json> last;  // by what changes, in key order: the JSON is canonical
    for (const SceneEvent& e : events) {
        if (e.frame > segmentStart) break;
        Json change = e.resolved;
        change.erase("frame");
        switch (e.kind) {
            case SceneEvent::Kind::Emission: last["emission/" + e.resolved["material"].get<std::string>()] = e.scale == 1.0f ? Json() : change; break;
            case SceneEvent::Kind::Sun: last["sun/" + std::to_string(e.sun)] = change; break;
            case SceneEvent::Kind::Move:
                last["move/" + e.resolved["shape"].get<std::string>()] = e.translate == vec3(0.0f) ? Json() : change;
                break;
        }
    }
    Json changes = Json::array();
    for (const auto& [what, change] : last)
        if (!change.is_null()) changes.push_back(change);
    return changes;
}

}  // namespace gibench
