#include "ref/visual_polar/map.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

float vp_acuity(float e) {
    if (e <= 5.79f) return 1.0f;
    const float d = 0.3f * e + 1.0f;
    return 7.49f / (d * d);
}

float vp_inverse_cdf(float u) {
    if (u <= vp_u0) return 18.64f * std::sqrt(std::max(u, 0.0f));
    return (((25.09f * u + 0.1680f) * u + 27.61f) * u + 23.87f) * u + 3.232f;
}

namespace {

// P at the dyadic points k / 65536, k = 0 .. 65536: the first 16 midpoints of the bisection.
constexpr int cdf_table_bits = 16;
const std::vector<float>& cdf_table() {
    static const std::vector<float> table = [] {
        std::vector<float> t;
        for (int k = 0; k <= (1 << cdf_table_bits); ++k)
            t.push_back(
                vp_inverse_cdf(static_cast<float>(k) / static_cast<float>(1 << cdf_table_bits)));
        return t;
    }();
    return table;
}

}  // namespace

namespace {

/// The bisection of vp_cdf from its first 16 steps' bracket [lo_k, hi_k] / 65536 on.
float bisect_cdf(float e, int lo_k, int hi_k) {
    constexpr float scale = 1.0f / static_cast<float>(1 << cdf_table_bits);
    float lo = static_cast<float>(lo_k) * scale, hi = static_cast<float>(hi_k) * scale;
    for (int step = cdf_table_bits; step < 64; ++step) {
        const float mid = 0.5f * (lo + hi);
        if (mid == lo || mid == hi) break;
        (vp_inverse_cdf(mid) < e ? lo : hi) = mid;
    }
    return 0.5f * (lo + hi);
}

/// Halves [lo_k, hi_k] (P(lo_k / 65536) < e <= P(hi_k / 65536)) on the table's values until
/// hi_k = lo_k + 1: from [0, 65536], the bisection's first 16 steps.
void narrow_bracket(float e, int& lo_k, int& hi_k) {
    const std::vector<float>& table = cdf_table();
    while (hi_k - lo_k > 1) {
        const int mid = (lo_k + hi_k) / 2;
        (table[static_cast<std::size_t>(mid)] < e ? lo_k : hi_k) = mid;
    }
}

/// The first 16 steps of the bisection (vp_cdf's table): lo_k, hi_k with P(lo_k / 65536) < e
/// <= P(hi_k / 65536) (0 < e < P(1)).
void table_bracket(float e, int& lo_k, int& hi_k) {
    lo_k = 0, hi_k = 1 << cdf_table_bits;
    narrow_bracket(e, lo_k, hi_k);
}

}  // namespace

float vp_cdf_bisection(float e) {
    if (!(e > 0.0f)) return 0.0f;
    if (e >= vp_inverse_cdf(1.0f)) return 1.0f;
    int lo_k = 0, hi_k = 0;
    table_bracket(e, lo_k, hi_k);
    return bisect_cdf(e, lo_k, hi_k);
}

namespace {

// vp_cdf's way into the table: e's bucket b = floor(e * buckets / P(1)) (binary64) gives a
// bracket [lo_b, hi_b] of table indices with P(lo_b / 65536) < e <= P(hi_b / 65536) for every e of
// the bucket (bounds taken half a bucket wider than the bucket); the search then runs on the few
// indices in between. P is non-decreasing, so this ends at the same (lo_k, lo_k + 1) as
// table_bracket's 16 steps from [0, 65536]: lo_k is the largest k with P(k / 65536) < e.
constexpr int cdf_bucket_count = 16384;
struct CdfBuckets {
    double scale = 0.0;  // buckets per degree
    std::vector<int> lo, hi;
};

const CdfBuckets& cdf_buckets() {
    static const CdfBuckets buckets = [] {
        const std::vector<float>& table = cdf_table();
        const int last = 1 << cdf_table_bits;
        CdfBuckets b;
        b.scale = static_cast<double>(cdf_bucket_count) / static_cast<double>(table.back());
        b.lo.resize(cdf_bucket_count);
        b.hi.resize(cdf_bucket_count);
        int lo = 0, hi = 0;
        for (int k = 0; k < cdf_bucket_count; ++k) {
            const double e_lo = (static_cast<double>(k) - 0.5) / b.scale;
            const double e_hi = (static_cast<double>(k) + 1.5) / b.scale;
            while (lo + 1 <= last && static_cast<double>(table[lo + 1]) < e_lo) ++lo;
            while (hi < last && static_cast<double>(table[hi]) < e_hi) ++hi;
            b.lo[static_cast<std::size_t>(k)] = lo;  // 0, or P(lo / 65536) < e_lo
            b.hi[static_cast<std::size_t>(k)] = hi;  // 65536, or P(hi / 65536) >= e_hi
        }
        return b;
    }();
    return buckets;
}

// The lanes' guess of P^-1 (vp_cdf_tables): per guess bucket of e, a quadratic through P^-1 at
// its ends and middle, P^-1 in binary64 by bisection on P's formulas in binary64.
constexpr int guess_bucket_count = 4096;
const std::vector<float>& guess_table() {
    static const std::vector<float> table = [] {
        // P's formulas with its binary32 constants, in binary64
        const auto p = [](double u) {
            const auto c = [](float v) { return static_cast<double>(v); };
            if (u <= c(vp_u0)) return c(18.64f) * std::sqrt(u);
            return (((c(25.09f) * u + c(0.1680f)) * u + c(27.61f)) * u + c(23.87f)) * u + c(3.232f);
        };
        const auto inverse = [&](double e) {
            double lo = 0.0, hi = 1.0;
            for (int step = 0; step < 60; ++step)
                (p(0.5 * (lo + hi)) < e ? lo : hi) = 0.5 * (lo + hi);
            return 0.5 * (lo + hi);
        };
        const double width = static_cast<double>(vp_inverse_cdf(1.0f)) / guess_bucket_count;
        // P jumps up at u0 (its two branches differ there): the bucket holding the jump is fitted
        // above it, where its e is searched (below lies the fovea)
        const double jump = p(std::nextafter(static_cast<double>(vp_u0), 1.0));
        std::vector<float> t;
        t.reserve(4 * guess_bucket_count);
        for (int k = 0; k < guess_bucket_count; ++k) {
            const bool jumps = k * width < jump && jump < (k + 1) * width;
            const double start = jumps ? jump : k * width;
            const double half = 0.5 * ((k + 1) * width - start), middle = start + half;
            const double u0 = inverse(middle - half), uc = inverse(middle),
                         u1 = inverse(middle + half);
            t.insert(t.end(), {static_cast<float>(middle), static_cast<float>(uc),
                               static_cast<float>((u1 - u0) / (2.0 * half)),
                               static_cast<float>((u1 - 2.0 * uc + u0) / (2.0 * half * half))});
        }
        return t;
    }();
    return table;
}

// The float after and before a finite float u > 0.
float next_up(float u) { return std::bit_cast<float>(std::bit_cast<std::uint32_t>(u) + 1u); }
float next_down(float u) { return std::bit_cast<float>(std::bit_cast<std::uint32_t>(u) - 1u); }

}  // namespace

VpCdfTables vp_cdf_tables() {
    return {cdf_table(),
            static_cast<float>(guess_bucket_count / static_cast<double>(vp_inverse_cdf(1.0f))),
            guess_table()};
}

float vp_cdf(float e) {
    if (!(e > 0.0f)) return 0.0f;
    if (e >= vp_inverse_cdf(1.0f)) return 1.0f;
    // table_bracket's result through e's bucket
    const std::vector<float>& table = cdf_table();
    const CdfBuckets& buckets = cdf_buckets();
    const auto b = static_cast<std::size_t>(
        std::min(static_cast<int>(static_cast<double>(e) * buckets.scale), cdf_bucket_count - 1));
    int lo_k = buckets.lo[b], hi_k = buckets.hi[b];
    narrow_bracket(e, lo_k, hi_k);
    if (lo_k >= 1) {
        // The bracket's floats are at least 2^-39 apart, so the bisection reaches adjacent
        // floats within its 48 remaining steps: it ends at the largest float u of [lo, hi) with
        // P(u) < e (P non-decreasing), which a guess reaches by moves of one float.
        constexpr float scale = 1.0f / static_cast<float>(1 << cdf_table_bits);
        const float lo = static_cast<float>(lo_k) * scale, hi = static_cast<float>(hi_k) * scale;
        const float p_lo = table[static_cast<std::size_t>(lo_k)];
        const float p_hi = table[static_cast<std::size_t>(hi_k)];
        const float last = next_down(hi);  // the bracket's largest float below hi
        float u = std::clamp(lo + (hi - lo) * ((e - p_lo) / (p_hi - p_lo)), lo, last);
        for (int move = 0; move < 8; ++move) {
            if (!(vp_inverse_cdf(u) < e)) {
                u = next_down(u);  // u > lo: P(lo) < e
                continue;
            }
            const float next = next_up(u);
            if (vp_inverse_cdf(next) < e) {
                u = next;  // next < hi: P(hi) >= e
                continue;
            }
            return 0.5f * (u + next);
        }
    }
    return bisect_cdf(e, lo_k, hi_k);
}

glm::ivec2 visual_polar_buffer_size(int screen_width, int screen_height) {
    return {static_cast<int>(std::lround(screen_width / 1.5)),
            static_cast<int>(std::lround(screen_height / 1.5))};
}

VisualPolarMap vp_log_polar_map(const LogPolarMap& map) {
    VisualPolarMap m;
    m.screen_width = map.screen_width;
    m.screen_height = map.screen_height;
    m.gaze = map.gaze;
    m.width = map.width;
    m.height = map.height;
    m.log_polar = map;
    return m;
}

VisualPolarMap make_visual_polar_map(int screen_width, int screen_height, glm::vec2 gaze, int width,
                                     int height) {
    if (screen_width < 1 || screen_height < 1 || width < 2 || height < 1)
        throw Error("visual-polar: the screen must be at least 1x1 and the buffer 2x1 (got " +
                    std::to_string(width) + "x" + std::to_string(height) + ")");
    if (!std::isfinite(gaze.x) || !std::isfinite(gaze.y))
        throw Error("visual-polar: the gaze is not finite");
    VisualPolarMap m;
    m.screen_width = screen_width;
    m.screen_height = screen_height;
    m.gaze = gaze;
    m.width = width;
    m.height = height;
    m.fovea_columns = std::clamp(static_cast<int>(std::lround(0.24 * width)), 1, width - 1);
    // R: the farthest corner from the gaze
    float r2 = 0.0f;
    for (const glm::vec2& corner :
         {glm::vec2(0.0f), glm::vec2(static_cast<float>(screen_width), 0.0f),
          glm::vec2(0.0f, static_cast<float>(screen_height)),
          glm::vec2(static_cast<float>(screen_width), static_cast<float>(screen_height))}) {
        const glm::vec2 d = corner - gaze;
        r2 = std::max(r2, d.x * d.x + d.y * d.y);
    }
    m.scale = std::sqrt(r2) / vp_inverse_cdf(1.0f);
    m.fovea_radius = m.scale * vp_inverse_cdf(vp_u0);
    return m;
}

int vp_triangle_rows(const VisualPolarMap& m, int i) {
    if (i >= m.fovea_columns) return m.height;
    const float t = static_cast<float>(m.height) * (static_cast<float>(i) + 0.5f) /
                        static_cast<float>(m.fovea_columns) -
                    0.5f;
    return std::clamp(static_cast<int>(std::ceil(t)), 1, m.height);
}

int vp_fovea_column_rows(const VisualPolarMap& m, int i) {
    if (m.staircase_block <= 0 || i >= m.fovea_columns) return vp_triangle_rows(m, i);
    // The block column of i (BMFR's grid: x + B/2 - o >= 0 for |o| <= B/2) and its last column
    // in the buffer, where the (nondecreasing) triangle is largest
    const int b = m.staircase_block;
    const int cell = (i + b / 2 - m.staircase_offset) / b;
    return vp_triangle_rows(m, std::min(cell * b + b / 2 - 1 + m.staircase_offset, m.width - 1));
}

bool VisualPolarMap::same_forward(const VisualPolarMap& o) const {
    return screen_width == o.screen_width && screen_height == o.screen_height && gaze == o.gaze &&
           width == o.width && height == o.height && fovea_columns == o.fovea_columns &&
           scale == o.scale && fovea_radius == o.fovea_radius && log_polar == o.log_polar;
}

float vp_column_radius(const VisualPolarMap& m, int i) {
    const float centre = static_cast<float>(i) + 0.5f;
    if (i < m.fovea_columns) return m.fovea_radius * centre / static_cast<float>(m.fovea_columns);
    const float rho = centre / static_cast<float>(m.width);
    const float rho_f = static_cast<float>(m.fovea_columns) / static_cast<float>(m.width);
    const float u = vp_u0 + (rho - rho_f) * (1.0f - vp_u0) / (1.0f - rho_f);
    return m.scale * vp_inverse_cdf(u);
}

bool vp_inverse(const VisualPolarMap& m, int i, int j, glm::vec2& screen) {
    if (m.log_polar) {
        if (j < 0 || j >= m.height) return false;
        screen =
            lp_inverse(*m.log_polar, {static_cast<float>(i) + 0.5f, static_cast<float>(j) + 0.5f});
        return true;
    }
    const int rows = vp_column_rows(m, i);
    if (j >= rows) return false;
    const float theta = vp_row_angle(j, rows);
    screen = vp_texel_point(m, vp_column_radius(m, i), dm::cos(theta), dm::sin(theta));
    return true;
}

float vp_row_angle(int row, int rows) {
    return dm::two_pi * (static_cast<float>(row) + 0.5f) / static_cast<float>(rows);
}

VpRowAngles::VpRowAngles(int rows) : cosine(static_cast<std::size_t>(rows)), sine(cosine.size()) {
    for (int j = 0; j < rows; ++j) {
        const float theta = vp_row_angle(j, rows);
        cosine[static_cast<std::size_t>(j)] = dm::cos(theta);
        sine[static_cast<std::size_t>(j)] = dm::sin(theta);
    }
}

float vp_forward_radius(const VisualPolarMap& m, float r) {
    if (r < m.fovea_radius) return static_cast<float>(m.fovea_columns) * r / m.fovea_radius;
    const float big_u = vp_cdf(r / m.scale);
    const float rho_f = static_cast<float>(m.fovea_columns) / static_cast<float>(m.width);
    const float rho = rho_f + (big_u - vp_u0) * (1.0f - rho_f) / (1.0f - vp_u0);
    return static_cast<float>(m.width) * rho;
}

void vp_polar(const VisualPolarMap& m, glm::vec2 p, float& r, float& theta) {
    const float dx = p.x - m.gaze.x, dy = p.y - m.gaze.y;
    r = std::sqrt(dx * dx + dy * dy);
    theta = dm::atan2(dy, dx);
    if (theta < 0.0f) theta += dm::two_pi;
}

glm::vec2 vp_forward(const VisualPolarMap& m, glm::vec2 p) {
    if (m.log_polar) return lp_forward(*m.log_polar, p);
    float r = 0.0f, theta = 0.0f;
    vp_polar(m, p, r, theta);
    const float u = vp_forward_radius(m, r);
    if (r < m.fovea_radius) {
        const int column = std::min(static_cast<int>(u), m.fovea_columns - 1);
        return {u, static_cast<float>(vp_column_rows(m, column)) * theta / dm::two_pi};
    }
    return {u, static_cast<float>(m.height) * theta / dm::two_pi};
}

glm::vec2 vp_forward_angle(const VisualPolarMap& m, glm::vec2 p) {
    if (m.log_polar) {
        const glm::vec2 uv = lp_forward(*m.log_polar, p);
        return {uv.x, uv.y / static_cast<float>(m.height)};
    }
    float r = 0.0f, theta = 0.0f;
    vp_polar(m, p, r, theta);
    return {vp_forward_radius(m, r), theta / dm::two_pi};
}

VpTexel vp_texel_status(const VisualPolarMap& m, int i, int j, glm::vec2& p) {
    if (!vp_inverse(m, i, j, p)) return VpTexel::clipped;
    if (!vp_on_screen(m, p)) return VpTexel::off_screen;
    return VpTexel::traced;
}

VisualPolarCounts vp_count_texels(const VisualPolarMap& m) {
    VisualPolarCounts c;
    for (int i = 0; i < m.width; ++i)
        for (int j = 0; j < m.height; ++j) {
            ++c.texels;
            glm::vec2 p;
            const VpTexel status = vp_texel_status(m, i, j, p);
            ++(status == VpTexel::clipped      ? c.clipped
               : status == VpTexel::off_screen ? c.off_screen
                                               : c.traced);
        }
    return c;
}

BlurRampGeometry blur_ramp_geometry(const VisualPolarMap& map) {
    return {map.screen_width, map.screen_height, map.gaze, map.scale, vp_inverse_cdf(vp_u0)};
}

}  // namespace fovref
