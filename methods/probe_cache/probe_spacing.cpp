#include "methods/probe_cache/probe_spacing.h"

#include "core/util/error.h"

namespace gibench {

ParamTable spacingParams(const std::string& key, const std::string& what) {
    return {
        {key, ParamType::Float, 0.0, what + " in scene units; 0: use " + key + "_relative", 0.0},
        {key + "_relative", ParamType::Float, 1.0 / 75.0,
         what + " as a fraction of the largest side of the scene's bounding box, when " + key + " is 0", 1e-4, 1.0},
    };
}

ProbeSpacing::ProbeSpacing(Params& params, const std::string& key)
    : m_absolute(params.getFloat(key)),
      m_relative(params.getFloat(key + "_relative")),
      m_key(key),
      m_relativeWhere(params.where(key + "_relative")) {}

float ProbeSpacing::resolve(const Bounds3& sceneBounds) const {
    if (m_absolute > 0.0f) return m_absolute;
    if (sceneBounds.empty()) return 0.0f;
    const float spacing = m_relative * maxComponent(sceneBounds.extent());
    if (!(spacing > 0.0f))
        throw InputError(m_relativeWhere + "the scene's bounding box has no extent to take a fraction of; give " + m_key +
                         " in scene units");
    return spacing;
}

}  // namespace gibench
