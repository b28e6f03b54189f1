// The Vulkan client's own BVH for the end-to-end frame pass (passes/frame.cpp), built on the host
// and traversed by shaders/include/frame_bvh.glsl. Not fovref's layout (docs/bvh.md: binned-SAH
// BVH2 collapsed into a BVH4 with SoA triangle blocks): a plain GPU BVH2, as a compute-shader
// ray tracer would have it.
//
//   build: binned SAH over the triangles' centroids, 16 bins per axis, C_t = C_i = 1; a node of
//          at most 4 triangles becomes a leaf unless a split is strictly cheaper; no split with
//          both sides non-empty (all centroids equal) -> a leaf (of any size). Ties: axes x, y,
//          z, planes from low to high, strict <; the partition is stable (std::stable_partition),
//          so the tree is a deterministic function of the triangle order.
//   layout: nodes depth first, 32 bytes each (GpuBvhNode); an inner node's left child is the
//          next node, its right child's index is stored; a leaf holds a range of GpuTriangle
//          records (48 bytes: the corners and the primitive id), the triangles reordered into
//          leaf order so that a leaf's triangles are contiguous.
#pragma once

#include <cstdint>
#include <vector>

#include "tools/clients/vulkan/passes/frame_scene.h"

namespace fovref_client {

/// std430 `struct { vec3 lo; uint a; vec3 hi; uint count; }`: inner node (count 0): `a` is the
/// right child (the left child is the next node); leaf: triangles a .. a + count - 1.
struct GpuBvhNode {
    float lo[3];
    std::uint32_t a;
    float hi[3];
    std::uint32_t count;
};

/// std430 `struct { vec3 p0; uint primitive; vec3 p1; float pad1; vec3 p2; float pad2; }`.
struct GpuTriangle {
    float p0[3];
    std::uint32_t primitive;
    float p1[3];
    float pad1;
    float p2[3];
    float pad2;
};

struct GpuBvh {
    std::vector<GpuBvhNode> nodes;
    std::vector<GpuTriangle> triangles;  ///< leaf order
    int depth = 0, leaves = 0;
};

/// Builds the tree over every triangle of `scene` (all of them hittable: the loader drops
/// zero-area triangles).
GpuBvh build_gpu_bvh(const FrameScene& scene);

}  // namespace fovref_client
