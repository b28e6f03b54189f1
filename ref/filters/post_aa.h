// Meng's post anti-aliasing (Meng 2018 eq. 2.14; SPEC §6): a screen-space Gaussian after pass 2
// whose size grows with the distance from the gaze point.
//
//   for each screen pixel (x, y), row by row:   post_aa_pixel(x, y)
//     c = (x + 1/2, y + 1/2), t = min(|c - g| / R, 1)   (R: the log-polar map's R; t is clamped
//                                                         to 1 where R = the diagonal and the gaze
//                                                         is off screen: choice)
//     t <= 0.10: unchanged
//     otherwise eta = 3 + 2 ceil((t - 0.10) / 0.05) (binary32: t - 0.1f, then / 0.05f, then
//       ceil; 5 .. 39), sigma = eta / 6 (choice), and the eta x eta Gaussian
//       out = sum_{dy} g(dy) sum_{dx} g(dx) I(clamp(x + dx), clamp(y + dy)),
//       dx, dy in -(eta-1)/2 .. (eta-1)/2, summed left to right within a row, rows top to bottom;
//       g(d) = e^(-d^2 / (2 sigma^2)) / sum_d e^(-d^2 / (2 sigma^2)) (binary32, dm::exp, the sum
//       from d = -(eta-1)/2 up), neighbours clamped to the screen.
// The weights of each eta are computed once (post_aa_weights). The pass computes each row sum
// (post_aa_row of an eta, column and row) once and reuses it for every pixel of that column and
// eta that reads it: the same operations on the same values as post_aa_pixel, bit for bit, at
// about 2 eta instead of eta^2 multiply-adds per pixel.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "ref/image/image.h"

namespace fovref {

/// The kernel size eta at distance ratio t = r / R: 3 + 2 ceil((t - 0.10) / 0.05) (Meng eq.
/// 2.14), 3 .. 39; 0 (no filter) for t <= 0.05, where eq. 2.14 gives 1 or less.
int post_aa_size(float t);

/// The normalised 1-D weights g(-(eta-1)/2) .. g((eta-1)/2) of size eta.
std::vector<float> post_aa_weights(int eta);

/// One row of the kernel: sum_{dx} g(dx) I(clamp(x + dx), yy), dx from -(eta-1)/2 up, per
/// channel (eta = g's size); writes in.channels values to `row`.
void post_aa_row(const Image& in, const std::vector<float>& g, int x, int yy, float* row);

/// Per-pixel work of the filter: pixel (x, y) of `out`. `weights[eta]` are post_aa_weights(eta).
void post_aa_pixel(const Image& in, glm::vec2 gaze, float radius_max,
                   const std::vector<std::vector<float>>& weights, Image& out, int x, int y);

/// Each pixel's kernel size (post_aa_size at its centre) for one gaze, R and screen, which the
/// post-AA stage keeps while they stay the same (a static gaze): the AVX pass then reads the
/// sizes instead of computing a square root and two divisions per pixel, the same values.
struct PostAaSizes {
    glm::vec2 gaze{0.0f};
    float radius_max = 0.0f;
    int width = 0, height = 0;
    std::vector<unsigned char> eta;  ///< W x H, row-major; empty: not made yet
    bool made_for(glm::vec2 gaze, float radius_max, int width, int height) const;
};

/// The filter: an image of `in`'s size and channels (post_aa_cached_pixel, row by row). With
/// `simd` (the default), simd_allowed() and a CPU with AVX, eight pixels at a time (once per
/// kernel size among them; near the left and right edges from a copy of the row with its clamped
/// neighbours), each lane doing post_aa_cached_pixel's operations in its order: the same bits as
/// `simd` false (the readable reference), NaN payloads aside (docs/determinism.md). `sizes`
/// (optional, AVX pass only): read when made for this gaze, R and size, else made as the pass
/// computes the sizes (the next frame with the same gaze reads them). `storage`: an image the
/// output is written into when it has the output's shape (a stage recycles an earlier frame's):
/// every pixel is written, none of its values is read; otherwise the output is made anew.
Image post_aa(const Image& in, glm::vec2 gaze, float radius_max, bool simd = true,
              PostAaSizes* sizes = nullptr, Image storage = {});

/// The row sums (post_aa_row) of one kernel size eta, kept for the last eta rows each column
/// asked for: the entry of (x, yy) lives in slot yy mod eta of column x. A window of eta rows
/// holds eta different rows (or fewer, clamped at the edges), so it never evicts its own rows.
/// Entries are stored by blocks of eight columns, each block's eta slots together (index):
/// the rows a group of eight pixels reads lie next to each other.
struct PostAaRowCache {
    int eta = 0;
    std::vector<float> value;  ///< entry k (index) at k x channels
    std::vector<int> row;      ///< the row each entry holds (-1: none yet)
    /// The entry of slot `slot` of column x: ((x / 8) eta + slot) 8 + x mod 8.
    std::size_t index(int slot, int x) const {
        return (static_cast<std::size_t>(x / 8) * eta + slot) * 8 + static_cast<std::size_t>(x % 8);
    }
};

/// post_aa's per-pixel work: post_aa_pixel with each row sum computed once per (eta, x, row)
/// instead of once per pixel that reads it (kept in cache[eta]) - the same operations on the
/// same values, so the same bits, when the pixels run row by row.
void post_aa_cached_pixel(const Image& in, glm::vec2 gaze, float radius_max,
                          const std::vector<std::vector<float>>& weights,
                          std::vector<PostAaRowCache>& cache, Image& out, int x, int y);

}  // namespace fovref
