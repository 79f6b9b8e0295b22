#include "methods/probe_cache/probe_light.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace gibench {

void ProbeLight::grow(std::size_t count) {
    if (m_atNormal.size() >= count) return;
    m_states.resize(count * m_floats, 0.0f);
    m_atNormal.resize(count);
}

void ProbeLight::clear(uint32_t id) {
    std::fill_n(state(id), m_floats, 0.0f);
    m_atNormal[id] = Memo{};
}

void ProbeLight::refresh(std::vector<uint32_t>& ids) {
    // One writer per memo.
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    tbb::parallel_for(std::size_t(0), ids.size(), [&](std::size_t i) {
        const uint32_t id = ids[i];
        const float* s = state(id);
        m_atNormal[id] = {m_encoding->irradiance(s, vec3(0.0f, 0.0f, 1.0f)), m_encoding->sampleWeight(s) > 0.0f};
    });
}

}  // namespace gibench
