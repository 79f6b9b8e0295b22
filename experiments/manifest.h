#pragma once
// Provenance recorded with every run: where the code came from and what it ran on.

#include "core/config/params.h"

namespace gibench {

// {"commit": hash, "dirty": bool} of the source tree gibench was built from ("unknown" when the
// tree is not a git checkout).
Json gitInfo();
// Host name, CPU model, logical cores, memory, operating system.
Json machineInfo();
// Current UTC time as ISO 8601.
std::string utcNow();

}  // namespace gibench
