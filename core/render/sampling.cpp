#include "core/render/sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gibench {

vec3 sampleUniformSphere(const vec2& u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u.y;
    return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

Distribution1D::Distribution1D(std::vector<float> weights) : m_weights(std::move(weights)) {
    m_cdf.resize(m_weights.size() + 1, 0.0);
    for (std::size_t i = 0; i < m_weights.size(); ++i) {
        if (!(m_weights[i] >= 0.0f) || !std::isfinite(m_weights[i]))
            throw std::invalid_argument("Distribution1D: weight " + std::to_string(i) + " is negative or not finite");
        m_cdf[i + 1] = m_cdf[i] + m_weights[i];
    }
    m_total = m_cdf.back();
    if (m_total > 0.0)
        for (double& c : m_cdf) c /= m_total;
    m_probabilities.reserve(m_weights.size());
    for (const float w : m_weights) m_probabilities.push_back(float(w / m_total));
    m_nonZeroFrom.resize(m_weights.size());
    for (std::size_t i = m_weights.size(); i-- > 0;)
        m_nonZeroFrom[i] = m_weights[i] != 0.0f || i + 1 == m_weights.size() ? uint32_t(i) : m_nonZeroFrom[i + 1];
}

std::size_t Distribution1D::bin(float u) const {
    // The last bin whose CDF start is <= u, skipping zero-weight bins that share that start.
    std::size_t i = 0;
    if (m_weights.size() <= kCountedBins) {
        for (std::size_t j = 1; j < m_weights.size(); ++j) i += m_cdf[j] <= double(u);
    } else {
        auto it = std::upper_bound(m_cdf.begin(), m_cdf.end() - 1, double(u));
        i = std::size_t(std::max<std::ptrdiff_t>(0, (it - m_cdf.begin()) - 1));
    }
    return m_nonZeroFrom[i];
}

std::size_t Distribution1D::sample(float u, float& probability, float& remapped) const {
    const std::size_t i = sample(u, probability);
    const double width = m_cdf[i + 1] - m_cdf[i];
    remapped = width > 0.0 ? float(std::clamp((double(u) - m_cdf[i]) / width, 0.0, 0x1.fffffep-1)) : 0.0f;
    return i;
}

Distribution2D::Distribution2D(const std::vector<float>& weights, int width, int height) : m_width(width), m_height(height) {
    std::vector<float> rowTotals(height);
    m_rows.reserve(height);
    for (int y = 0; y < height; ++y) {
        m_rows.emplace_back(std::vector<float>(weights.begin() + std::ptrdiff_t(y) * width, weights.begin() + std::ptrdiff_t(y + 1) * width));
        rowTotals[y] = float(m_rows.back().total());
    }
    m_marginal = Distribution1D(rowTotals);
}

vec2 Distribution2D::sample(const vec2& u, float& pdf) const {
    float pRow, pColumn, vWithin, uWithin;
    const std::size_t row = m_marginal.sample(u.y, pRow, vWithin);
    const std::size_t column = m_rows[row].sample(u.x, pColumn, uWithin);
    pdf = pRow * pColumn * float(m_width) * float(m_height);
    return vec2((float(column) + uWithin) / float(m_width), (float(row) + vWithin) / float(m_height));
}

float Distribution2D::pdf(const vec2& p) const {
    if (m_marginal.empty()) return 0.0f;
    const int column = std::clamp(int(p.x * float(m_width)), 0, m_width - 1);
    const int row = std::clamp(int(p.y * float(m_height)), 0, m_height - 1);
    return m_marginal.probability(row) * m_rows[row].probability(column) * float(m_width) * float(m_height);
}

}  // namespace gibench
