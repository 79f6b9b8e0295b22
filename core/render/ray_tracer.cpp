#include "core/render/ray_tracer.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace gibench {

ScopedFlushToZero::ScopedFlushToZero() : m_flushZero(_MM_GET_FLUSH_ZERO_MODE()), m_denormalsZero(_MM_GET_DENORMALS_ZERO_MODE()) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

ScopedFlushToZero::~ScopedFlushToZero() {
    _MM_SET_FLUSH_ZERO_MODE(m_flushZero);
    _MM_SET_DENORMALS_ZERO_MODE(m_denormalsZero);
}

static void throwOnEmbreeError(RTCDevice device, const char* what) {
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree error ") + std::to_string(int(e)) + " in " + what);
}

RayTracer::RayTracer(const Scene& scene) {
    m_device = rtcNewDevice(nullptr);
    if (!m_device) throw std::runtime_error("Embree: cannot create a device");
    m_scene = rtcNewScene(m_device);
    rtcSetSceneFlags(m_scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_HIGH);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        RTCGeometry geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree-allocated buffers carry the padding its 16-byte vertex loads need.
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                     3 * sizeof(float), mesh.positions.size()));
        std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(vec3));
        auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(uint32_t), mesh.indices.size()));
        std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(uvec3));
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(m_scene, geometry, unsigned(m));
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(m_scene);
    throwOnEmbreeError(m_device, "building the BVH");
}

RayTracer::~RayTracer() {
    if (m_scene) rtcReleaseScene(m_scene);
    if (m_device) rtcReleaseDevice(m_device);
}

RayHit RayTracer::intersect(const Ray& ray, float tMax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x;
    rh.ray.org_y = ray.origin.y;
    rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.direction.x;
    rh.ray.dir_y = ray.direction.y;
    rh.ray.dir_z = ray.direction.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = tMax;
    rh.ray.time = 0.0f;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_scene, &context, &rh);
    RayHit hit;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.t = rh.ray.tfar;
    hit.mesh = int(rh.hit.geomID);
    hit.triangle = rh.hit.primID;
    hit.b1 = rh.hit.u;
    hit.b2 = rh.hit.v;
    return hit;
}

namespace {

// Lane i of a packet: the segment origin + t·direction for t in (0, tMax).
void setLane(RTCRay8& r, int i, const Ray& ray, float tMax) {
    r.org_x[i] = ray.origin.x;
    r.org_y[i] = ray.origin.y;
    r.org_z[i] = ray.origin.z;
    r.dir_x[i] = ray.direction.x;
    r.dir_y[i] = ray.direction.y;
    r.dir_z[i] = ray.direction.z;
    r.tnear[i] = 0.0f;
    r.tfar[i] = tMax;
    r.time[i] = 0.0f;
    r.mask[i] = ~0u;
    r.id[i] = unsigned(i);
    r.flags[i] = 0;
}

}  // namespace

void RayTracer::intersect(const Ray* rays, int n, RayHit* hits, bool coherent) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    alignas(32) int valid[kPacketSize];
    alignas(32) RTCRayHit8 rh;
    for (int i = 0; i < kPacketSize; ++i) {
        // Unused lanes are masked off but still read: they get a harmless ray.
        valid[i] = i < n ? -1 : 0;
        setLane(rh.ray, i, rays[std::min(i, n - 1)], kInfinity);
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, m_scene, &context, &rh);
    for (int i = 0; i < n; ++i) {
        RayHit& hit = hits[i];
        hit = RayHit{};
        if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
        hit.t = rh.ray.tfar[i];
        hit.mesh = int(rh.hit.geomID[i]);
        hit.triangle = rh.hit.primID[i];
        hit.b1 = rh.hit.u[i];
        hit.b2 = rh.hit.v[i];
    }
}

bool RayTracer::occluded(const Ray& ray, float tMax) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    r.org_x = ray.origin.x;
    r.org_y = ray.origin.y;
    r.org_z = ray.origin.z;
    r.dir_x = ray.direction.x;
    r.dir_y = ray.direction.y;
    r.dir_z = ray.direction.z;
    r.tnear = 0.0f;
    r.tfar = tMax;
    r.time = 0.0f;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(m_scene, &context, &r);
    return r.tfar < 0.0f;
}

void RayTracer::occluded(const ShadowRay* segments, int n, bool* blocked) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    alignas(32) int valid[kPacketSize];
    alignas(32) RTCRay8 r;
    for (int i = 0; i < kPacketSize; ++i) {
        // Unused lanes are masked off but still read: they get a harmless ray.
        const ShadowRay& s = segments[std::min(i, n - 1)];
        valid[i] = i < n ? -1 : 0;
        setLane(r, i, s.ray, s.tMax);
    }
    rtcOccluded8(valid, m_scene, &context, &r);
    for (int i = 0; i < n; ++i) blocked[i] = r.tfar[i] < 0.0f;
}

}  // namespace gibench
