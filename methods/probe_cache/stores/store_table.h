#pragma once
// Every probe store, by name: a new store is its own folder under stores/ plus one row here.

#include "methods/probe_cache/probe_store.h"

#include <vector>

namespace gibench {

const std::vector<ProbeStoreInfo>& probeStoreTable();

}  // namespace gibench
