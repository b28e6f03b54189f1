// Optional comparison backend for `fovref bench rays`: the same triangles and rays traced by
// Embree 3 on one thread. Compiled only when cmake/embree.cmake finds Embree (FOVREF_HAVE_EMBREE).
#pragma once

#ifdef FOVREF_HAVE_EMBREE

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "ref/bvh/ray.h"

namespace fovref {

class EmbreeScene {
public:
    /// Builds an Embree scene (one thread, RTC_BUILD_QUALITY_HIGH) over `positions` (3 corners
    /// per triangle, as Scene::positions). build_seconds() is the time of rtcCommitScene.
    explicit EmbreeScene(const std::vector<glm::vec3>& positions);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    double build_seconds() const;
    /// Closest hits with rtcIntersect1: t, primitive id and (u, v) as Embree reports them.
    void intersect(const std::vector<Ray>& rays, std::vector<Hit>& hits) const;
    /// Occlusion with rtcOccluded1.
    void occluded(const std::vector<Ray>& rays, std::vector<std::uint8_t>& blocked) const;
    /// The same answers from Embree's stream API: all rays in one rtcIntersect1M /
    /// rtcOccluded1M call (Embree then orders the work itself; the rays are converted first, as
    /// the one-at-a-time calls convert each ray).
    void intersect_stream(const std::vector<Ray>& rays, std::vector<Hit>& hits) const;
    void occluded_stream(const std::vector<Ray>& rays, std::vector<std::uint8_t>& blocked) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fovref

#endif  // FOVREF_HAVE_EMBREE
