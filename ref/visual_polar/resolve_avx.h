// Pass 2 of the Visual-Polar modes eight screen pixels at a time with AVX2: the same bits as
// resolve_vp_pixel, which stays the readable reference (docs/visual-polar.md, "The resolve eight
// pixels at a time"). Each lane reads its (u, r, theta) and its columns' levels from the forward
// table, finds its two columns along rho, and on each column samples level floor(lambda) and,
// where resolve_vp_pixel does, the next one along phi (each lane at its own levels, each tap's
// colours and mask one load from a packed copy of the pyramid). The reference's choices between
// traced and untraced taps are made per lane by masks, and its lerps in its order. A lane whose
// phi lookup lies outside the range sample_vp_phi accepts, and every group with a non-finite
// table entry, runs the reference.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "ref/visual_polar/resolve.h"

namespace fovref {

/// Whether resolve_vp_row_avx covers a resolve: a forward table, a pyramid of 3-channel levels
/// with one-channel masks of their size, all of the map's width (level 0 its height; w (2 h + 25)
/// within int32, w and h at most 2^24), simd_allowed() and AVX2.
bool resolve_vp_avx_applies(const VisualPolarMap& map, const VpMips& mips,
                            const VpForwardTable* table);
/// The same for a pyramid built from the buffer itself (vp_resolve_avx_inputs below): a
/// 3-channel buffer and a one-channel mask of the map's size (the table only with `need_table`).
bool resolve_vp_avx_applies(const VisualPolarMap& map, const Image& color, const Image& valid,
                            const VpForwardTable* table, bool need_table = true);

/// What resolve_vp_row_avx reads of a pyramid, made once per resolve (vp_resolve_avx_inputs):
/// each column's rows n_i and last level vp_mip_last_level(n_i), and the pyramid's texels packed
/// with each texel's three colours and its mask side by side (R, G, B, mask: 16 bytes, so that a
/// lane reads a tap with one load), level after level, each level row-major as in VpMips (texel
/// (i, j) of level k at level_start[k] + j w + i): the same floats as build_vp_mips's levels.
struct VpResolveAvxInputs {
    int width = 0;
    std::vector<int> column_rows;
    std::vector<int> last_levels;
    std::vector<std::int32_t> level_start;
    alignas(32) std::int32_t first_starts[8] = {};  ///< level_start[0 .. 7] (0 beyond the last)
    std::vector<float> texels;
};
/// The packed copy of `mips`.
VpResolveAvxInputs vp_resolve_avx_inputs(const VpMips& mips);
/// The packed pyramid of a buffer and its mask (where resolve_vp_avx_applies) built straight
/// from them into `in` (its storage reused): level 0 packed, each next level downsampled from
/// the packed one before as build_vp_mips downsamples (two texels at a time in AVX2 lanes where
/// their columns have the same rows, each lane the reference's operations in its order): the
/// same floats as vp_resolve_avx_inputs(build_vp_mips(map, color, valid)).
void vp_resolve_avx_inputs(const VisualPolarMap& map, const Image& color, const Image& valid,
                           VpResolveAvxInputs& in);

/// The pyramid the reference's pixels read (those the lanes leave, and the last W mod 8 of each
/// row): given, or built from the buffer on first use (the lanes read the packed one, so that a
/// resolve the lanes cover whole never builds it).
class VpMipsSource {
public:
    explicit VpMipsSource(const VpMips& mips) : mips_(&mips) {}
    VpMipsSource(const VisualPolarMap& map, const Image& color, const Image& valid)
        : map_(&map), color_(&color), valid_(&valid) {}
    const VpMips& get() {
        if (!mips_) mips_ = &built_.emplace(build_vp_mips(*map_, *color_, *valid_));
        return *mips_;
    }

private:
    const VpMips* mips_ = nullptr;
    const VisualPolarMap* map_ = nullptr;
    const Image* color_ = nullptr;
    const Image* valid_ = nullptr;
    std::optional<VpMips> built_;
};

/// Pixels 0 .. 8 floor(W / 8) - 1 of screen row y as resolve_vp_pixel computes them (with `mip`
/// and `table`; the counters in `stats`); returns the pixels done. Only where
/// resolve_vp_avx_applies; `in` the packed pyramid of the resolve's buffer.
int resolve_vp_row_avx(const VisualPolarMap& map, VpMipsSource& mips, const VpResolveAvxInputs& in,
                       const VpForwardTable& table, bool mip, Image& out, int y,
                       ResolveStats& stats);

/// vp_forward_table's per-pixel arguments of a row, eight pixels at a time with AVX2 (where
/// simd_allowed()): for pixels k < n with their u and r, the columns i0, i1 of
/// vp_rho_columns(width, u) into column[0][k], column[1][k] and vp_mip_lambda's arguments
/// rows[i] / (2 pi max(r, 2^-10)) into argument[0][k], argument[1][k]. Returns the pixels done
/// (groups of eight, up to a group with a NaN u; the caller does the rest). `rows`: the width
/// columns' row counts.
std::size_t vp_table_arguments_avx(int width, const int* rows, const float* u, const float* r,
                                   std::size_t n, int* const column[2], float* const argument[2]);

/// Whether downsample_group_avx covers a pyramid level: 3-channel colours, a one-channel mask of
/// their size, simd_allowed() and AVX2.
bool downsample_avx_applies(const Image& color, const Image& valid);

/// Texels (i .. i + 7, j) of the next pyramid level (build_vp_mips) where the eight columns have
/// the same n > 1 rows at this level (`rows`) and j < ceil(n / 2): each lane the reference's
/// running mean of rows 2j and (2j + 1) mod n, the same operations in its order. Returns 8, or
/// 0 (nothing written) where the columns differ: the reference's.
int downsample_group_avx(const Image& color, const Image& valid, const std::vector<int>& rows,
                         int i, int j, Image& color_out, Image& valid_out);

}  // namespace fovref
