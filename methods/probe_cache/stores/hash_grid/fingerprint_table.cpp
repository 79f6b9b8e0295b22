#include "methods/probe_cache/stores/hash_grid/fingerprint_table.h"

#include <algorithm>

namespace gibench {

FingerprintTable::FingerprintTable(uint32_t slots, uint32_t maxProbeLength)
    : m_fingerprints(std::max<uint32_t>(slots, 1), 0u), m_ids(std::max<uint32_t>(slots, 1), 0u),
      m_maxProbeLength(std::min(maxProbeLength, std::max<uint32_t>(slots, 1))) {}

bool FingerprintTable::insert(uint64_t hash, uint32_t id) {
    uint32_t slot = homeOf(hash);
    for (uint32_t step = 0; step < m_maxProbeLength; ++step, slot = next(slot)) {
        if (m_fingerprints[slot] != 0) {
            ++m_collisions;
            continue;
        }
        m_fingerprints[slot] = fingerprintOf(hash);
        m_ids[slot] = id;
        ++m_used;
        return true;
    }
    return false;
}

}  // namespace gibench
