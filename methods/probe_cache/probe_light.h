#pragma once
// The light a probe cache holds: one encoding state per probe id, plus each sampled probe's
// irradiance at its own normal, E(+z), kept current as the states change. A gather on a plane
// meets the normal of the probes placed on it again and again (every probe on a wall serves tens
// of pixels with the wall's normal), and one E(n) costs a pass over all the bins of the state:
// served from the memo, such a read is one load.
//
// A receiving normal whose probe-local form has |n_xy| <= kMemoTilt reads E(+z). The difference
// is at most 2π |n − z| max|L| (max(0, ·) is 1-Lipschitz and the hemisphere spans 2π sr), about
// 1.6e-3 per unit of the largest cached radiance: 5 % of kProbeIrradianceTolerance, and far
// beyond the float rounding that separates the normals of two pixels of one flat triangle.

#include "methods/probe_cache/probe_encoding.h"

#include <cstdint>
#include <vector>

namespace gibench {

class ProbeLight {
public:
    static constexpr float kMemoTilt = 2.5e-4f;

    explicit ProbeLight(const ProbeEncoding& encoding) : m_encoding(&encoding), m_floats(std::size_t(encoding.floatsPerProbe())) {}

    // Room for probe ids below `count`; new probes are empty.
    void grow(std::size_t count);
    std::size_t probes() const { return m_atNormal.size(); }
    std::size_t bytes() const { return m_states.size() * sizeof(float) + m_atNormal.size() * sizeof(Memo); }
    std::size_t bytesPerProbe() const { return m_floats * sizeof(float) + sizeof(Memo); }

    // Empties probe `id` (its id went to a new probe).
    void clear(uint32_t id);

    // The state to add samples to; call refresh() with the ids written before the next read.
    float* state(uint32_t id) { return m_states.data() + std::size_t(id) * m_floats; }
    const float* state(uint32_t id) const { return m_states.data() + std::size_t(id) * m_floats; }
    // Recomputes the memo of every id listed (in parallel), leaving `ids` sorted without duplicates.
    void refresh(std::vector<uint32_t>& ids);

    bool sampled(uint32_t id) const { return m_atNormal[id].sampled; }
    // E(local) of probe `id` (ProbeEncoding::irradiance), from the memo within kMemoTilt of +z.
    Color irradiance(uint32_t id, const vec3& local) const {
        if (local.z > 0.0f && local.x * local.x + local.y * local.y <= kMemoTilt * kMemoTilt) return m_atNormal[id].irradiance;
        return m_encoding->irradiance(state(id), local);
    }

private:
    struct Memo {
        Color irradiance{0.0f};  // E(+z)
        bool sampled = false;    // sampleWeight() > 0
    };

    const ProbeEncoding* m_encoding;
    std::size_t m_floats;
    std::vector<float> m_states;
    std::vector<Memo> m_atNormal;
};

}  // namespace gibench
