#pragma once
// A fixed-size open-addressing hash table from 64-bit key hashes to probe ids, the way SHaRC keeps
// its cache: each slot holds a 32-bit fingerprint of the key (0: empty) and an id; a key's home
// slot comes from the low bits of its hash, the fingerprint from the high bits, so that two keys
// sharing a home slot still tell apart. Lookups and inserts probe linearly at most
// `maxProbeLength` slots from home; erase() shifts the entries after a freed slot back towards
// their homes (no tombstones), so no entry ever sits farther from home than an insert put it.
//
// A fingerprint is not the key: the owner checks a matching entry's full key (sameKey) and the
// table counts a match that was another key (fingerprint_collisions), the error a table holding
// fingerprints alone would make silently.

#include <atomic>
#include <cstdint>
#include <vector>

namespace gibench {

class FingerprintTable {
public:
    FingerprintTable(uint32_t slots, uint32_t maxProbeLength);

    uint32_t slots() const { return uint32_t(m_fingerprints.size()); }

    // The id stored for `hash` whose key sameKey(id) confirms, or false. `home(id)` gives the home
    // slot of an id's key (for erase's shifts); both are the owner's, which keeps the keys.
    template <class SameKey>
    bool find(uint64_t hash, SameKey&& sameKey, uint32_t& id) const {
        const uint32_t fingerprint = fingerprintOf(hash);
        uint32_t slot = homeOf(hash);
        for (uint32_t step = 0; step < m_maxProbeLength; ++step, slot = next(slot)) {
            if (m_fingerprints[slot] == 0) return false;
            if (m_fingerprints[slot] != fingerprint) continue;
            if (sameKey(m_ids[slot])) {
                id = m_ids[slot];
                return true;
            }
            m_fingerprintCollisions.fetch_add(1, std::memory_order_relaxed);
        }
        return false;
    }

    // Puts `id` in the first empty slot within reach of the home of `hash` (whose key the table
    // must not hold yet); false when every slot in reach is taken (the caller counts a refusal).
    // Slots passed over count as collisions.
    bool insert(uint64_t hash, uint32_t id);

    // Removes the entry of `id` stored for `hash`; `homeOfId(id)` gives the home slot of any
    // stored id's key.
    template <class HomeOfId>
    void erase(uint64_t hash, uint32_t id, HomeOfId&& homeOfId) {
        uint32_t slot = homeOf(hash);
        for (uint32_t step = 0; step < m_maxProbeLength; ++step, slot = next(slot))
            if (m_fingerprints[slot] != 0 && m_ids[slot] == id) {
                shiftBack(slot, homeOfId);
                return;
            }
    }

    uint32_t homeOf(uint64_t hash) const { return uint32_t(hash % uint64_t(m_fingerprints.size())); }

    uint64_t used() const { return m_used; }
    uint64_t collisions() const { return m_collisions; }
    uint64_t fingerprintCollisions() const { return m_fingerprintCollisions.load(std::memory_order_relaxed); }
    static constexpr std::size_t kBytesPerSlot = 2 * sizeof(uint32_t);

private:
    static uint32_t fingerprintOf(uint64_t hash) { return uint32_t(hash >> 32) | 1u; }
    uint32_t next(uint32_t slot) const { return slot + 1 == m_fingerprints.size() ? 0 : slot + 1; }
    uint32_t distance(uint32_t from, uint32_t to) const {
        return to >= from ? to - from : to + uint32_t(m_fingerprints.size()) - from;
    }

    // Backward-shift deletion: walks the run after the freed slot and moves back each entry whose
    // home is not between the hole and it, until an empty slot ends the run.
    template <class HomeOfId>
    void shiftBack(uint32_t hole, HomeOfId&& homeOfId) {
        uint32_t slot = hole;
        for (uint32_t step = 1; step < m_fingerprints.size(); ++step) {
            slot = next(slot);
            if (m_fingerprints[slot] == 0) break;
            const uint32_t home = homeOfId(m_ids[slot]);
            if (distance(home, slot) >= distance(hole, slot)) {
                m_fingerprints[hole] = m_fingerprints[slot];
                m_ids[hole] = m_ids[slot];
                hole = slot;
            }
        }
        m_fingerprints[hole] = 0;
        --m_used;
    }

    std::vector<uint32_t> m_fingerprints;  // per slot, 0: empty
    std::vector<uint32_t> m_ids;           // per slot
    uint32_t m_maxProbeLength;
    uint64_t m_used = 0, m_collisions = 0;
    // Counted by const finds, which run concurrently; rare, so an atomic costs nothing measurable.
    mutable std::atomic<uint64_t> m_fingerprintCollisions{0};
};

}  // namespace gibench
