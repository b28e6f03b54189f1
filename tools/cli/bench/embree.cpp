// Embree 3 comparison backend for `fovref bench rays` (see tools/cli/bench/embree.h).
#ifdef FOVREF_HAVE_EMBREE

#include "tools/cli/bench/embree.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <limits>
#include <string>

#include "ref/core/error.h"

namespace fovref {

struct EmbreeScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    double build_seconds = 0.0;
};

namespace {

void check_device(RTCDevice device, const char* what) {
    const RTCError error = rtcGetDeviceError(device);
    if (error != RTC_ERROR_NONE)
        throw Error(std::string("Embree: ") + what + " failed (error " +
                    std::to_string(static_cast<int>(error)) + ")");
}

RTCRayHit embree_ray(const Ray& ray) {
    RTCRayHit rh{};
    rh.ray.org_x = ray.origin.x;
    rh.ray.org_y = ray.origin.y;
    rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.direction.x;
    rh.ray.dir_y = ray.direction.y;
    rh.ray.dir_z = ray.direction.z;
    rh.ray.tnear = ray.t_min;
    rh.ray.tfar = ray.t_max;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

Hit fovref_hit(const RTCRayHit& rh) {
    Hit h;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        h.t = rh.ray.tfar;
        h.primitive = static_cast<std::int32_t>(rh.hit.primID);
        h.u = rh.hit.u;
        h.v = rh.hit.v;
    }
    return h;
}

// Embree marks an occluded ray by setting tfar to -inf.
std::uint8_t is_blocked(const RTCRay& ray) {
    return ray.tfar == -std::numeric_limits<float>::infinity() ? 1 : 0;
}

}  // namespace

EmbreeScene::EmbreeScene(const std::vector<glm::vec3>& positions)
    : impl_(std::make_unique<Impl>()) {
    // One thread, like the reference.
    impl_->device = rtcNewDevice("threads=1");
    if (impl_->device == nullptr) throw Error("Embree: rtcNewDevice failed");
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);

    // One triangle geometry: vertices as stored (3 per triangle), indices 3t, 3t+1, 3t+2.
    const std::size_t triangles = positions.size() / 3;
    RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), triangles));
    check_device(impl_->device, "buffer allocation");
    for (std::size_t i = 0; i < positions.size(); ++i) {
        vertices[3 * i] = positions[i].x;
        vertices[3 * i + 1] = positions[i].y;
        vertices[3 * i + 2] = positions[i].z;
        indices[i] = static_cast<unsigned>(i);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(impl_->scene, geometry);
    rtcReleaseGeometry(geometry);

    // The BVH build happens in rtcCommitScene.
    const auto start = std::chrono::steady_clock::now();
    rtcCommitScene(impl_->scene);
    impl_->build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    check_device(impl_->device, "scene build");
}

EmbreeScene::~EmbreeScene() {
    if (impl_->scene != nullptr) rtcReleaseScene(impl_->scene);
    if (impl_->device != nullptr) rtcReleaseDevice(impl_->device);
}

double EmbreeScene::build_seconds() const { return impl_->build_seconds; }

void EmbreeScene::intersect(const std::vector<Ray>& rays, std::vector<Hit>& hits) const {
    hits.resize(rays.size());
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        RTCRayHit rh = embree_ray(rays[i]);
        rtcIntersect1(impl_->scene, &context, &rh);
        hits[i] = fovref_hit(rh);
    }
}

void EmbreeScene::intersect_stream(const std::vector<Ray>& rays, std::vector<Hit>& hits) const {
    std::vector<RTCRayHit> stream(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) stream[i] = embree_ray(rays[i]);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1M(impl_->scene, &context, stream.data(), static_cast<unsigned>(stream.size()),
                   sizeof(RTCRayHit));
    hits.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = fovref_hit(stream[i]);
}

void EmbreeScene::occluded_stream(const std::vector<Ray>& rays,
                                  std::vector<std::uint8_t>& blocked) const {
    std::vector<RTCRay> stream(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) stream[i] = embree_ray(rays[i]).ray;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1M(impl_->scene, &context, stream.data(), static_cast<unsigned>(stream.size()),
                  sizeof(RTCRay));
    blocked.resize(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) blocked[i] = is_blocked(stream[i]);
}

void EmbreeScene::occluded(const std::vector<Ray>& rays, std::vector<std::uint8_t>& blocked) const {
    blocked.resize(rays.size());
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        RTCRay ray = embree_ray(rays[i]).ray;
        rtcOccluded1(impl_->scene, &context, &ray);
        blocked[i] = is_blocked(ray);
    }
}

}  // namespace fovref

#endif  // FOVREF_HAVE_EMBREE
