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
//
// States are kept in one of two formats (key "state_format"):
//  - float32: the encoding's floats as they are;
//  - bfloat16: the sample weights (ProbeEncoding::sampleWeightsOffset) as floats, the running
//    means rounded to bfloat16 after each update (a frame's samples of the probe): 2 bytes instead of 4, 8 bits of
//    precision. A running mean of weight w then ignores a sample that would move it by less than
//    half a spacing, |x − m| < m w 2^-9 (to 2^-8), so a mean of many samples stops moving; but
//    it stops within 2^-8 of where it stood, and a float mean's own noise, about 1/√w of the
//    signal, falls below that only past w ≈ 2^16 samples in one bin. Measured against float32
//    (every store, bounded and unbounded history up to 2048 frames): a thousandth or less of the
//    relMSE between two seeds; docs/performance.md, "Probe state".

#include "core/config/params.h"
#include "methods/probe_cache/probe_encoding.h"

#include <cstdint>
#include <vector>

namespace gibench {

enum class ProbeStateFormat { Float32, BFloat16 };
// The config names of the formats (key "state_format").
const EnumChoices<ProbeStateFormat>& probeStateFormatChoices();

class ProbeLight {
public:
    static constexpr float kMemoTilt = 2.5e-4f;

    ProbeLight(const ProbeEncoding& encoding, ProbeStateFormat format);

    // Room for probe ids below `count`; new probes are empty.
    void grow(std::size_t count);
    std::size_t probes() const { return m_atNormal.size(); }
    std::size_t bytes() const { return probes() * bytesPerProbe(); }
    std::size_t bytesPerProbe() const;

    // Empties probe `id` (its id went to a new probe).
    void clear(uint32_t id);

    // Probe `id`'s state as floats, valid until the calling thread's next read() of any
    // ProbeLight (decoded into a buffer of that thread unless the format is float32).
    const float* read(uint32_t id) const;
    // Calls edit(float* state) on probe `id`'s state, stores it back in the format and recomputes
    // the memo from what was stored. The update stage calls it once per probe and frame with all
    // of the probe's samples: one decode, encode and memo per probe rather than per sample. Threads
    // may update different probes at once.
    template <class Edit>
    void update(uint32_t id, Edit&& edit) {
        float* state = m_format == ProbeStateFormat::Float32 ? m_floats.data() + std::size_t(id) * m_floatsPerProbe : editBuffer();
        if (m_format != ProbeStateFormat::Float32) decode(id, state);
        edit(state);
        if (m_format != ProbeStateFormat::Float32) encode(id, state);
        refreshMemo(id, state);
    }

    bool sampled(uint32_t id) const { return m_atNormal[id].sampled; }
    // Probe `id` will be read soon: brings its memo into cache.
    void prefetch(uint32_t id) const {
        if (id < m_atNormal.size()) __builtin_prefetch(&m_atNormal[id]);
    }
    // irradiance(id, Frame(n).toLocal(n)) for the probe's own normal n: the memo, since that local
    // normal lies within float rounding of +z, far inside kMemoTilt (test ProbeLight.*OwnNormal*).
    Color irradianceAtOwnNormal(uint32_t id) const { return m_atNormal[id].irradiance; }
    // E(local) of probe `id` (ProbeEncoding::irradiance), from the memo within kMemoTilt of +z.
    Color irradiance(uint32_t id, const vec3& local) const {
        if (local.z > 0.0f && local.x * local.x + local.y * local.y <= kMemoTilt * kMemoTilt) return m_atNormal[id].irradiance;
        return m_encoding->irradiance(read(id), local);
    }

private:
    struct Memo {
        Color irradiance{0.0f};  // E(+z)
        bool sampled = false;    // sampleWeight() > 0
    };
    float* editBuffer() const;
    void decode(uint32_t id, float* state) const;
    // Stores `state` and leaves in it what was stored (the means rounded).
    void encode(uint32_t id, float* state);
    void refreshMemo(uint32_t id, const float* state);

    const ProbeEncoding* m_encoding;
    ProbeStateFormat m_format;
    std::size_t m_floatsPerProbe;
    std::vector<float> m_floats;     // float32: every float of every state; bfloat16: the sample weights
    std::vector<uint16_t> m_halves;  // bfloat16: the means, rounded
    std::size_t m_halvesPerProbe = 0, m_weightsPerProbe = 0;  // bfloat16: per state, ProbeEncoding::sampleWeightsOffset() and the rest
    std::vector<Memo> m_atNormal;
};

}  // namespace gibench
