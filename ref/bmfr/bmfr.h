// Blockwise multi-order feature regression, BMFR (Koskela et al. 2019, publication P2 of the
// Koskela thesis; SPEC §9; docs/bmfr.md). Each phase below is one plain function, one GPU kernel
// of the authors' OpenCL code, from explicit input buffers to explicit output buffers:
//
//   bmfr_demodulate            radiance / max(albedo, 0.01)                        -> illumination
//   bmfr_accumulate_noisy      phase I: reproject, test, blend with the history    -> accumulated
//   bmfr_fit                   phase II: per 32x32 block, features, noise, QR      -> weights
//   bmfr_weighted_sum          phase II: sum_i w_i T_i per pixel, clamp at 0        -> fitted
//   bmfr_accumulate_filtered   phase III: blend the fit with its history            -> filtered
//   bmfr_remodulate            x max(albedo, 0.01), clamp(x^(1/2.2), 0, 1)           -> display
//   bmfr_taa                   the authors' YCoCg TAA in display space              -> output
//
// Every per-pixel product is binary32 in the order written in the functions' comments; the QR's
// dot products and norms accumulate in binary64 in row order and are rounded to float (SPEC §0).
// Inputs that are NaN or infinite are replaced by 0 and counted (bmfr_nonfinite_inputs).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "ref/image/image.h"
#include "ref/scene/camera.h"
#include "ref/visual_polar/map.h"

namespace fovref {

enum class BmfrStorage {
    half,   ///< the block matrix in binary16, rounded after every Householder column (default)
    single  ///< binary32 throughout (`bmfr_storage=float`)
};

/// The integer hash of the stochastic regularisation (SPEC §9 item 6).
enum class BmfrNoiseHash {
    jenkins,  ///< Bob Jenkins' six-shift hash, the authors' `random()` (default)
    wang      ///< Thomas Wang's hash (`bmfr_noise_hash=wang`)
};

/// How the QR's sums (column norms and dot products over a block's rows) are added up.
enum class BmfrSums {
    binary64,  ///< in binary64, rows in order, rounded to float once (default; exact products)
    workgroup  ///< as the authors' fitter kernel on 256 work items (`bmfr_sums=workgroup`):
               ///< work item t adds rows t, t + 256, t + 512, ... in float, then their
               ///< parallel_reduction_sum (bmfr_workgroup_sum)
};

/// The denoiser's parameters; the defaults are the authors' (SPEC §9).
struct BmfrParams {
    BmfrStorage storage = BmfrStorage::half;
    float position_limit_squared = 0.01f;  ///< phase I: |P' - P|^2 below this (scene units^2)
    float normal_limit_squared = 0.25f;    ///< phase I: |n' - n|^2 below this
    float albedo_floor = 0.01f;            ///< demodulation divides by max(albedo, this)
    /// Remodulation multiplies by max(albedo, this): albedo_floor, the demodulation's inverse
    /// (default, SPEC §9), or 0, the albedo itself as the authors' accumulate_filtered_data
    /// kernel (bmfr_remodulate=albedo).
    float remodulation_floor = 0.01f;
    float noisy_alpha_min = 0.2f;     ///< phase I: alpha = max(1 / (spp + 1), this)
    float filtered_alpha_min = 0.1f;  ///< phase III: alpha = max(1 / spp, this)
    float noise_amount = 0.01f;       ///< stochastic regularisation amplitude
    /// Phase I's reprojection of a point behind the previous camera (clip w < 0): false, no
    /// history (default, bmfr_behind_camera=reject); true, divided by the negative w as the
    /// authors' code does (bmfr_behind_camera=project; w = 0 has no history either way).
    bool project_behind_camera = false;
    BmfrNoiseHash noise_hash = BmfrNoiseHash::jenkins;  ///< its hash
    BmfrSums sums = BmfrSums::binary64;                 ///< the QR's sums (bmfr_sums)
    /// binary16 storage: round the fit's rows with F16C where the CPU has it (false: always
    /// the integer code of ref/bmfr/half.h; the same bits, which the tests compare)
    bool f16c = true;
    /// The block edge (bmfr_block): 32, the authors' (their code supports no other), or 64,
    /// which P2 §6.1 found best in quality. A block has block^2 rows; the noise's seed strides
    /// by block^2 as the authors' BLOCK_EDGE_LENGTH * BLOCK_EDGE_LENGTH; the grid's offsets are
    /// the authors' scaled by block / 32 (choice: they move the grid over the same share of a
    /// block).
    int block_size = 32;
    /// The display exponent of the remodulation (bmfr_gamma): the authors' 0.454545f (their
    /// powr(x, 0.454545f)) or 1.0f / 2.2f (0.45454547f, fovref's before). The linear output
    /// (bmfr_output) raises to 2.2 either way.
    float display_exponent = 0.454545f;
    float pivot_epsilon = 1e-7f;  ///< |R_ii| below this: weight 0 (counted)
    float taa_alpha = 0.2f;       ///< TAA: 0.2 new + 0.8 history
    /// Keep the directly seen emission out of the fit (bmfr_emission=separate, our extension,
    /// docs/bmfr.md): demodulate radiance - emission and add the emission back when
    /// remodulating. Off by default, and without an emission buffer: the radiance is demodulated
    /// whole, as SPEC §9.
    bool separate_emission = false;
    /// The input colour is already divided by max(albedo, floor) (the BMFR authors' input,
    /// `denoise bmfr --demodulated`): phase I takes it as the illumination as it is (NaN and
    /// infinities -> 0, clamped to +-65504), and remodulation multiplies by max(albedo, floor)
    /// as usual. Not with separate_emission.
    bool demodulated_input = false;
    /// Where this frame's samples lie in their pixels (the authors' pixel_offsets[frame], x
    /// right, y down in fovref's rows): phase I's reprojected pixel index is the projection
    /// minus this offset, (0.5, 0.5) for pixel centres (bmfr_project). Screen space only.
    glm::vec2 pixel_offset{0.5f, 0.5f};
};

inline constexpr int bmfr_block_size = 32;  ///< the authors' block edge in pixels (the default)
inline constexpr int bmfr_block_pixels = bmfr_block_size * bmfr_block_size;
inline constexpr int bmfr_feature_count = 10;  ///< [1, n_x, n_y, n_z, w, w^2]
inline constexpr int bmfr_column_count = 13;   ///< the features and the three colour channels
inline constexpr int bmfr_scaled_first = 4;    ///< features 4..9 are scaled per block
inline constexpr int bmfr_scaled_count = 6;    ///< world position and its squares
inline constexpr int bmfr_weight_count = 30;   ///< 10 weights per colour channel

/// The authors' 16 block-grid offsets (SPEC §9 item 3); frame f uses offset[f mod 16].
const std::array<glm::ivec2, 16>& bmfr_block_offsets();

/// The view-projection of a pinhole camera as the authors pass it (column vectors, OpenGL clip
/// space: x and y in [-w, w] on screen, NDC y up, w the view depth). Rows (binary32):
///   row 0 = (R, -R.C) / (tan (W / H)),  row 1 = (U, -U.C) / tan,  row 2 = row 3 = (F, -F.C)
/// with tan = tan(vfov / 2). A pixel index (x, y) (integers at pixel centres) of a world point:
///   x = (clip.x / clip.w + 1) 0.5 W - 0.5,  y = (1 - clip.y / clip.w) 0.5 H - 0.5,
/// the point not seen when clip.w <= 0. `fovref denoise bmfr` reads these matrices from JSON.
struct ViewProjection {
    std::array<float, 16> m{};  ///< row-major
    bool operator==(const ViewProjection&) const = default;
};
ViewProjection view_projection(const Camera& camera, int width, int height);
/// The pixel index at which `world` appears under `vp` on a W x H screen, for samples at
/// `offset` in their pixels (x = (clip.x / clip.w + 1) 0.5 W - offset.x, y = (1 - clip.y /
/// clip.w) 0.5 H - offset.y); false when behind (clip.w <= 0), or, with `behind`, only when
/// clip.w = 0 or the result is not finite: a point behind the camera then projects through the
/// negative w as the authors' code does (bmfr_behind_camera=project).
bool bmfr_project(const ViewProjection& vp, int width, int height, glm::vec3 world,
                  glm::vec2& pixel, glm::vec2 offset = glm::vec2(0.5f), bool behind = false);

/// Where BMFR runs (SPEC §9 item 11, Koskela P5 §3.3; docs/bmfr.md "Visual-Polar space"): on the
/// screen (no map), or on a Visual-Polar buffer (`map`), where
///   - only texels with valid = 1 carry data (clipped and off-screen texels are never traced);
///     the others are zero rows of their blocks and give 0 in every phase;
///   - rows (phi) wrap around: column c's rows are taken modulo its row count n_c; columns
///     (rho) clamp;
///   - the reprojection goes through the screen: the previous view-projection gives the previous
///     screen pixel s, and the previous frame's map gives (u, t) = vp_forward_angle(s + 1/2);
///     the stored reprojected pixel is q = (u - 1/2, t), t the angle as a fraction of the turn;
///   - bilinear taps of q (bmfr_vp_taps): columns x0 = floor(q.x) and x0 + 1, each with its own
///     rows: v_c = t n_c - 1/2, rows floor(v_c) and + 1 modulo n_c;
///   - blocks (bmfr_grid with a map): cell columns as on the screen (clamped); cell column cx
///     has the phi height H = the largest n_c of its columns, ceil(H / 32) blocks at rows
///     32 cy + offset.y + (0 .. 31) modulo H (the staircase of P5 Fig. 4b).
struct BmfrSpace {
    std::optional<VisualPolarMap> map;      ///< this frame's map; none: screen space
    const Image* valid = nullptr;           ///< the frame's traced texels (Visual-Polar)
    const Image* previous_valid = nullptr;  ///< the previous frame's (the TAA's history taps)
    /// The previous frame's map: the history buffers' layout, whose row counts the history's
    /// taps follow (they differ from this frame's under P5's moving staircase clip)
    std::optional<VisualPolarMap> previous_map;
    bool visual_polar() const { return map.has_value(); }
    /// The map of the history buffers: the previous frame's, else this frame's.
    const VisualPolarMap& history_map() const { return previous_map ? *previous_map : *map; }
};

/// What a frame hands on to the next one (all W x H).
struct BmfrHistory {
    bool valid = false;
    ViewProjection view_projection;     ///< the previous frame's camera
    std::optional<VisualPolarMap> map;  ///< Visual-Polar: the previous frame's map
    Image valid_texels;                 ///< Visual-Polar: its traced texels (1 channel)
    Image world_position;               ///< 3
    Image normal;                       ///< 3
    Image accumulated_noisy;            ///< 3: phase I's output
    Image spp;                          ///< 1: phase I's sample counts (1 .. 255)
    Image accumulated_filtered;         ///< 3: phase III's output
    Image taa;                          ///< 3: the TAA output (display space)
};

/// Counters of one frame (their names in the run's statistics in brackets).
struct BmfrStats {
    std::int64_t nonfinite_inputs = 0;     ///< [bmfr_nonfinite_inputs] values replaced by 0
    std::int64_t history_accepted = 0;     ///< [bmfr_history_accepted] pixels with history
    std::int64_t history_rejected = 0;     ///< [bmfr_history_rejected] reprojected, no tap
    std::int64_t history_off_screen = 0;   ///< [bmfr_history_off_screen] behind or outside
    std::int64_t blocks = 0;               ///< [bmfr_blocks] blocks fitted
    std::int64_t pivots_zeroed = 0;        ///< [bmfr_pivots_zeroed] |R_ii| < pivot_epsilon
    std::int64_t reflections_skipped = 0;  ///< [bmfr_reflections_skipped] |u|^2 = 0
    std::int64_t fit_nonfinite = 0;        ///< [bmfr_fit_nonfinite] sums set to 0
    std::int64_t taa_history_used = 0;     ///< [bmfr_taa_history_used]
};

// ---- demodulation -------------------------------------------------------------------------

/// illumination = radiance / max(albedo, floor) per channel, clamped to [-65504, 65504] (the
/// range the fit can store); a NaN or infinite radiance or albedo value is replaced by 0 first
/// (counted).
/// `emission` (empty: none) is subtracted from the radiance first (separate_emission).
/// `storage` (here and in the passes below that take it): an image the output is written into
/// when it has the output's shape (a stage's earlier frame's storage): every value is written,
/// none of its own is read; otherwise the output is made anew.
Image bmfr_demodulate(const BmfrParams& params, const Image& radiance, const Image& albedo,
                      const Image& emission, BmfrStats& stats, Image storage = {});

// ---- phase I --------------------------------------------------------------------------------

/// Phase I's outputs (W x H).
struct BmfrAccumulation {
    Image accumulated;  ///< 3: alpha current + (1 - alpha) history
    Image spp;          ///< 1: sample count after this frame
    Image accept;       ///< 1: bit k set when tap k was accepted (k as in bmfr_taps)
    /// 2: the reprojected pixel index; the pixel itself without a previous frame (Visual-Polar:
    /// (x, (y + 1/2) / n_x), BmfrSpace),
    /// bmfr_behind_camera when the point is behind the previous camera
    Image previous_pixel;
    /// 3 (`bmfr_accept_margin`, for `fovref diff`'s threshold decisions; written only when
    /// allocated): how far the pixel's accept decisions lay from their limits, over the taps
    /// inside the buffer the smallest |L^2 - d^2| / L^2 of the position test (channel 0) and of
    /// the normal test (1), and (screen space) the reprojected index's distance from the
    /// nearest integer, where the taps change (2); bmfr_no_margin where none was decided.
    Image accept_margin;
};

/// A margin of a decision a pixel did not make (BmfrAccumulation::accept_margin).
inline constexpr float bmfr_no_margin = 1e30f;

/// The reprojected pixel of a point behind the previous camera: off the image for every stage.
inline constexpr glm::vec2 bmfr_behind_camera{-2.0f, -2.0f};

/// The four bilinear taps around pixel index q: (x0, y0), (x0 + 1, y0), (x0, y0 + 1),
/// (x0 + 1, y0 + 1), x0 = floor(q.x), fx = q.x - x0, weights (1 - fx)(1 - fy), fx (1 - fy),
/// (1 - fx) fy, fx fy (q clamped to +-1e6 first).
struct BmfrTaps {
    int x[4], y[4];
    float w[4];
};
BmfrTaps bmfr_taps(glm::vec2 q);

/// The taps of a reprojected point q = (u - 1/2, t) in a Visual-Polar buffer (BmfrSpace): column
/// x0 = floor(q.x) with fx = q.x - x0, and x0 + 1; column c's rows y_c = floor(t n_c - 1/2) and
/// y_c + 1, both modulo n_c, fy_c the fraction; weights (1 - fx)(1 - fy_a), fx (1 - fy_b),
/// (1 - fx) fy_a, fx fy_b (a = x0, b = x0 + 1). A column outside [0, w) gives y = -1 (outside).
/// t is taken modulo 1 first (t - floor(t); not finite: 0).
BmfrTaps bmfr_vp_taps(const VisualPolarMap& map, glm::vec2 q);

/// Phase I (the authors' accumulate_noisy_data). Per pixel: project its world position with the
/// previous view-projection; tap k is accepted when it is inside the image,
/// |P_k - P|^2 < position_limit_squared and |n_k - n|^2 < normal_limit_squared (strict); the
/// accepted taps' colours and counts are averaged with their bilinear weights renormalised;
/// alpha = max(1 / (spp_h + 1), noisy_alpha_min), out = alpha c + (1 - alpha) h,
/// spp = min(round_half_even(spp_h) + 1, 255). No history (first frame, behind the camera, no
/// tap accepted or their weights sum to 0): out = c, spp = 1. A NaN or infinite position or
/// normal is taken as 0 (counted). `margins` false: accept_margin is left empty (not wanted).
/// `storage`: accumulated, spp, accept and previous_pixel written into, as bmfr_demodulate's.
BmfrAccumulation bmfr_accumulate_noisy(const BmfrParams& params, const Image& illumination,
                                       const Image& world_position, const Image& normal,
                                       const BmfrHistory& history, BmfrStats& stats,
                                       const BmfrSpace& space = {}, bool margins = true,
                                       BmfrAccumulation storage = {});
/// Per-pixel work of phase I: pixel (x, y) of `out` (whose images have the frame's size);
/// `has_previous`: the history holds a previous frame.
void bmfr_accumulate_noisy_pixel(const BmfrParams& params, const Image& illumination,
                                 const Image& world_position, const Image& normal,
                                 const BmfrHistory& history, bool has_previous,
                                 const BmfrSpace& space, BmfrAccumulation& out, int x, int y,
                                 BmfrStats& stats);

// ---- phase II -------------------------------------------------------------------------------

/// The features T_0..T_9 of one pixel: 1, n, w, w^2 (squares of the raw coordinates), NaN -> 0
/// and each clamped to [-65504, 65504].
void bmfr_features(glm::vec3 normal, glm::vec3 world, float t[bmfr_feature_count]);

/// A block's scaling of features 4..9: (v - min) / (max - min) when the range exceeds 1, else
/// v - min (SPEC §9 item 4).
float bmfr_scale_feature(float v, float lo, float hi);

/// The block grid of frame `frame` on a W x H image: (ceil(W/32) + 1) x (ceil(H/32) + 1) cells;
/// cell (i, j) covers pixels (32 i - 16 + o.x .. +31, 32 j - 16 + o.y .. +31), o the offset.
/// With a Visual-Polar map (BmfrSpace): cells_y = ceil(h / 32), cell column cx holds
/// cells_in_column(cx) = ceil(H_cx / 32) blocks, block (cx, cy) row r covers texel
/// (clamp(32 cx - 16 + o.x + r mod 32, 0, w - 1), (32 cy + o.y + r div 32) mod H_cx), and a
/// texel row at or beyond its column's n_c is no data.
struct BmfrGrid {
    int width = 0, height = 0;     ///< the image
    int cells_x = 0, cells_y = 0;  ///< the grid
    int block = bmfr_block_size;   ///< the block edge B (32 or 64; "32" above stands for B)
    glm::ivec2 offset{0};
    std::vector<int> column_rows;  ///< Visual-Polar: n_c per image column (empty: the screen)
    std::vector<int> cell_rows;    ///< Visual-Polar: H per cell column
    bool visual_polar() const { return !column_rows.empty(); }
    glm::ivec2 origin(int cell_x, int cell_y) const {
        return {cell_x * block - block / 2 + offset.x,
                visual_polar() ? cell_y * block + offset.y : cell_y * block - block / 2 + offset.y};
    }
    /// The cell that covers pixel (x, y).
    glm::ivec2 cell_of(int x, int y) const;
    /// The blocks of cell column cx (cells_y on the screen).
    int cells_in_column(int cell_x) const;
    /// The texel (x, y) behind row `row` of block (cell_x, cell_y): mirrored on the screen; false
    /// for a Visual-Polar row beyond its column's n_c (no data).
    bool source(int cell_x, int cell_y, int row, int& x, int& y) const;
};
/// `map`: the Visual-Polar grid of that buffer (width, height must be the map's). `block`: the
/// block edge B (32 or 64); the offset is the authors' times B / 32.
BmfrGrid bmfr_grid(int width, int height, int frame, const VisualPolarMap* map = nullptr,
                   int block = bmfr_block_size);

/// Mirrors a coordinate into [0, size): -1 -> 0, size -> size - 1, reflecting again as often
/// as needed (images narrower than a block).
int bmfr_mirror(int index, int size);

/// The fit of one block: the weights of the three colour channels and the range of the scaled
/// features (what the weighted sum needs to scale them identically).
struct BmfrBlockFit {
    float weights[3][bmfr_feature_count] = {};
    float feature_min[bmfr_scaled_count] = {};
    float feature_max[bmfr_scaled_count] = {};
    int pivots_zeroed = 0;
    int reflections_skipped = 0;
    int weights_nonfinite = 0;  ///< weights that overflowed (set to 0)
};

/// One block's B^2 x 13 matrix (1024 rows for the authors' 32 x 32 blocks) as the QR receives
/// it: row r = pixel_in_block r (row-major in the block), columns the scaled features with the
/// regularisation noise (features 1..9) and the three colour channels, in the storage
/// precision. Stride bmfr_matrix_stride floats per row. bmfr_gather_block sizes it to its grid's
/// blocks.
inline constexpr int bmfr_matrix_stride = 16;
struct BmfrBlockMatrix {
    int rows = bmfr_block_pixels;
    int data_rows = 0;  ///< rows with data (0: every value is 0, whatever the block)
    std::vector<float> a = std::vector<float>(bmfr_block_pixels * bmfr_matrix_stride, 0.0f);
    float feature_min[bmfr_scaled_count] = {};
    float feature_max[bmfr_scaled_count] = {};
    float& at(int row, int column) { return a[row * bmfr_matrix_stride + column]; }
    float at(int row, int column) const { return a[row * bmfr_matrix_stride + column]; }
};

/// Gathers block (cell_x, cell_y) of `grid` (mirrored borders) in the authors' order: every value
/// stored (storage precision); features 4..9 scaled with the block's min and max of the stored
/// values ((v - min) / (max - min) when max - min > 1, else v - min) and stored again; then the
/// noise 0.01 2 (r - 0.5) added in float to features 1..9, r = hash(s) / 4294967295.0f (the
/// params' noise_hash), s = pixel_in_block + feature 1024 + frame 13 1024 (`noise` false: none, for
/// tests). Visual-Polar: rows without data (grid.source false, or `valid` 0) are zero rows, left
/// out of the ranges and given no noise (a block without any data has ranges 0). `noise_table`
/// (optional): bmfr_noise_table of the frame (the same values, computed once for every block).
void bmfr_gather_block(const BmfrParams& params, const BmfrGrid& grid, int cell_x, int cell_y,
                       const Image& accumulated, const Image& world_position, const Image& normal,
                       int frame, bool noise, BmfrBlockMatrix& out, const Image* valid = nullptr,
                       const std::vector<float>* noise_table = nullptr);

/// The regularisation noise of every row (block_pixels of them) and feature 1..9 of frame
/// `frame`: [row * 9 + feature - 1] = bmfr_regularisation_noise(amount, hash, row, feature,
/// frame, block_pixels). The pattern is the same in every block, so the fit computes it once.
std::vector<float> bmfr_noise_table(float amount, BmfrNoiseHash hash, int frame, int block_pixels);

/// The work items of the authors' fitter kernel (their LOCAL_SIZE), for bmfr_sums=workgroup.
constexpr int bmfr_workgroup_size = 256;

/// The authors' parallel_reduction_sum of 256 float partial sums (bmfr.cl), in their order:
/// s_t += (s_t+64 + s_t+128) + s_t+192 for t < 64; s_t += (((s_t+8 + s_t+16) + s_t+24) + ...)
/// + s_t+56 for t < 8; the result (((s_0 + s_1) + s_2) + ...) + s_7.
float bmfr_workgroup_sum(const float* partial);

/// The augmented Householder QR of a gathered block and the back substitution (SPEC §9 item 7),
/// in place: columns 0..12, pivot row c = min(column, 10); s = sum over rows > c of x^2 and the
/// dot products d_j = u . a_j (rows >= c) in binary64, row order, rounded to float (or, with
/// bmfr_sums=workgroup, float products added by work item t = row mod 256 in row order, then
/// bmfr_workgroup_sum);
/// r = sqrt(s + x_c x_c), u_c = x_c - r, |u|^2 = s + u_c u_c; a_ij -= ((2 u_i) d_j) / |u|^2,
/// each updated value rounded to the storage precision; the column itself becomes r (float) at
/// row c and 0 below. |u|^2 = 0 leaves the columns as they are (counted for columns 0..9).
/// Weights from row 9 to 0 in the authors' order: w_i = b_i / R_ii - sum_{k > i} (R_ik w_k) / R_ii
/// (k ascending), 0 when |R_ii| < pivot_epsilon; a weight that overflows is 0 (counted).
BmfrBlockFit bmfr_solve_block(const BmfrParams& params, BmfrBlockMatrix& matrix);

/// The stochastic regularisation of feature `feature` (1..9) at block row `row`, frame `frame`
/// (the same in every block; SPEC §9 item 6): amount * 2 * (r - 1/2), r = hash(row + feature
/// P + frame 13 P) / 4294967295.0f, in binary32 in that order; P = the block's pixels (1024).
float bmfr_regularisation_noise(float amount, BmfrNoiseHash hash, int row, int feature, int frame,
                                int block_pixels = bmfr_block_pixels);

/// Phase II's fit (the authors' fit kernel) over every block of the frame's grid. Outputs, one
/// texel per block (cells_x x cells_y): weights (30 channels: red w_0..w_9, green, blue) and the
/// feature ranges (12: min of features 4..9, then their max).
struct BmfrFit {
    BmfrGrid grid;
    Image weights;
    Image feature_range;
};
BmfrFit bmfr_fit(const BmfrParams& params, const Image& accumulated, const Image& world_position,
                 const Image& normal, int frame, BmfrStats& stats, const BmfrSpace& space = {});

/// Phase II's weighted sum: each pixel takes its grid cell's weights and feature ranges,
/// evaluates sum_{i=0..9} w_i T_i (i ascending, noise-free features, scaled as in the fit), and
/// clamps each channel at 0 from below (a sum that overflows to infinity gives 0, counted).
Image bmfr_weighted_sum(const BmfrFit& fit, const Image& world_position, const Image& normal,
                        BmfrStats& stats, const Image* valid = nullptr);
/// Per-pixel work of the weighted sum: pixel (x, y) of `out` (W x H x 3), from its cell's fit.
void bmfr_weighted_sum_pixel(const BmfrFit& fit, const Image& world_position, const Image& normal,
                             Image& out, int x, int y, BmfrStats& stats);

// ---- phase III, remodulation, TAA -----------------------------------------------------------

/// Phase III: the fit blended with the previous phase III output `history` (empty: none),
/// through phase I's accepted taps (its accept mask and reprojected pixel);
/// alpha = max(1 / spp, filtered_alpha_min), out = alpha fit + (1 - alpha) history.
Image bmfr_accumulate_filtered(const BmfrParams& params, const Image& fitted, const Image& spp,
                               const Image& accept, const Image& previous_pixel,
                               const Image& history, const BmfrSpace& space = {},
                               Image storage = {});
/// Per-pixel work of phase III: pixel (x, y) of `out` (W x H x 3).
void bmfr_accumulate_filtered_pixel(const BmfrParams& params, const Image& fitted, const Image& spp,
                                    const Image& accept, const Image& previous_pixel,
                                    const Image& history, const BmfrSpace& space, Image& out, int x,
                                    int y);

/// display = clamp((max(albedo, floor) max(0, x) + e)^(1/2.2), 0, 1) per channel, e the emission
/// (empty: 0).
Image bmfr_remodulate(const BmfrParams& params, const Image& filtered, const Image& albedo,
                      const Image& emission, Image storage = {});

/// The authors' TAA in display space (SPEC §9 item 10): 3x3 neighbourhood in unnormalised
/// YCoCg (Y = R + 2G + B, Co = 2R - 2B, Cg = -R + 2G - B; neighbours outside the image are
/// skipped), min/max = (box extent + cross extent) 0.5; the history sampled bilinearly at phase
/// I's reprojected pixel q (taps outside the image dropped, weights renormalised), clamped, back
/// to RGB (R = ((Y + Co) - Cg) / 4, G = (Y + Cg) / 4, B = ((Y - Co) - Cg) / 4);
/// out = 0.2 new + 0.8 history. The new colour alone on the first frame, when floor(q) lies
/// outside [-1, W - 1] x [-1, H - 1] (the authors' test; behind the camera included), or when
/// the taps inside have no weight.
/// `history` is the previous TAA output (empty: none).
/// Visual-Polar (BmfrSpace): untraced texels keep their value; the neighbourhood of (x, y) in
/// column x + dx is row floor(t n_(x+dx)) + dy modulo n_(x+dx) with t = (y + 1/2) / n_x
/// (traced texels only); the reprojection is on the buffer when floor(q.x) lies in [-1, w - 1];
/// the history's taps are bmfr_vp_taps on traced texels of the previous frame.
Image bmfr_taa(const BmfrParams& params, const Image& display, const Image& previous_pixel,
               const Image& history, BmfrStats& stats, const BmfrSpace& space = {},
               Image storage = {});
/// `display` in unnormalised YCoCg, per pixel (what the TAA's neighbourhoods read).
Image bmfr_ycocg(const Image& display);
/// Per-pixel work of the TAA: pixel (x, y) of `out` (W x H x 3); `ycocg` = bmfr_ycocg(display)
/// (unused without history). True when the history was blended in.
bool bmfr_taa_pixel(const BmfrParams& params, const Image& display, const Image& ycocg,
                    const Image& previous_pixel, const Image& history, const BmfrSpace& space,
                    Image& out, int x, int y);

/// The linear value of a display-space output: x^2.2 (the `final` buffer of a denoised frame).
Image bmfr_linearize(const Image& display, Image storage = {});

// ---- the whole frame ------------------------------------------------------------------------

/// Every buffer of one denoised frame, in phase order.
struct BmfrFrame {
    Image illumination;
    BmfrAccumulation accumulation;
    BmfrFit fit;
    Image fitted;
    Image filtered;
    Image display;
    Image taa;
    Image output;  ///< linear (bmfr_linearize of taa)
};

/// Runs every phase on one frame and hands on its history (`history` is read, then replaced).
/// Inputs are W x H: radiance, albedo, normal and world position (3 channels each), and the
/// directly seen emission (empty: none; used when params.separate_emission).
/// `space`: the Visual-Polar variant (its map and valid mask; previous_valid is taken from the
/// history).
BmfrFrame bmfr_denoise_frame(const BmfrParams& params, const Image& radiance, const Image& albedo,
                             const Image& emission, const Image& normal,
                             const Image& world_position, const ViewProjection& camera, int frame,
                             BmfrHistory& history, BmfrStats& stats, const BmfrSpace& space = {});

/// The history a denoised frame hands on (its camera, G-buffer and accumulations).
BmfrHistory bmfr_next_history(const BmfrFrame& frame, const Image& world_position,
                              const Image& normal, const ViewProjection& camera,
                              const BmfrSpace& space = {});

}  // namespace fovref
