#pragma once
// A run's id: the first 16 hex digits of the SHA-256 of its resolved config without what does not
// change its result (run, experiment, output, threads). Equal for equal runs whatever the key
// order of their files (the resolved config's keys are sorted), so a sweep can tell a run it made
// before from another one under the same name.

#include "core/config/params.h"
#include "experiments/run_config.h"

#include <filesystem>
#include <string>

namespace gibench {

std::string runId(const Json& resolvedConfig);
inline std::string runId(const RunConfig& config) { return runId(config.resolved); }

// The id of the finished run whose folder this is, or "" when it holds none (no manifest, an
// unreadable one, or one without "finished": a run written whole has it, see output_dir.h).
std::string finishedRunId(const std::filesystem::path& runFolder);

}  // namespace gibench
