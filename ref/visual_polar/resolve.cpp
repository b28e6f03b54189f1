#include "ref/visual_polar/resolve.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/visual_polar/map_avx.h"
#include "ref/visual_polar/resolve_avx.h"

namespace fovref {

namespace {

constexpr float two_pi = 6.28318530717958647692f;
constexpr int max_channels = 4;  // the per-pixel scratch arrays below

float lerp(float a, float b, float t) { return a + t * (b - a); }

/// Texel (i, j) of level k + 1 from level k, whose column i has n rows (j < ceil(n / 2)).
void downsample_texel(const Image& color, const Image& valid, int n, int i, int j, Image& color_out,
                      Image& valid_out) {
    const int channels = color.channels;
    // A column of one row: carried down unchanged.
    if (n == 1) {
        valid_out.at(i, 0) = valid.at(i, 0) != 0.0f ? 1.0f : 0.0f;
        if (valid_out.at(i, 0) != 0.0f)
            for (int c = 0; c < channels; ++c) color_out.at(i, 0, c) = color.at(i, 0, c);
        return;
    }
    // Rows 2j and (2j + 1) mod n, as a running mean over the traced ones.
    const int taps[2] = {2 * j, (2 * j + 1) % n};
    float* mean = &color_out.at(i, j, 0);
    int count = 0;
    for (const int row : taps) {
        if (valid.at(i, row) == 0.0f) continue;
        ++count;
        for (int c = 0; c < channels; ++c)
            mean[c] += (color.at(i, row, c) - mean[c]) / static_cast<float>(count);
    }
    if (count > 0) valid_out.at(i, j) = 1.0f;
}

/// Level k + 1 of the pyramid from level k (`rows_k[i]`: column i's rows at level k), row by row;
/// eight columns at a time where the AVX2 path covers them (the same bits: resolve_avx.h).
void downsample_phi(const Image& color, const Image& valid, const std::vector<int>& rows_k,
                    Image& color_out, Image& valid_out) {
    const int w = color.width, channels = color.channels;
    const int h_out = (color.height + 1) / 2;
    color_out = Image(w, h_out, channels, 0.0f);
    valid_out = Image(w, h_out, 1, 0.0f);
    const bool avx = downsample_avx_applies(color, valid);
    for (int j = 0; j < h_out; ++j)
        for (int i = 0; i < w; ++i) {
            if (avx && i + 8 <= w) {
                const int done =
                    downsample_group_avx(color, valid, rows_k, i, j, color_out, valid_out);
                if (done > 0) {
                    i += done - 1;
                    continue;
                }
            }
            const int n = rows_k[static_cast<std::size_t>(i)];
            if (j < (n + 1) / 2) downsample_texel(color, valid, n, i, j, color_out, valid_out);
        }
}

/// The value of one column for a pixel: levels floor(lambda) and floor(lambda) + 1 lerped.
bool sample_column(const VpMips& mips, int column, float v, float lambda, int channels,
                   float* out) {
    const int rows0 = mips.column_rows[static_cast<std::size_t>(column)];
    const int last = vp_mip_last_level(rows0);
    const int l0 = static_cast<int>(std::floor(lambda));
    const int l1 = std::min(l0 + 1, last);
    const float f = lambda - static_cast<float>(l0);
    float a[max_channels] = {0, 0, 0, 0}, b[max_channels] = {0, 0, 0, 0};
    const auto sample = [&](int level, float* value) {
        const float scale = 1.0f / static_cast<float>(1 << level);  // exact: 2^-level
        const std::size_t k = static_cast<std::size_t>(level);
        return sample_vp_phi(mips.color[k], mips.valid[k], column, vp_mip_rows(rows0, level),
                             v * scale, value);
    };
    const bool have_a = sample(l0, a);
    const bool have_b = l1 != l0 && f > 0.0f && sample(l1, b);
    for (int c = 0; c < channels; ++c) {
        if (have_a && have_b)
            out[c] = lerp(a[c], b[c], f);
        else if (have_a)
            out[c] = a[c];
        else
            out[c] = b[c];
    }
    return have_a || have_b;
}

/// Every row: eight pixels at a time in AVX2 lanes (resolve_vp_row_avx, the same bits), the last
/// W mod 8 pixels by resolve_vp_pixel, the reference.
void resolve_rows(const VisualPolarMap& map, VpMipsSource& mips, const VpResolveAvxInputs& in,
                  bool mip, const VpForwardTable* table, Image& out, ResolveStats& stats) {
    for (int y = 0; y < map.screen_height; ++y)
        for (int x = resolve_vp_row_avx(map, mips, in, *table, mip, out, y, stats);
             x < map.screen_width; ++x)
            resolve_vp_pixel(map, mips.get(), out, x, y, stats, nullptr, mip, table);
}

}  // namespace

int vp_mip_rows(int rows, int level) {
    for (int k = 0; k < level; ++k) rows = (rows + 1) / 2;
    return rows;
}

int vp_mip_last_level(int rows) {
    int level = 0;
    for (; rows > 1; ++level) rows = (rows + 1) / 2;
    return level;
}

int vp_mip_levels(const VisualPolarMap& map) {
    int max_rows = 1;
    for (int i = 0; i < map.width; ++i) max_rows = std::max(max_rows, vp_column_rows(map, i));
    return vp_mip_last_level(max_rows) + 1;
}

int vp_mip_column_rows(const VpMips& mips, int column, int level) {
    return vp_mip_rows(mips.column_rows[static_cast<std::size_t>(column)], level);
}

VpMips build_vp_mips(const VisualPolarMap& map, const Image& color, const Image& valid) {
    FOVREF_CHECK_EQ(color.width, map.width, "visual-polar buffer width");
    FOVREF_CHECK_EQ(color.height, map.height, "visual-polar buffer height");
    FOVREF_CHECK_EQ(valid.width, map.width, "validity mask width");
    FOVREF_CHECK_EQ(valid.height, map.height, "validity mask height");
    FOVREF_CHECK_EQ(valid.channels, 1, "validity mask channels");
    FOVREF_CHECK(color.channels >= 1 && color.channels <= max_channels,
                 "a visual-polar pyramid of 1 to 4 channels");
    VpMips mips;
    mips.column_rows.resize(static_cast<std::size_t>(map.width));
    int max_rows = 1;
    for (int i = 0; i < map.width; ++i) {
        mips.column_rows[static_cast<std::size_t>(i)] = vp_column_rows(map, i);
        max_rows = std::max(max_rows, vp_column_rows(map, i));
    }
    mips.color.push_back(color);
    mips.valid.push_back(valid);
    std::vector<int> rows_k = mips.column_rows;
    for (int level = 0; level < vp_mip_last_level(max_rows); ++level) {
        Image color_next, valid_next;
        downsample_phi(mips.color.back(), mips.valid.back(), rows_k, color_next, valid_next);
        mips.color.push_back(std::move(color_next));
        mips.valid.push_back(std::move(valid_next));
        for (int& n : rows_k) n = (n + 1) / 2;
    }
    return mips;
}

float vp_mip_lambda(int rows, float radius) {
    const float r = std::max(radius, 0x1p-10f);
    return dm::log2(static_cast<float>(rows) / (two_pi * r));
}

float vp_mip_level(int rows, float radius) {
    return std::clamp(vp_mip_lambda(rows, radius), 0.0f,
                      static_cast<float>(vp_mip_last_level(rows)));
}

VpColumns vp_rho_columns(int width, float u) {
    VpColumns c;
    const float s = std::clamp(u, 0.5f, static_cast<float>(width) - 0.5f) - 0.5f;
    const float i0f = std::floor(s);
    c.i0 = static_cast<int>(i0f);
    c.i1 = std::min(c.i0 + 1, width - 1);
    c.fx = s - i0f;
    c.count = c.i1 != c.i0 && c.fx > 0.0f ? 2 : 1;
    return c;
}

VpRows vp_phi_rows(int rows, float v) {
    VpRows r;
    const float t = v - 0.5f;
    const float j0f = std::floor(t);
    r.fv = t - j0f;
    r.j0 = vp_wrap_row(static_cast<int>(j0f), rows);
    r.j1 = r.j0 + 1 == rows ? 0 : r.j0 + 1;
    return r;
}

bool sample_vp_phi(const Image& color, const Image& valid, int column, int rows, float v,
                   float* out) {
    const int channels = color.channels;
    // v lies in [0, rows] for the lookups of resolve_vp_pixel; anything within one turn of
    // that is wrapped the same way, anything else is a caller's bug.
    FOVREF_CHECK(v >= -static_cast<float>(rows) && v <= 2.0f * static_cast<float>(rows),
                 "a phi lookup outside the column's angular range");
    const VpRows phi = vp_phi_rows(rows, v);
    const int j0 = phi.j0, j1 = phi.j1;
    const float fv = phi.fv;
    const bool traced0 = valid.at(column, j0) != 0.0f;               // weight 1 - fv > 0
    const bool traced1 = fv > 0.0f && valid.at(column, j1) != 0.0f;  // weight fv
    for (int c = 0; c < channels; ++c) {
        if (traced0 && traced1)
            out[c] = lerp(color.at(column, j0, c), color.at(column, j1, c), fv);
        else if (traced0)
            out[c] = color.at(column, j0, c);
        else if (traced1)
            out[c] = color.at(column, j1, c);
        else
            out[c] = 0.0f;
    }
    return traced0 || traced1;
}

void vp_polar_pixel(const VisualPolarMap& map, int x, int y, float& u, float& r, float& theta) {
    vp_polar(map, pixel_centre(x, y), r, theta);
    u = vp_forward_radius(map, r);
}

VpForwardTable vp_forward_table(const VisualPolarMap& map) {
    VpForwardTable t;
    t.map = map;
    const int width = map.screen_width;
    t.polar = Image(width, map.screen_height, 3);
    t.levels = Image(width, map.screen_height, 4);
    // Each buffer column's rows and last level
    std::vector<int> rows(static_cast<std::size_t>(map.width)), last(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rows[i] = vp_column_rows(map, static_cast<int>(i));
        last[i] = vp_mip_last_level(rows[i]);
    }
    // Row by row: vp_polar_pixel eight pixels at a time (vp_polar_span, the same bits), then
    // vp_mip_level of both columns with the logarithms of the row at once (dm::log2_array)
    const auto w = static_cast<std::size_t>(width);
    std::vector<float> u(w), r(w), theta(w), px(w), py(w);
    std::vector<float> arguments[2] = {std::vector<float>(w), std::vector<float>(w)};
    std::vector<float> lambdas[2] = {std::vector<float>(w), std::vector<float>(w)};
    std::vector<int> columns[2] = {std::vector<int>(w), std::vector<int>(w)};
    int* const column[2] = {columns[0].data(), columns[1].data()};
    float* const argument[2] = {arguments[0].data(), arguments[1].data()};
    std::vector<float> second_arguments, second_lambdas;  // where the two columns' differ
    std::vector<std::size_t> second;
    for (std::size_t x = 0; x < w; ++x) px[x] = static_cast<float>(x) + 0.5f;
    for (int y = 0; y < map.screen_height; ++y) {
        std::fill(py.begin(), py.end(), static_cast<float>(y) + 0.5f);
        vp_polar_span(map, px.data(), py.data(), w, u.data(), r.data(), theta.data());
        // the columns and the logarithms' arguments: eight at a time (the same bits), the rest
        const std::size_t done =
            vp_table_arguments_avx(map.width, rows.data(), u.data(), r.data(), w, column, argument);
        for (std::size_t x = 0; x < w; ++x) {
            float* p = &t.polar.data[t.polar.index(static_cast<int>(x), y)];
            p[0] = u[x], p[1] = r[x], p[2] = theta[x];
            if (x < done) continue;
            const VpColumns rho = vp_rho_columns(map.width, u[x]);
            // vp_mip_lambda's argument: rows / (2 pi max(r, 2^-10))
            const float radius = std::max(r[x], 0x1p-10f);
            for (int k = 0; k < 2; ++k) {
                const int i = k == 0 ? rho.i0 : rho.i1;
                column[k][x] = i;
                argument[k][x] =
                    static_cast<float>(rows[static_cast<std::size_t>(i)]) / (two_pi * radius);
            }
        }
        // The second column's logarithm is the first's where their arguments have the same bits
        // (both columns have h rows: the periphery); only the others are computed
        dm::log2_array(argument[0], lambdas[0].data(), w);
        second.clear(), second_arguments.clear();
        for (std::size_t x = 0; x < w; ++x) {
            if (std::bit_cast<std::uint32_t>(argument[1][x]) ==
                std::bit_cast<std::uint32_t>(argument[0][x])) {
                lambdas[1][x] = lambdas[0][x];
                continue;
            }
            second.push_back(x);
            second_arguments.push_back(argument[1][x]);
        }
        second_lambdas.resize(second.size());
        dm::log2_array(second_arguments.data(), second_lambdas.data(), second.size());
        for (std::size_t k = 0; k < second.size(); ++k) lambdas[1][second[k]] = second_lambdas[k];
        for (std::size_t x = 0; x < w; ++x) {
            float* level = &t.levels.data[t.levels.index(static_cast<int>(x), y)];
            for (int k = 0; k < 2; ++k) {  // vp_mip_level: lambda clamped to [0, last level]
                const auto i = static_cast<std::size_t>(column[k][x]);
                level[2 * k] = static_cast<float>(rows[i]);
                level[2 * k + 1] = std::clamp(lambdas[k][x], 0.0f, static_cast<float>(last[i]));
            }
        }
    }
    vp_mark_level0_groups(t);
    return t;
}

void vp_mark_level0_groups(VpForwardTable& table) {
    const int width = table.map.screen_width, height = table.map.screen_height, groups = width / 8;
    table.level0_rows = vp_column_rows(table.map, table.map.width - 1);
    const auto n = static_cast<float>(table.level0_rows);
    table.level0.assign(static_cast<std::size_t>(groups) * static_cast<std::size_t>(height), 0);
    for (int y = 0; y < height; ++y)
        for (int g = 0; g < groups; ++g) {
            bool level0 = true;
            for (int x = 8 * g; x < 8 * g + 8; ++x) {
                const float* l = &table.levels.data[table.levels.index(x, y)];
                level0 = level0 && l[0] == n && l[2] == n && l[1] == 0.0f && l[3] == 0.0f;
            }
            table.level0[static_cast<std::size_t>(y) * static_cast<std::size_t>(groups) +
                         static_cast<std::size_t>(g)] = level0 ? 1 : 0;
        }
}

void resolve_vp_pixel(const VisualPolarMap& map, const VpMips& mips, Image& out, int x, int y,
                      ResolveStats& stats, float* lambda_out, bool mip,
                      const VpForwardTable* table) {
    const int channels = out.channels;
    float* pixel = &out.at(x, y, 0);
    ++stats.pixels_from_buffer;

    // Polar coordinates of the pixel centre (u: vp_forward's, bit for bit)
    float u = 0.0f, r = 0.0f, theta = 0.0f;
    const float* levels = nullptr;  // the table's (n_k, lambda_k)
    if (table) {
        const float* p = &table->polar.data[table->polar.index(x, y)];
        u = p[0], r = p[1], theta = p[2];
        levels = &table->levels.data[table->levels.index(x, y)];
    } else {
        vp_polar_pixel(map, x, y, u, r, theta);
    }

    // The two columns along rho (clamped to the first and last texel centres)
    const VpColumns rho = vp_rho_columns(map.width, u);
    const int columns[2] = {rho.i0, rho.i1};
    const float fx = rho.fx;

    // Each column at the pixel's angle on its own rows, at its own phi level
    float values[2][max_channels] = {{0, 0, 0, 0}, {0, 0, 0, 0}};
    bool have[2] = {false, false};
    for (int k = 0; k < rho.count; ++k) {
        const int n = mips.column_rows[static_cast<std::size_t>(columns[k])];
        const float v = static_cast<float>(n) * theta / two_pi;
        float lambda = 0.0f;
        if (mip)
            lambda = levels && levels[2 * k] == static_cast<float>(n) ? levels[2 * k + 1]
                                                                      : vp_mip_level(n, r);
        if (k == 0 && lambda_out) *lambda_out = lambda;
        have[k] = sample_column(mips, columns[k], v, lambda, channels, values[k]);
    }

    // Lerp of the columns over those with a value
    for (int c = 0; c < channels; ++c) {
        if (have[0] && have[1])
            pixel[c] = lerp(values[0][c], values[1][c], fx);
        else if (have[0])
            pixel[c] = values[0][c];
        else
            pixel[c] = values[1][c];
    }
    if (!have[0] && !have[1]) ++stats.pixels_untraced_taps;
}

Image resolve_visual_polar(const VisualPolarMap& map, const VpMips& mips, ResolveStats& stats,
                           bool mip, const VpForwardTable* table, Image storage) {
    FOVREF_CHECK(!table || table->map == map, "a forward table made for another map");
    FOVREF_CHECK(!mips.color.empty() && mips.color.size() == mips.valid.size(),
                 "an empty or inconsistent visual-polar pyramid");
    FOVREF_CHECK_EQ(mips.color[0].width, map.width, "visual-polar buffer width");
    FOVREF_CHECK_EQ(mips.color[0].height, map.height, "visual-polar buffer height");
    FOVREF_CHECK_EQ(mips.column_rows.size(), static_cast<std::size_t>(map.width),
                    "visual-polar pyramid columns");
    for (int i = 0; i < map.width; ++i)
        FOVREF_CHECK_EQ(mips.column_rows[static_cast<std::size_t>(i)], vp_column_rows(map, i),
                        "a pyramid built for another map");
    int max_rows = 1;
    for (const int n : mips.column_rows) max_rows = std::max(max_rows, n);
    FOVREF_CHECK_EQ(mips.color.size(), static_cast<std::size_t>(vp_mip_last_level(max_rows) + 1),
                    "visual-polar pyramid levels");
    // Every pixel is written below (each lane and resolve_vp_pixel write all its channels)
    Image out = std::move(storage);
    keep_or_make(out, map.screen_width, map.screen_height, mips.color[0].channels);
    // Eight pixels at a time where the AVX2 path covers the resolve (the same bits:
    // resolve_avx.h); resolve_vp_pixel, the reference, does the rest.
    if (resolve_vp_avx_applies(map, mips, table)) {
        VpMipsSource source(mips);
        resolve_rows(map, source, vp_resolve_avx_inputs(mips), mip, table, out, stats);
        return out;
    }
    for (int y = 0; y < map.screen_height; ++y)
        for (int x = 0; x < map.screen_width; ++x)
            resolve_vp_pixel(map, mips, out, x, y, stats, nullptr, mip, table);
    return out;
}

Image resolve_visual_polar(const VisualPolarMap& map, const Image& color, const Image& valid,
                           ResolveStats& stats, bool mip, const VpForwardTable* table,
                           Image storage, VpResolveAvxInputs* packed) {
    if (!resolve_vp_avx_applies(map, color, valid, table))
        return resolve_visual_polar(map, build_vp_mips(map, color, valid), stats, mip, table,
                                    std::move(storage));
    FOVREF_CHECK(table->map == map, "a forward table made for another map");
    VpResolveAvxInputs own;
    VpResolveAvxInputs& in = packed ? *packed : own;
    vp_resolve_avx_inputs(map, color, valid, in);
    Image out = std::move(storage);  // every pixel is written below
    keep_or_make(out, map.screen_width, map.screen_height, color.channels);
    VpMipsSource source(map, color, valid);  // built only for the reference's pixels
    resolve_rows(map, source, in, mip, table, out, stats);
    return out;
}

std::vector<glm::ivec2> vp_resolve_taps(const VisualPolarMap& map, int x, int y) {
    float u = 0.0f, r = 0.0f, theta = 0.0f;
    vp_polar_pixel(map, x, y, u, r, theta);
    const VpColumns rho = vp_rho_columns(map.width, u);
    std::vector<glm::ivec2> taps;
    for (int k = 0; k < rho.count; ++k) {
        // the rows sample_vp_phi reads on this column's own rows
        const int column = k == 0 ? rho.i0 : rho.i1;
        const int rows = vp_column_rows(map, column);
        const VpRows phi = vp_phi_rows(rows, static_cast<float>(rows) * theta / two_pi);
        taps.emplace_back(column, phi.j0);
        if (phi.fv > 0.0f) taps.emplace_back(column, phi.j1);
    }
    return taps;
}

}  // namespace fovref
