#pragma once
// A deliberately naive second renderer, for tests only: the independent estimator the ground
// truth (`path_traced`, core/render/path_tracing.cpp) is checked against.
//
// It shares no rendering code with core/render: no Embree (brute-force Möller–Trumbore over every
// triangle, in double precision), no light sampler, no next-event estimation towards emitters, no
// MIS, no Russian roulette, no core BSDF. Paths are built by BSDF sampling alone and collect
// radiance only where they hit a front-facing emitter or escape into a constant environment. The
// one exception is the sun: a delta light no sampled direction can hit, so each scattering vertex
// sends one shadow ray towards each sun (its own code below, not core's light sampling).
//
// Same integral as path_traced: the same camera (PinholeCamera::generateRay, pixel (x, y) covers
// film positions [x, x+1) × [y, y+1), jittered uniformly), the same depth convention (pbrt's
// max_depth counts scattering events; 1 = emission seen + light arriving at the first hit), the
// same material model (written again from the description in core/render/bsdf.h) and the same
// shading-normal convention (shadingNormal and shadingCosines below, written again from
// core/render/surface.cpp and bsdf.cpp).
// What it shares is scene data (Scene, Mesh, Material, Texture::lookup), the camera geometry and
// the random number generator (Rng), on a seed of its own so its noise is independent.
//
// Constant environments only: an environment map throws std::invalid_argument.

#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "core/util/math.h"
#include "core/util/rng.h"
#include "support/block_z_test.h"

#include <glm/glm.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gibench::naive {

using glm::dvec3;

inline constexpr double kPiD = 3.14159265358979323846;

inline dvec3 toDouble(const vec3& v) { return dvec3(v); }

// ---- Geometry: every triangle of the scene in one flat list ------------------------------------

struct Triangle {
    dvec3 p0, e1, e2;    // vertices p0, p0 + e1, p0 + e2 (the mesh's order: counter-clockwise front)
    dvec3 frontNormal;   // unit normal of the counter-clockwise front
    const Mesh* mesh = nullptr;
    uint32_t index = 0;  // triangle of `mesh`
    const Material* material = nullptr;
};

struct Hit {
    double t = std::numeric_limits<double>::infinity();
    const Triangle* triangle = nullptr;
    double b1 = 0.0, b2 = 0.0;  // barycentrics of p0 + e1 and p0 + e2

    bool found() const { return triangle != nullptr; }
};

class TriangleList {
public:
    explicit TriangleList(const Scene& scene) {
        for (const Mesh& mesh : scene.meshes)
            for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
                const uvec3 i = mesh.indices[t];
                Triangle tri;
                tri.p0 = toDouble(mesh.positions[i.x]);
                tri.e1 = toDouble(mesh.positions[i.y]) - tri.p0;
                tri.e2 = toDouble(mesh.positions[i.z]) - tri.p0;
                const dvec3 n = glm::cross(tri.e1, tri.e2);
                if (!(glm::length(n) > 0.0)) continue;  // degenerate: no ray can hit it
                tri.frontNormal = glm::normalize(n);
                tri.mesh = &mesh;
                tri.index = t;
                tri.material = &scene.materials[mesh.materials[t]];
                m_triangles.push_back(tri);
            }
        // Hits closer than this to a ray's origin are the surface the ray leaves (rounding of the
        // hit point), never geometry: a billionth of the scene's size, far below any feature.
        m_tMin = 1e-9 * std::max(1.0, double(glm::length(scene.bounds().extent())));
    }

    // The closest triangle along origin + t·dir (dir unit), t > tMin, ignoring `skip` (the
    // triangle the ray leaves: a flat triangle cannot be hit again by a ray leaving it).
    Hit closest(const dvec3& origin, const dvec3& dir, const Triangle* skip) const {
        Hit best;
        for (const Triangle& tri : m_triangles) {
            if (&tri == skip) continue;
            double t, b1, b2;
            if (intersect(tri, origin, dir, t, b1, b2) && t < best.t) {
                best.t = t;
                best.triangle = &tri;
                best.b1 = b1;
                best.b2 = b2;
            }
        }
        return best;
    }

    // Whether anything lies along the ray to infinity (shadow rays towards a sun).
    bool blocked(const dvec3& origin, const dvec3& dir, const Triangle* skip) const {
        for (const Triangle& tri : m_triangles) {
            double t, b1, b2;
            if (&tri != skip && intersect(tri, origin, dir, t, b1, b2)) return true;
        }
        return false;
    }

    std::size_t size() const { return m_triangles.size(); }

private:
    // Möller & Trumbore 1997, both faces.
    bool intersect(const Triangle& tri, const dvec3& origin, const dvec3& dir, double& t, double& b1, double& b2) const {
        const dvec3 p = glm::cross(dir, tri.e2);
        const double det = glm::dot(tri.e1, p);
        if (det == 0.0) return false;  // parallel to the plane
        const double inv = 1.0 / det;
        const dvec3 s = origin - tri.p0;
        b1 = glm::dot(s, p) * inv;
        if (b1 < 0.0 || b1 > 1.0) return false;
        const dvec3 q = glm::cross(s, tri.e1);
        b2 = glm::dot(dir, q) * inv;
        if (b2 < 0.0 || b1 + b2 > 1.0) return false;
        t = glm::dot(tri.e2, q) * inv;
        return t > m_tMin;
    }

    std::vector<Triangle> m_triangles;
    double m_tMin = 0.0;
};

// ---- The point a ray hit ---------------------------------------------------------------------

struct Surface {
    dvec3 position;
    dvec3 geometricNormal;     // unit, turned towards the side the ray came from
    dvec3 interpolatedNormal;  // unit vertex normals interpolated, as the mesh gives them; else the geometric one
    bool frontFacing = true;   // the ray arrived on the counter-clockwise side: the side that emits
    const Triangle* triangle = nullptr;
    const Material* material = nullptr;
    dvec3 albedo{0.0};
};

inline Surface surfaceAt(const Scene& scene, const Hit& hit, const dvec3& rayDirection) {
    const Triangle& tri = *hit.triangle;
    Surface s;
    s.triangle = &tri;
    s.material = tri.material;
    // From the barycentrics rather than origin + t·dir: the point then lies on the plane to
    // rounding of the vertices, whatever the distance travelled.
    s.position = tri.p0 + hit.b1 * tri.e1 + hit.b2 * tri.e2;
    s.frontFacing = glm::dot(tri.frontNormal, rayDirection) < 0.0;
    s.geometricNormal = s.frontFacing ? tri.frontNormal : -tri.frontNormal;
    s.interpolatedNormal = s.geometricNormal;
    const Mesh& mesh = *tri.mesh;
    const uvec3 i = mesh.indices[tri.index];
    const double b0 = 1.0 - hit.b1 - hit.b2;
    if (!mesh.normals.empty()) {
        const dvec3 n = b0 * toDouble(mesh.normals[i.x]) + hit.b1 * toDouble(mesh.normals[i.y]) + hit.b2 * toDouble(mesh.normals[i.z]);
        if (glm::length(n) > 0.0) s.interpolatedNormal = glm::normalize(n);
    }
    if (tri.material->albedoTexture >= 0) {
        if (mesh.uvs.empty()) throw std::invalid_argument("naive renderer: a textured material on a mesh without uvs");
        const vec2 uv = float(b0) * mesh.uvs[i.x] + float(hit.b1) * mesh.uvs[i.y] + float(hit.b2) * mesh.uvs[i.z];
        s.albedo = toDouble(scene.textures[tri.material->albedoTexture].lookup(uv));
    } else {
        s.albedo = toDouble(tri.material->albedo);
    }
    return s;
}

// ---- The shading-normal convention -------------------------------------------------------------
// Core's convention (README, "Ground truth conventions"; core/render/surface.cpp, bsdf.cpp),
// written again here from its statement, not its code, so that both renderers estimate the same
// integral and a slip in either implementation shows as a disagreement:
//  1. The interpolated normal is turned to the side the ray came from, then bent towards the
//     geometric normal, in the plane of the two, just enough that the mirror reflection of wo
//     lies t = min(0.9 wo·ng, 0.01) above the surface, wherever it would lie lower (Keller et al.
//     2017; Cycles' ensure_valid_reflection). Found here by bisection, not by core's closed form:
//     for the normal at angle θ from ng towards ns the reflection's height is
//     h(θ) = (wo·ng) cos 2θ + (wo·x) sin 2θ (x the tangent towards ns), a sinusoid in 2θ whose
//     one extremum in [0°, 90°] lets it cross t only once there, from h(0) = wo·ng > t down.
//  2. The BSDF sees cosines against that normal but reflects only between directions that both
//     lie on the ray's side of the *geometric* surface and both above the shading normal (core:
//     Bsdf::sameSide plus the local-frame z > 0 tests).

inline dvec3 shadingNormal(const Surface& s, const dvec3& wo) {
    const dvec3& ng = s.geometricNormal;
    const dvec3 ns = glm::dot(s.interpolatedNormal, ng) < 0.0 ? -s.interpolatedNormal : s.interpolatedNormal;
    const double cosView = glm::dot(wo, ng), threshold = std::min(0.9 * cosView, 0.01);
    const auto reflectionHeight = [&](const dvec3& n) { return glm::dot(2.0 * glm::dot(n, wo) * n - wo, ng); };
    if (reflectionHeight(ns) >= threshold) return ns;
    const dvec3 tangent = ns - glm::dot(ns, ng) * ng;
    if (!(glm::length(tangent) > 0.0) || !(cosView > 0.0)) return ng;
    const dvec3 x = glm::normalize(tangent);
    double above = 0.0, below = std::atan2(glm::dot(ns, x), glm::dot(ns, ng));  // h(above) >= t > h(below)
    for (int i = 0; i < 64; ++i) {
        const double mid = 0.5 * (above + below);
        (reflectionHeight(std::cos(mid) * ng + std::sin(mid) * x) >= threshold ? above : below) = mid;
    }
    return std::cos(above) * ng + std::sin(above) * x;
}

struct ShadingCosines {
    double out = 0.0, in = 0.0;  // wo·ns and wi·ns; both 0 where the convention allows no reflection
    bool reflects() const { return out > 0.0 && in > 0.0; }
};

inline ShadingCosines shadingCosines(const Surface& s, const dvec3& shading, const dvec3& wo, const dvec3& wi) {
    if (glm::dot(wo, s.geometricNormal) <= 0.0 || glm::dot(wi, s.geometricNormal) <= 0.0) return {};
    const ShadingCosines c{glm::dot(wo, shading), glm::dot(wi, shading)};
    return c.reflects() ? c : ShadingCosines{};
}

// ---- Reflection: Lambert, or Lambert under a GGX coat ------------------------------------------
// The model of core/render/bsdf.h's header, evaluated from its formulas: diffuse ρ/π; "glossy"
// adds Walter et al. 2007's GGX microfacet lobe F(wi·h) D(h) G2 / (4 cos θo cos θi) with
// D(h) = α² / (π ((h·n)² (α² − 1) + 1)²), α = roughness², Schlick's F(c) = F0 + (1 − F0)(1 − c)⁵
// with F0 = `specular`, and the height-correlated Smith term G2 = 1 / (1 + Λ(wo) + Λ(wi)),
// Λ(w) = (sqrt(1 + α² tan²θ) − 1) / 2; the diffuse base is then scaled by
// (1 − F(cos θo))(1 − F(cos θi)). A glossy material whose `specular` is zero has no coat (core's
// rule: no lobe to sample, so plain Lambert).

// At one path vertex: the shading normal depends on the direction the path arrived from, wo.
class Reflection {
public:
    Reflection(const Surface& s, const dvec3& wo) : m_surface(s), m_normal(shadingNormal(s, wo)), m_albedo(s.albedo) {
        const Material& m = *s.material;
        if (m.type == MaterialType::Glossy && maxComponent(m.specular) > 0.0f) {
            m_coated = true;
            m_f0 = toDouble(m.specular);
            m_alpha = double(m.roughness) * double(m.roughness);
        }
    }

    ShadingCosines cosines(const dvec3& wo, const dvec3& wi) const { return shadingCosines(m_surface, m_normal, wo, wi); }

    // BSDF value f(wo, wi) (no cosine); both directions point away from the surface.
    dvec3 f(const dvec3& wo, const dvec3& wi) const {
        const ShadingCosines c = cosines(wo, wi);
        if (!c.reflects()) return dvec3(0.0);
        const dvec3 lambert = m_albedo / kPiD;
        if (!m_coated) return lambert;
        const dvec3 h = glm::normalize(wo + wi);
        const double g2 = 1.0 / (1.0 + lambda(c.out) + lambda(c.in));
        const dvec3 coat = fresnel(glm::dot(wi, h)) * (ggx(glm::dot(h, m_normal)) * g2 / (4.0 * c.out * c.in));
        return lambert * (dvec3(1.0) - fresnel(c.out)) * (dvec3(1.0) - fresnel(c.in)) + coat;
    }

    // Directions are drawn from a fixed mixture: cosine-weighted about the shading normal, and
    // (coated only, half the time) reflection about a GGX normal drawn with density D(h) cos θh
    // (Walter et al. 2007, not core's visible-normal sampling). density() is the mixture's, so
    // f cos / density is unbiased wherever f is not zero (the cosine part covers that set).
    dvec3 sampleDirection(const dvec3& wo, double uLobe, double u1, double u2) const {
        const dvec3 t = tangent(m_normal), b = glm::cross(m_normal, t);
        if (uLobe >= coatProbability()) {
            const double r = std::sqrt(u1), phi = 2.0 * kPiD * u2;
            return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u1)) * m_normal);
        }
        const double a2 = m_alpha * m_alpha;
        const double cosTheta = std::sqrt((1.0 - u1) / (1.0 + (a2 - 1.0) * u1));
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta)), phi = 2.0 * kPiD * u2;
        const dvec3 h = sinTheta * std::cos(phi) * t + sinTheta * std::sin(phi) * b + cosTheta * m_normal;
        return glm::normalize(2.0 * glm::dot(wo, h) * h - wo);
    }

    double density(const dvec3& wo, const dvec3& wi) const {
        const double cosIn = glm::dot(wi, m_normal);
        double pdf = (1.0 - coatProbability()) * std::max(0.0, cosIn) / kPiD;
        if (m_coated) {
            // The half vector of (wo, wi) is the only GGX normal that reflects wo into wi;
            // the reflection's Jacobian is 1 / (4 |wo·h|).
            const dvec3 h = glm::normalize(wo + wi);
            const double cosH = glm::dot(h, m_normal);
            if (cosH > 0.0) pdf += coatProbability() * ggx(cosH) * cosH / (4.0 * std::fabs(glm::dot(wo, h)));
        }
        return pdf;
    }

private:
    double coatProbability() const { return m_coated ? 0.5 : 0.0; }
    double ggx(double cosH) const {
        if (cosH <= 0.0) return 0.0;
        const double a2 = m_alpha * m_alpha, d = cosH * cosH * (a2 - 1.0) + 1.0;
        return a2 / (kPiD * d * d);
    }
    double lambda(double cosTheta) const {
        const double tan2 = std::max(0.0, 1.0 - cosTheta * cosTheta) / (cosTheta * cosTheta);
        return 0.5 * (std::sqrt(1.0 + m_alpha * m_alpha * tan2) - 1.0);
    }
    dvec3 fresnel(double c) const { return m_f0 + (dvec3(1.0) - m_f0) * std::pow(1.0 - std::clamp(c, 0.0, 1.0), 5.0); }
    // Any unit vector perpendicular to n.
    static dvec3 tangent(const dvec3& n) {
        const dvec3 other = std::fabs(n.x) < 0.9 ? dvec3(1.0, 0.0, 0.0) : dvec3(0.0, 1.0, 0.0);
        return glm::normalize(glm::cross(other, n));
    }

    const Surface& m_surface;
    dvec3 m_normal;
    dvec3 m_albedo;
    bool m_coated = false;
    dvec3 m_f0{0.0};
    double m_alpha = 1.0;
};

// ---- Paths -------------------------------------------------------------------------------------

struct Settings {
    int maxDepth = 8;  // scattering events per path (pbrt convention, as path_traced's max_depth)
    int spp = 64;
    uint64_t seed = 0x6e61697665ull;  // "naive": not path_traced's seed, so the noise is independent
};

class Renderer {
public:
    explicit Renderer(const Scene& scene) : m_scene(scene), m_triangles(scene) {
        if (scene.environment) {
            if (scene.environment->map) throw std::invalid_argument("naive renderer: environment maps are not supported");
            m_environment = toDouble(scene.environment->radiance);
        }
    }

    // Radiance arriving at the camera along -dir, from one path.
    dvec3 trace(dvec3 origin, dvec3 dir, Rng& rng, int maxDepth) const {
        dvec3 radiance(0.0), throughput(1.0);
        const Triangle* leaving = nullptr;
        for (int bounce = 0;; ++bounce) {
            const Hit hit = m_triangles.closest(origin, dir, leaving);
            if (!hit.found()) {
                radiance += throughput * m_environment;
                break;
            }
            const Surface s = surfaceAt(m_scene, hit, dir);
            if (s.frontFacing) radiance += throughput * toDouble(s.material->emission);
            if (bounce == maxDepth) break;

            const dvec3 wo = -dir;
            const Reflection reflection(s, wo);
            for (const SunLight& sun : m_scene.suns) radiance += throughput * sunlight(s, reflection, wo, sun);

            const double uLobe = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            const dvec3 wi = reflection.sampleDirection(wo, uLobe, u1, u2);
            const double pdf = reflection.density(wo, wi);
            const ShadingCosines c = reflection.cosines(wo, wi);
            if (!c.reflects() || !(pdf > 0.0)) break;
            throughput *= reflection.f(wo, wi) * (c.in / pdf);
            if (throughput == dvec3(0.0)) break;
            origin = s.position;
            dir = wi;
            leaving = s.triangle;
        }
        return radiance;
    }

    // Per pixel and channel: the mean of `spp` paths and the variance of that mean. Rows run in
    // parallel; each path's random numbers depend only on (seed, pixel, sample).
    test::PixelEstimates render(const CameraDesc& camera, const Settings& settings) const {
        const PinholeCamera pinhole(camera.poseAt(0.0f).relativeTo(m_scene.worldOrigin), camera.width, camera.height);
        test::PixelEstimates out(camera.width, camera.height, settings.spp);
        tbb::parallel_for(0, camera.height, [&](int y) {
            for (int x = 0; x < camera.width; ++x) {
                const uint64_t pixel = uint64_t(y) * camera.width + x;
                dvec3 sum(0.0), sumSquared(0.0);
                for (int sample = 0; sample < settings.spp; ++sample) {
                    Rng rng = Rng::forPath(settings.seed, 0, pixel, uint64_t(sample));
                    // path_traced's jitter: uniform over the pixel's square of film positions.
                    const float jx = rng.uniform(), jy = rng.uniform();
                    const Ray ray = pinhole.generateRay(float(x) + jx, float(y) + jy);
                    const dvec3 l = trace(toDouble(ray.origin), glm::normalize(toDouble(ray.direction)), rng, settings.maxDepth);
                    sum += l;
                    sumSquared += l * l;
                }
                const double n = settings.spp;
                for (int c = 0; c < 3; ++c) {
                    const double mean = sum[c] / n;
                    const double sampleVariance = n > 1 ? std::max(0.0, (sumSquared[c] - n * mean * mean) / (n - 1.0)) : 0.0;
                    out.mean[out.index(x, y, c)] = mean;
                    out.variance[out.index(x, y, c)] = sampleVariance / n;
                }
            }
        });
        return out;
    }

    std::size_t triangleCount() const { return m_triangles.size(); }

private:
    // Light from one sun reflected towards wo: a delta light, so one shadow ray, no sampling.
    dvec3 sunlight(const Surface& s, const Reflection& reflection, const dvec3& wo, const SunLight& sun) const {
        const dvec3 toSun = -glm::normalize(toDouble(sun.direction));
        const ShadingCosines c = reflection.cosines(wo, toSun);
        if (!c.reflects() || m_triangles.blocked(s.position, toSun, s.triangle)) return dvec3(0.0);
        return reflection.f(wo, toSun) * c.in * toDouble(sun.irradiance);
    }

    const Scene& m_scene;
    TriangleList m_triangles;
    dvec3 m_environment{0.0};
};

}  // namespace gibench::naive
