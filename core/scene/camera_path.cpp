#include "core/scene/camera_path.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gibench {
namespace {

using glm::dvec3;

// glm::mix rounds each interpolated coordinate by a few float ulps (6e-8 of its magnitude);
// a hundredfold margin covers that.
constexpr double kRounding = 1e-6;

double maxAbs(const vec3& v) { return double(glm::max(glm::abs(v.x), glm::max(glm::abs(v.y), glm::abs(v.z)))); }

// The t in (0, 1) where |start + t delta| is least, when that is not at an end.
std::optional<double> closestInside(const dvec3& start, const dvec3& delta) {
    const double dd = glm::dot(delta, delta);
    if (dd == 0.0) return std::nullopt;
    const double t = -glm::dot(start, delta) / dd;
    if (t > 0.0 && t < 1.0) return t;
    return std::nullopt;
}

// Roots in (0, 1) of the cubic f, whose derivative is the quadratic f', by bisection on the
// stretches between the roots of f', where f is monotone.
template <typename F>
std::vector<double> rootsInside(const F& f, double a, double b, double c) {  // f'(t) = a t^2 + b t + c
    std::vector<double> splits = {0.0};
    auto addSplit = [&](double t) {
        if (t > 0.0 && t < 1.0) splits.push_back(t);
    };
    if (a != 0.0) {
        const double discriminant = b * b - 4.0 * a * c;
        if (discriminant >= 0.0) {
            addSplit((-b - std::sqrt(discriminant)) / (2.0 * a));
            addSplit((-b + std::sqrt(discriminant)) / (2.0 * a));
        }
    } else if (b != 0.0) {
        addSplit(-c / b);
    }
    splits.push_back(1.0);
    std::sort(splits.begin(), splits.end());
    std::vector<double> roots;
    for (std::size_t i = 0; i + 1 < splits.size(); ++i) {
        double lo = splits[i], hi = splits[i + 1];
        double flo = f(lo);
        const double fhi = f(hi);
        if (flo == 0.0) {
            if (lo > 0.0) roots.push_back(lo);
            continue;
        }
        if ((flo < 0.0) == (fhi < 0.0) || fhi == 0.0) continue;  // a root at hi is the next stretch's lo
        for (int step = 0; step < 100 && lo < hi; ++step) {
            const double mid = 0.5 * (lo + hi);
            const double fmid = f(mid);
            if ((fmid < 0.0) == (flo < 0.0)) {
                lo = mid;
                flo = fmid;
            } else {
                hi = mid;
            }
        }
        roots.push_back(0.5 * (lo + hi));
    }
    return roots;
}

}  // namespace

std::optional<PoseDegeneracy> findDegeneratePose(const CameraPose& a, const CameraPose& b) {
    // View d(t) = d0 + t dd and up u(t) = u0 + t du are linear in t.
    const dvec3 d0 = dvec3(a.target) - dvec3(a.eye), dd = dvec3(b.target) - dvec3(b.eye) - d0;
    const dvec3 u0 = dvec3(a.up), du = dvec3(b.up) - u0;
    const double tolView = kRounding * std::max({maxAbs(a.eye), maxAbs(a.target), maxAbs(b.eye), maxAbs(b.target)});
    const double tolUp = kRounding * std::max(maxAbs(a.up), maxAbs(b.up));

    if (const auto t = closestInside(d0, dd); t && glm::length(d0 + *t * dd) <= tolView)
        return PoseDegeneracy{PoseDegeneracy::Kind::EyeMeetsTarget, *t};
    if (const auto t = closestInside(u0, du); t && glm::length(u0 + *t * du) <= tolUp)
        return PoseDegeneracy{PoseDegeneracy::Kind::UpVanishes, *t};

    // c(t) = d(t) x u(t) = c0 + t c1 + t^2 c2 vanishes where up lies along the view; |c|^2 is
    // least where c . c' = 0, a cubic whose derivative is |c'|^2 + 2 c . c2.
    const dvec3 c0 = glm::cross(d0, u0), c1 = glm::cross(d0, du) + glm::cross(dd, u0), c2 = glm::cross(dd, du);
    auto c = [&](double t) { return c0 + t * c1 + t * t * c2; };
    auto slope = [&](double t) { return glm::dot(c(t), c1 + 2.0 * t * c2); };
    const auto candidates = rootsInside(slope, 6.0 * glm::dot(c2, c2), 6.0 * glm::dot(c1, c2),
                                         glm::dot(c1, c1) + 2.0 * glm::dot(c0, c2));
    for (double t : candidates) {
        const double view = glm::length(d0 + t * dd), up = glm::length(u0 + t * du);
        // Perturbing d by tolView and u by tolUp moves d x u by at most this much.
        if (glm::length(c(t)) <= tolView * up + tolUp * view + tolView * tolUp)
            return PoseDegeneracy{PoseDegeneracy::Kind::UpAlongView, t};
    }
    return std::nullopt;
}

}  // namespace gibench
