#pragma once
// `gibench run`: renders a config's frames with its method and writes, atomically,
// results/<experiment>/<run>/ with manifest.json, metrics.json, frames.jsonl and images.

#include "experiments/run_config.h"

#include <filesystem>

namespace gibench {

struct RunResult {
    std::filesystem::path directory;
    Json metrics;  // the contents of metrics.json
};

RunResult executeRun(RunConfig& config, bool showProgress);

}  // namespace gibench
