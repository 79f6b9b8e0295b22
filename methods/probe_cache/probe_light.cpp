#include "methods/probe_cache/probe_light.h"

#include "core/util/bfloat16.h"

#include <algorithm>

namespace gibench {

const EnumChoices<ProbeStateFormat>& probeStateFormatChoices() {
    static const EnumChoices<ProbeStateFormat> choices = {{"float32", ProbeStateFormat::Float32}, {"bfloat16", ProbeStateFormat::BFloat16}};
    return choices;
}

namespace {

// A thread's decoded states: one for reads, one for edits, so that an edit may read other probes.
std::vector<float>& threadBuffer(bool forEdits, std::size_t floats) {
    thread_local std::vector<float> buffers[2];
    std::vector<float>& buffer = buffers[forEdits ? 1 : 0];
    if (buffer.size() < floats) buffer.resize(floats);
    return buffer;
}

}  // namespace

ProbeLight::ProbeLight(const ProbeEncoding& encoding, ProbeStateFormat format)
    : m_encoding(&encoding), m_format(format), m_floatsPerProbe(std::size_t(encoding.floatsPerProbe())) {
    if (m_format == ProbeStateFormat::Float32) return;
    m_halvesPerProbe = std::size_t(encoding.sampleWeightsOffset());
    m_weightsPerProbe = m_floatsPerProbe - m_halvesPerProbe;
}

std::size_t ProbeLight::bytesPerProbe() const {
    const std::size_t state = m_format == ProbeStateFormat::Float32 ? m_floatsPerProbe * sizeof(float)
                                                                     : m_weightsPerProbe * sizeof(float) + m_halvesPerProbe * sizeof(uint16_t);
    return state + sizeof(Memo);
}

void ProbeLight::grow(std::size_t count) {
    if (m_atNormal.size() >= count) return;
    if (m_format == ProbeStateFormat::Float32) {
        m_floats.resize(count * m_floatsPerProbe, 0.0f);
    } else {
        m_floats.resize(count * m_weightsPerProbe, 0.0f);
        m_halves.resize(count * m_halvesPerProbe, toBFloat16(0.0f));
    }
    m_atNormal.resize(count);
}

void ProbeLight::clear(uint32_t id) {
    update(id, [&](float* state) { std::fill_n(state, m_floatsPerProbe, 0.0f); });
}

const float* ProbeLight::read(uint32_t id) const {
    if (m_format == ProbeStateFormat::Float32) return m_floats.data() + std::size_t(id) * m_floatsPerProbe;
    float* state = threadBuffer(false, m_floatsPerProbe).data();
    decode(id, state);
    return state;
}

float* ProbeLight::editBuffer() const { return threadBuffer(true, m_floatsPerProbe).data(); }

// The means come first in a state, the weights after them (ProbeEncoding::sampleWeightsOffset):
// two straight loops, which the compiler vectorises.
void ProbeLight::decode(uint32_t id, float* state) const {
    const uint16_t* halves = m_halves.data() + std::size_t(id) * m_halvesPerProbe;
    for (std::size_t i = 0; i < m_halvesPerProbe; ++i) state[i] = fromBFloat16(halves[i]);
    std::copy_n(m_floats.data() + std::size_t(id) * m_weightsPerProbe, m_weightsPerProbe, state + m_halvesPerProbe);
}

void ProbeLight::encode(uint32_t id, float* state) {
    uint16_t* halves = m_halves.data() + std::size_t(id) * m_halvesPerProbe;
    for (std::size_t i = 0; i < m_halvesPerProbe; ++i) {
        halves[i] = toBFloat16(state[i]);
        state[i] = fromBFloat16(halves[i]);
    }
    std::copy_n(state + m_halvesPerProbe, m_weightsPerProbe, m_floats.data() + std::size_t(id) * m_weightsPerProbe);
}

void ProbeLight::refreshMemo(uint32_t id, const float* state) {
    m_atNormal[id] = {m_encoding->irradiance(state, vec3(0.0f, 0.0f, 1.0f)), m_encoding->sampleWeight(state) > 0.0f};
}

}  // namespace gibench
