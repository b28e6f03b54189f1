// The BMFR authors' 16 block-grid offsets (Koskela P2's OpenCL code, BLOCK_OFFSETS; SPEC §9 item
// 3), in pixels for 32 x 32 blocks: frame f moves the grid by offset[f mod 16]. A fixed
// sequence like Halton's, kept here because two passes follow it: BMFR's block grid
// (ref/bmfr/bmfr.h, bmfr_block_offsets) and the Visual-Polar staircase clip synchronised with
// that grid (ref/visual_polar/map.h, P5 Fig. 4b).
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace fovref {

inline const std::array<glm::ivec2, 16>& block_grid_offsets() {
    static const std::array<glm::ivec2, 16> offsets = {
        glm::ivec2{-14, -14}, glm::ivec2{4, -6},   glm::ivec2{-8, 14},  glm::ivec2{8, 0},
        glm::ivec2{-10, -8},  glm::ivec2{2, 12},   glm::ivec2{12, -12}, glm::ivec2{-10, 0},
        glm::ivec2{12, 14},   glm::ivec2{-8, -16}, glm::ivec2{6, 6},    glm::ivec2{-2, -2},
        glm::ivec2{6, -14},   glm::ivec2{-16, 12}, glm::ivec2{14, -4},  glm::ivec2{-6, 4}};
    return offsets;
}

}  // namespace fovref
