#pragma once
// The reference of every config key (`gibench keys`: run config, camera, reference, output,
// budget, checkpoints, events, sweep file, every method), generated from the same tables that
// read configs, so the reference (docs/parameters.md) cannot drift from the code: a test compares
// the committed file with this output.

#include "core/config/params.h"

#include <string>

namespace gibench {

std::string parameterReferenceMarkdown();
// One row per key: {"section", "key" (dotted, as --set names it), "type", "default", "allowed", "meaning"}.
Json parameterReferenceJson();

}  // namespace gibench
