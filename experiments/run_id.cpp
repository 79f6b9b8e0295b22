#include "experiments/run_id.h"

#include "core/util/hash.h"

#include <fstream>

namespace gibench {

std::string runId(const Json& resolvedConfig) {
    Json kept = resolvedConfig;
    for (const char* key : {"run", "experiment", "output", "threads"}) kept.erase(key);
    return sha256Hex(kept.dump()).substr(0, 16);
}

std::string finishedRunId(const std::filesystem::path& runFolder) {
    std::ifstream in(runFolder / "manifest.json");
    if (!in) return "";
    const Json manifest = Json::parse(in, nullptr, false);
    if (manifest.is_discarded() || !manifest.is_object() || !manifest.contains("config") || !manifest.contains("finished")) return "";
    return runId(manifest["config"]);
}

}  // namespace gibench
