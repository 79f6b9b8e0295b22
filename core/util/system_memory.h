#pragma once
// How much memory this machine has: the bound a config's worst-case memory is checked against
// before a run allocates it.

#include <cstdint>

namespace gibench {

// Physical memory in bytes (sysconf); 0 when the system does not say.
uint64_t physicalMemoryBytes();

}  // namespace gibench
