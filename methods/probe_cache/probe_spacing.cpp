#include "methods/probe_cache/probe_spacing.h"

#include "core/util/error.h"
#include "core/util/text_format.h"

#include <algorithm>

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
      m_absoluteWhere(params.where(key)),
      m_relativeWhere(params.where(key + "_relative")) {}

float ProbeSpacing::resolve(const Bounds3& sceneBounds) const {
    if (sceneBounds.empty()) return m_absolute > 0.0f ? m_absolute : 0.0f;
    const float spacing = m_absolute > 0.0f ? m_absolute : m_relative * maxComponent(sceneBounds.extent());
    if (!(spacing > 0.0f))
        throw InputError(m_relativeWhere + "the scene's bounding box has no extent to take a fraction of; give " + m_key +
                         " in scene units");
    const double reach = std::max(maxComponent(glm::abs(sceneBounds.min)), maxComponent(glm::abs(sceneBounds.max)));
    if (reach / spacing > kMaxSpacingsFromOrigin) {
        const bool absolute = m_absolute > 0.0f;
        throw InputError((absolute ? m_absoluteWhere : m_relativeWhere) + "a spacing of " + formatNumber(spacing) +
                         " units is too fine for float positions in this scene, which reaches " + formatNumber(reach) +
                         " units from the origin (" + formatNumber(reach / spacing) + " spacings, at most " +
                         formatCount(kMaxSpacingsFromOrigin) + "); use " + m_key + " >= " +
                         formatNumber(reach / kMaxSpacingsFromOrigin) + (absolute ? "" : " or a larger " + m_key + "_relative"));
    }
    return spacing;
}

}  // namespace gibench
