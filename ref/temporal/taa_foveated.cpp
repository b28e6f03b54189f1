#include "ref/temporal/taa_foveated.h"

#include <algorithm>
#include <memory>
#include <utility>

#include <xmmintrin.h>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/log_polar/trace.h"
#include "ref/temporal/taa_avx.h"

namespace fovref {

namespace {

// The bilinear weights of the four taps, in tap order.
void tap_weights(const BilinearLookup& l, float* weights) {
    weights[0] = (1.0f - l.fu) * (1.0f - l.fv);
    weights[1] = l.fu * (1.0f - l.fv);
    weights[2] = (1.0f - l.fu) * l.fv;
    weights[3] = l.fu * l.fv;
}

}  // namespace

TaaSource taa_source(const TaaBufferInputs& in, int x, int y) {
    TaaSource s;
    const LogPolarMap& map = in.map;
    const glm::vec2 centre = pixel_centre(x, y);
    if (in.gaze_valid && inside_gaze_circle(map, centre)) {
        const ScreenWindow window = gaze_window(map);
        s.kind = TaaSource::Kind::gaze;
        s.i = x - window.x0;
        s.j = y - window.y0;
        return s;
    }
    const glm::vec2 uv =
        in.forward.uv[static_cast<std::size_t>(y) * static_cast<std::size_t>(map.screen_width) +
                      static_cast<std::size_t>(x)];
    const BilinearLookup l = lp_bilinear_taps(in.lp_valid, uv);
    float weights[4];
    tap_weights(l, weights);
    const int is[4] = {l.i0, l.i1, l.i0, l.i1}, js[4] = {l.j0, l.j0, l.j1, l.j1};
    float best = 0.0f;
    for (int k = 0; k < 4; ++k)
        if (l.traced[k] && weights[k] > best) {
            best = weights[k];
            s.kind = TaaSource::Kind::buffer;
            s.i = is[k];
            s.j = js[k];
        }
    return s;
}

namespace {

void check_inputs(const TaaBufferInputs& in) {
    FOVREF_CHECK(in.forward.map == in.map, "a forward table made for another map");
    FOVREF_CHECK(in.lp_valid.width == in.map.width && in.lp_valid.height == in.map.height,
                 "validity mask of another size than the buffer");
    if (in.gaze_valid) {
        const ScreenWindow window = gaze_window(in.map);
        FOVREF_CHECK(in.gaze_valid->width == window.width && in.gaze_valid->height == window.height,
                     "a gaze mask of another size than the gaze buffer's window");
    }
}

}  // namespace

namespace {

// The box of every texel (or gaze pixel) of `image`: min (r, g, b) and max (r, g, b) over its
// 3x3 neighbourhood of traced texels, starting from the texel itself; columns clamped, rows
// wrapped (`wrap_rows`, the angle axis) or clamped. Made once per buffer (a GPU's buffer-space
// min/max pass); the screen pixels then read the box of their source texel.
void texel_box(const Image& image, const Image& valid, bool wrap_rows, int si, int sj,
               float* record) {
    float lo[3], hi[3];
    for (int c = 0; c < 3; ++c) lo[c] = hi[c] = image.at(si, sj, c);
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
            const int i = std::clamp(si + di, 0, image.width - 1);
            const int j = wrap_rows ? (sj + dj + image.height) % image.height
                                    : std::clamp(sj + dj, 0, image.height - 1);
            if (valid.at(i, j) == 0.0f) continue;
            for (int c = 0; c < 3; ++c) {
                lo[c] = std::min(lo[c], image.at(i, j, c));
                hi[c] = std::max(hi[c], image.at(i, j, c));
            }
        }
    for (int c = 0; c < 3; ++c) {
        record[c] = lo[c];
        record[3 + c] = hi[c];
    }
}

// Every texel's record (taa_record_channels floats, row-major): its box (texel_box), its depth
// and its mask as `depth` and `valid` hold them; a pixel reads its source's three from one
// record. With `traced_only` only the traced texels get a box (the others' first six floats are
// never written, nor read), for a buffer whose sources are always traced (the log-polar one: its
// off-screen and gaze-circle texels cost nothing). The records are not zero-filled: every
// record's depth and mask are written, and every box a pixel can read.
std::unique_ptr<float[]> texel_records(const Image& image, const Image& valid, const Image& depth,
                                       bool wrap_rows, bool traced_only) {
    const std::size_t row_floats = static_cast<std::size_t>(image.width) * taa_record_channels;
    auto records = std::make_unique_for_overwrite<float[]>(row_floats * image.height);
    // Column 0 by texel_box, then eight texels at a time where the AVX2 path covers the image
    // (the same bits: taa_avx.h), then the rest by texel_box; then the row's depths and masks
    const bool avx = texel_boxes_avx_applies(image, valid);
    for (int sj = 0; sj < image.height; ++sj) {
        float* row = &records[row_floats * static_cast<std::size_t>(sj)];
        const auto box = [&](int si) {
            if (!traced_only || valid.at(si, sj) != 0.0f)
                texel_box(image, valid, wrap_rows, si, sj,
                          row + static_cast<std::size_t>(si) * taa_record_channels);
        };
        int si = 0;
        if (avx) {
            box(0);
            si = texel_boxes_row_avx(image, valid, wrap_rows, traced_only, sj, row);
        }
        for (; si < image.width; ++si) box(si);
        for (si = 0; si < image.width; ++si) {
            row[static_cast<std::size_t>(si) * taa_record_channels + 6] = depth.at(si, sj);
            row[static_cast<std::size_t>(si) * taa_record_channels + 7] = valid.at(si, sj);
        }
    }
    return records;
}

}  // namespace

TaaSourceTable taa_source_table(const TaaBufferInputs& in) {
    check_inputs(in);
    const LogPolarMap& map = in.map;
    TaaSourceTable table;
    table.map = map;
    table.gaze = in.gaze_valid != nullptr;
    const std::size_t pixels =
        static_cast<std::size_t>(map.screen_width) * static_cast<std::size_t>(map.screen_height);
    table.count.assign(pixels, 0);
    table.first.assign(pixels, 0);
    table.rest.assign(pixels, {0, 0, 0});
    const ScreenWindow window = gaze_window(map);
    for (int y = 0; y < map.screen_height; ++y)
        for (int x = 0; x < map.screen_width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * map.screen_width + x;
            if (table.gaze && inside_gaze_circle(map, pixel_centre(x, y))) {
                table.count[p] = -1;
                table.first[p] = (y - window.y0) * window.width + (x - window.x0);
                continue;
            }
            // taa_source's choice, the largest traced weight with ties to the first tap, is the
            // first traced tap of the non-zero weights sorted by weight, then tap order.
            const BilinearLookup l = lp_bilinear_index(map.width, map.height, in.forward.uv[p]);
            float weights[4];
            tap_weights(l, weights);
            const int is[4] = {l.i0, l.i1, l.i0, l.i1}, js[4] = {l.j0, l.j0, l.j1, l.j1};
            int order[4], n = 0;
            for (int k = 0; k < 4; ++k)
                if (weights[k] > 0.0f) order[n++] = k;  // (a NaN weight is never chosen)
            for (int a = 1; a < n; ++a)                 // insertion sort: stable
                for (int b = a; b > 0 && weights[order[b]] > weights[order[b - 1]]; --b)
                    std::swap(order[b], order[b - 1]);
            table.count[p] = static_cast<std::int8_t>(n);
            for (int k = 0; k < n; ++k)
                (k == 0 ? table.first[p] : table.rest[p][static_cast<std::size_t>(k - 1)]) =
                    js[order[k]] * map.width + is[order[k]];
        }
    return table;
}

bool taa_source_table_fits(const TaaSourceTable& table, const TaaBufferInputs& in) {
    return !table.count.empty() && table.map == in.map && table.gaze == (in.gaze_valid != nullptr);
}

namespace {

// Pixel p's source from the table: its kind and the texel's row-major index in its buffer. The
// mask of texel t is valid[t * stride] (the mask itself, or the texel records' channel 7).
TaaSource::Kind table_source(const TaaSourceTable& table, std::size_t p, const float* valid,
                             std::size_t stride, std::size_t& texel) {
    const int count = table.count[p];
    texel = static_cast<std::size_t>(table.first[p]);
    if (count < 0) return TaaSource::Kind::gaze;
    for (int k = 0; k < count; ++k) {
        if (k > 0) texel = static_cast<std::size_t>(table.rest[p][static_cast<std::size_t>(k - 1)]);
        if (valid[texel * stride] != 0.0f) return TaaSource::Kind::buffer;
    }
    return TaaSource::Kind::none;
}

// What the per-pixel pass reads of a source texel t: lp[k][t * stride] in the log-polar buffer,
// gaze[k][t * stride] in the gaze buffer (null where nothing is read).
struct SourceReads {
    const float* lp[2] = {nullptr, nullptr};
    const float* gaze[2] = {nullptr, nullptr};
    std::size_t stride = 1;
};

// How many pixels ahead the table path prefetches its first tap's reads. Those reads are
// scattered (a screen row crosses many of the buffer's rows), and waiting on them was most of
// the pass (perf annotate); a prefetch changes no value.
constexpr std::size_t prefetch_ahead = 64;

// Prefetches what pixel q reads of its first tap (the source of most pixels). Always inlined: a
// function whose only effect is a prefetch counts as pure to g++, which then drops its calls.
[[gnu::always_inline]] inline void prefetch_source(const TaaSourceTable& table, std::size_t q,
                                                   const SourceReads& reads) {
    if (q >= table.count.size()) return;
    const std::size_t offset = static_cast<std::size_t>(table.first[q]) * reads.stride;
    for (const float* base : table.count[q] < 0 ? reads.gaze : reads.lp)
        if (base) __builtin_prefetch(base + offset);
}

// taa_source_pass with a table and colours (the stages' case): per pixel the same source
// (table_source), depth and widened box as the reference loop, read and written through plain
// pointers, each half of the box widened four floats at a time with SSE. minps(v, lo) is
// (v < lo) ? v : lo = std::min(lo, v), and maxps(v, hi) is (v > hi) ? v : hi = std::max(hi, v),
// NaN and signed zeros included. The fourth lane of each half is overwritten: the minima's by
// the maxima, the maxima's (float 6 of the pixel's box) by the next pixel's box; the colour's
// fourth float is the next pixel's. The last pixel, which has neither, goes through copies.
void table_boxes(const TaaSourceTable& table, const float* lp_records, const float* gaze_records,
                 const Image& screen_color, Image& depth, Image& bounds) {
    const SourceReads reads{{lp_records, nullptr}, {gaze_records, nullptr}, taa_record_channels};
    float* depth_out = depth.data.data();
    // Pixel p from its colour's four floats `colour` into its box's seven `box`
    const auto pixel = [&](std::size_t p, const float* colour, float* box) {
        prefetch_source(table, p + prefetch_ahead, reads);
        std::size_t texel = 0;
        const TaaSource::Kind kind =
            table_source(table, p, lp_records + 7, taa_record_channels, texel);
        const __m128 v = _mm_loadu_ps(colour);
        if (kind == TaaSource::Kind::none) {
            depth_out[p] = 0.0f;
            _mm_storeu_ps(box, v);
            _mm_storeu_ps(box + 3, v);
            return;
        }
        const float* record = (kind == TaaSource::Kind::gaze ? gaze_records : lp_records) +
                              texel * taa_record_channels;
        depth_out[p] = record[6];
        _mm_storeu_ps(box, _mm_min_ps(v, _mm_loadu_ps(record)));
        _mm_storeu_ps(box + 3, _mm_max_ps(v, _mm_loadu_ps(record + 3)));
    };
    const std::size_t pixels = depth.data.size();
    if (pixels == 0) return;
    const float* colour = screen_color.data.data();
    float* box_out = bounds.data.data();
    for (std::size_t p = 0; p + 1 < pixels; ++p) pixel(p, colour + 3 * p, box_out + 6 * p);
    float last_colour[4] = {}, last_box[7];
    std::copy_n(colour + 3 * (pixels - 1), 3, last_colour);
    pixel(pixels - 1, last_colour, last_box);
    std::copy_n(last_box, 6, box_out + 6 * (pixels - 1));
}

// taa_source_pass with a table, without colours (the depth alone), through plain pointers: per
// pixel the same source (table_source) and depth as the reference loop.
void table_depths(const TaaSourceTable& table, const float* lp_valid, const float* lp_depth,
                  const float* gaze_depth, Image& depth) {
    const SourceReads reads{{lp_valid, lp_depth}, {gaze_depth, nullptr}, 1};
    float* depth_out = depth.data.data();
    for (std::size_t p = 0; p < depth.data.size(); ++p) {
        prefetch_source(table, p + prefetch_ahead, reads);
        std::size_t texel = 0;
        const TaaSource::Kind kind = table_source(table, p, lp_valid, 1, texel);
        depth_out[p] = kind == TaaSource::Kind::none   ? 0.0f
                       : kind == TaaSource::Kind::gaze ? gaze_depth[texel]
                                                       : lp_depth[texel];
    }
}

// taa_source_pass's inputs: the buffers agree with the map, and the depths and colours with
// their masks (or the screen), as the texel records index them together.
void check_pass_inputs(const TaaBufferInputs& in, const Image& lp_depth, const Image* gaze_depth,
                       const TaaBoxColors* colors, const TaaSourceTable* table) {
    check_inputs(in);
    FOVREF_CHECK(!table || taa_source_table_fits(*table, in),
                 "a TAA source table made for another map");
    FOVREF_CHECK(in.gaze_valid == nullptr || gaze_depth != nullptr, "gaze depth missing");
    // `channels` channels of a mask's (or the screen's) width x height
    const auto shaped = [](const Image& image, int channels, int width, int height) {
        return image.channels == channels && image.width == width && image.height == height;
    };
    const Image* gaze = in.gaze_valid;
    FOVREF_CHECK(shaped(lp_depth, 1, in.lp_valid.width, in.lp_valid.height) &&
                     (!gaze || shaped(*gaze_depth, 1, gaze->width, gaze->height)),
                 "a view depth of another size than its buffer (or not one channel)");
    FOVREF_CHECK(!colors || !gaze || colors->gaze_color != nullptr, "gaze colour missing");
    FOVREF_CHECK(
        !colors || (shaped(colors->lp_color, 3, in.map.width, in.map.height) &&
                    shaped(colors->screen_color, 3, in.map.screen_width, in.map.screen_height) &&
                    (!gaze || shaped(*colors->gaze_color, 3, gaze->width, gaze->height))),
        "a colour buffer that is not RGB of its mask's or the screen's size");
}

}  // namespace

TaaSourceOutputs taa_source_pass(const TaaBufferInputs& in, const Image& lp_depth,
                                 const Image* gaze_depth, const TaaBoxColors* colors,
                                 const TaaSourceTable* table, TaaSourceOutputs storage) {
    check_pass_inputs(in, lp_depth, gaze_depth, colors, table);
    TaaSourceOutputs out = std::move(storage);
    // The storage where it has the outputs' shapes (every value is written below), else new
    const int width = in.map.screen_width, height = in.map.screen_height;
    keep_or_make(out.depth, width, height, 1);
    if (colors) keep_or_make(out.bounds, width, height, 6);
    // With colours each texel's box, depth and mask come from its record (texel_records).
    std::unique_ptr<float[]> lp_records, gaze_records;
    if (colors) {
        lp_records = texel_records(colors->lp_color, in.lp_valid, lp_depth, true, true);
        if (in.gaze_valid)
            gaze_records =
                texel_records(*colors->gaze_color, *in.gaze_valid, *gaze_depth, false, false);
    }
    const int gaze_width = in.gaze_valid ? in.gaze_valid->width : 0;
    // With a table (whose texel indices address a one-channel mask, as the stages' masks always
    // are) plain-pointer loops do every pixel, the same bits as the reference loop below.
    if (table && in.lp_valid.channels == 1) {
        if (colors)
            table_boxes(*table, lp_records.get(), gaze_records.get(), colors->screen_color,
                        out.depth, out.bounds);
        else
            table_depths(*table, in.lp_valid.data.data(), lp_depth.data.data(),
                         gaze_depth ? gaze_depth->data.data() : nullptr, out.depth);
        return out;
    }
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x;
            const TaaSource s = taa_source(in, x, y);
            const TaaSource::Kind kind = s.kind;
            const int buffer_width = kind == TaaSource::Kind::gaze ? gaze_width : in.map.width;
            const std::size_t texel = static_cast<std::size_t>(s.j) * buffer_width + s.i;
            const bool gaze = kind == TaaSource::Kind::gaze;
            if (!colors) {
                out.depth.data[p] = kind == TaaSource::Kind::none ? 0.0f
                                    : gaze                        ? gaze_depth->data[texel]
                                                                  : lp_depth.data[texel];
                continue;
            }
            if (kind == TaaSource::Kind::none) {
                out.depth.data[p] = 0.0f;
                for (int c = 0; c < 3; ++c)
                    out.bounds.at(x, y, c) = out.bounds.at(x, y, 3 + c) =
                        colors->screen_color.at(x, y, c);
                continue;
            }
            // The box, widened to hold pass 2's own value (a mip resolve mixes coarser levels,
            // which can lie outside the level-0 box; bilinear pass 2 lies inside it).
            const float* box = &(gaze ? gaze_records : lp_records)[texel * taa_record_channels];
            out.depth.data[p] = box[6];
            for (int c = 0; c < 3; ++c) {
                const float v = colors->screen_color.at(x, y, c);
                out.bounds.at(x, y, c) = std::min(box[c], v);
                out.bounds.at(x, y, 3 + c) = std::max(box[3 + c], v);
            }
        }
    return out;
}

}  // namespace fovref
