// Lane-by-lane helpers for the AVX paths that must give their scalar reference's bits (eight
// binary32 lanes, docs/determinism.md "SIMD paths"): comparisons, selects, and the standard
// library's std::max, std::min, std::isfinite, std::fabs and std::floor with their exact
// semantics (the first argument on ties and NaN, as the standard defines them). Each helper is
// forced inline into the caller, which must itself be compiled for AVX
// (`__attribute__((target("avx")))`; AVX2 for the gathers, FOVREF_AVX2_INLINE) and must not pass
// an __m256 to code without AVX.
#pragma once

#include <immintrin.h>

#include <cstddef>
#include <limits>

namespace fovref::avx {

constexpr int lanes = 8;

#define FOVREF_AVX_INLINE __attribute__((target("avx"), always_inline)) inline

/// Call before scalar code runs from AVX code (a lane the vector path leaves to its scalar
/// reference): vzeroupper, the upper halves of the ymm registers cleared. The scalar code is
/// compiled without AVX (legacy SSE encoding); on Intel cores every SSE instruction that runs
/// while an upper half is dirty carries a false dependency and a merge, and g++ 12 does not
/// always insert vzeroupper before such a call itself (it left it out in pow_fast_array's AVX2
/// kernel, whose fallback lanes then ran about 5x slower on an Intel Xeon: docs/speed.md).
/// Changes no value; tools/scripts/check_vzeroupper.py looks for calls it should precede.
FOVREF_AVX_INLINE void leave_for_scalar() { _mm256_zeroupper(); }

/// The lanes a vector kernel could not do, redone by its scalar reference: out[k] = scalar(x[k])
/// for each of the `count` lanes whose bit in `done` is clear, after leave_for_scalar(). Nothing
/// runs when every lane is done. `x` holds the kernel's inputs (a copy when `out` may be `x`).
template <class Scalar>
FOVREF_AVX_INLINE void redo_lanes(int done, int count, const float* x, float* out, Scalar scalar) {
    if (done == (1 << count) - 1) return;
    leave_for_scalar();
    for (int k = 0; k < count; ++k)
        if (!(done & (1 << k))) out[k] = scalar(x[k]);
}

FOVREF_AVX_INLINE __m256 set(float v) { return _mm256_set1_ps(v); }
FOVREF_AVX_INLINE __m256 zero() { return _mm256_setzero_ps(); }
/// `yes` where the comparison mask is set, else `no`, bit for bit.
FOVREF_AVX_INLINE __m256 select(__m256 mask, __m256 yes, __m256 no) {
    return _mm256_or_ps(_mm256_and_ps(mask, yes), _mm256_andnot_ps(mask, no));
}
/// Ordered comparisons (false where either lane is NaN), as C++'s <, >, <=, >=, ==.
FOVREF_AVX_INLINE __m256 less(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
FOVREF_AVX_INLINE __m256 greater(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
FOVREF_AVX_INLINE __m256 at_most(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
FOVREF_AVX_INLINE __m256 at_least(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
FOVREF_AVX_INLINE __m256 equal(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
/// C++'s != (true where either lane is NaN).
FOVREF_AVX_INLINE __m256 not_equal(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }
FOVREF_AVX_INLINE __m256 both(__m256 a, __m256 b) { return _mm256_and_ps(a, b); }
FOVREF_AVX_INLINE __m256 either(__m256 a, __m256 b) { return _mm256_or_ps(a, b); }
FOVREF_AVX_INLINE __m256 negation(__m256 a) {
    return _mm256_xor_ps(a, _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
}
/// std::isfinite: |v| < infinity (false for NaN).
FOVREF_AVX_INLINE __m256 finite(__m256 v) {
    const __m256 magnitude = _mm256_and_ps(v, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
    return less(magnitude, set(std::numeric_limits<float>::infinity()));
}
/// std::fabs and unary minus: the sign bit cleared or flipped (NaN payloads kept).
FOVREF_AVX_INLINE __m256 abs(__m256 v) {
    return _mm256_and_ps(v, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
}
FOVREF_AVX_INLINE __m256 negate(__m256 v) {
    return _mm256_xor_ps(v, _mm256_castsi256_ps(_mm256_set1_epi32(static_cast<int>(0x80000000u))));
}
/// std::max(a, b) = (a < b) ? b : a and std::min(a, b) = (b < a) ? b : a; chained left to right
/// they give std::max({a, b, c, ...}) and std::min({...}) (the first largest or smallest). One
/// instruction each: vmaxps(x, y) is (x > y) ? x : y and vminps(x, y) is (x < y) ? x : y, lane by
/// lane, y on ties (±0) and wherever either is NaN (Intel SDM, MAXPS/MINPS), so with x = b and
/// y = a they are the standard's expressions bit for bit; neither compiler swaps their operands.
FOVREF_AVX_INLINE __m256 std_max(__m256 a, __m256 b) { return _mm256_max_ps(b, a); }
FOVREF_AVX_INLINE __m256 std_min(__m256 a, __m256 b) { return _mm256_min_ps(b, a); }
/// std::floor and std::ceil (exact: roundps).
FOVREF_AVX_INLINE __m256 floor(__m256 v) {
    return _mm256_round_ps(v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
}
FOVREF_AVX_INLINE __m256 ceil(__m256 v) {
    return _mm256_round_ps(v, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
}
/// The lanes of `todo` (bits) whose `values` equal its lowest lane's, taken out of `todo`; that
/// lane's value in `value`. Repeated until `todo` is 0, it visits each distinct value once (a
/// NaN lane would never match itself: the caller keeps them out).
FOVREF_AVX_INLINE int take_equal_lanes(__m256 values, int& todo, float& value) {
    alignas(32) float each[lanes];
    _mm256_store_ps(each, values);
    value = each[__builtin_ctz(static_cast<unsigned>(todo))];
    const int equal_lanes =
        _mm256_movemask_ps(_mm256_cmp_ps(values, _mm256_set1_ps(value), _CMP_EQ_OQ)) & todo;
    todo &= ~equal_lanes;
    return equal_lanes;
}
/// The lanes set in a comparison mask.
FOVREF_AVX_INLINE int count(__m256 mask) { return __builtin_popcount(_mm256_movemask_ps(mask)); }
FOVREF_AVX_INLINE int bits(__m256 mask) { return _mm256_movemask_ps(mask); }

/// Eight pixels of two interleaved channels (p: the first pixel's first value) as one array per
/// channel (the lanes' layout).
inline void load2_lanes(const float* p, float (*out)[lanes]) {
    for (int l = 0; l < lanes; ++l)
        for (int c = 0; c < 2; ++c) out[c][l] = p[l * 2 + c];
}
/// Eight pixels of three interleaved channels as one array per channel, and back.
inline void load3_lanes(const float* p, float (*out)[lanes]) {
    for (int l = 0; l < lanes; ++l)
        for (int c = 0; c < 3; ++c) out[c][l] = p[l * 3 + c];
}
inline void store3_lanes(const float (*in)[lanes], float* p) {
    for (int l = 0; l < lanes; ++l)
        for (int c = 0; c < 3; ++c) p[l * 3 + c] = in[c][l];
}

#define FOVREF_AVX2_INLINE __attribute__((target("avx2"), always_inline)) inline

/// Four floats of each of eight lanes (q[l], lane l) as one register per float: out[e] holds
/// float e of every lane (the same floats, moved by shuffles).
FOVREF_AVX_INLINE void transpose4_lanes(__m128* q, __m256* out) {
    _MM_TRANSPOSE4_PS(q[0], q[1], q[2], q[3]);
    _MM_TRANSPOSE4_PS(q[4], q[5], q[6], q[7]);
    for (int e = 0; e < 4; ++e) out[e] = _mm256_set_m128(q[4 + e], q[e]);
}

/// The three floats of pixel at[l] of an interleaved 3-channel image (`rgb`, `pixels` pixels)
/// for each lane of `on` (+0 in the others, whose at[l] must be 0), stored whole into out[0 .. 2]
/// (channel c of lane l at out[c][l]): loads of whole registers from `out` then take them from
/// those stores, where a lane-by-lane fill would make them wait until eight stores reach the
/// cache. Four floats are read per lane (the pixel's three and the next one's first) and
/// transposed; where a lane's pixel is the image's last (no fourth float), lane by lane.
FOVREF_AVX_INLINE void load3_pixels(const float* rgb, std::size_t pixels, const std::size_t* at,
                                    __m256 on, float (*out)[lanes]) {
    bool inner = true;
    for (int l = 0; l < lanes; ++l) inner = inner && at[l] + 1 < pixels;
    if (!inner) {
        const int on_bits = _mm256_movemask_ps(on);
        for (int l = 0; l < lanes; ++l)
            for (int c = 0; c < 3; ++c) out[c][l] = (on_bits >> l & 1) ? rgb[3 * at[l] + c] : 0.0f;
        return;
    }
    __m128 q[lanes];
    for (int l = 0; l < lanes; ++l) q[l] = _mm_loadu_ps(rgb + 3 * at[l]);
    __m256 v[4];
    transpose4_lanes(q, v);
    for (int c = 0; c < 3; ++c) _mm256_store_ps(out[c], select(on, v[c], zero()));
}

/// Tap k's pixel index(k, l) of each lane l of `on`, 0 in the others (load3_pixels' `at`).
template <class Index>
FOVREF_AVX_INLINE void tap_pixels(__m256 on, int k, Index index, std::size_t* at) {
    const int on_bits = _mm256_movemask_ps(on);
    for (int l = 0; l < lanes; ++l) at[l] = (on_bits >> l & 1) ? index(k, l) : 0;
}

/// load3_pixels for each of four taps: tap k's pixel of lane l is index(k, l) where on[k] holds
/// the lane; taps[k][c][l] its channel c (+0 where off).
template <class Index>
FOVREF_AVX_INLINE void load3_taps(const float* rgb, std::size_t pixels, const __m256* on,
                                  Index index, float (*taps)[3][lanes]) {
    for (int k = 0; k < 4; ++k) {
        std::size_t at[lanes];
        tap_pixels(on[k], k, index, at);
        load3_pixels(rgb, pixels, at, on[k], taps[k]);
    }
}

/// (AVX2) The row-major indices y * width + x of eight pixels, in int32 (the caller makes sure
/// that 3 * width * height fits).
FOVREF_AVX2_INLINE __m256i row_major(__m256i x, __m256i y, int width) {
    return _mm256_add_epi32(_mm256_mullo_epi32(y, _mm256_set1_epi32(width)), x);
}
/// (AVX2) The comparison mask whose lanes are the bits of `lane_bits` (bit l: lane l), the
/// inverse of bits().
FOVREF_AVX2_INLINE __m256 mask_of(int lane_bits) {
    const __m256i each = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_castsi256_ps(
        _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(lane_bits), each), each));
}
/// (AVX2) base[index] in the lanes of `mask` by eight scalar loads (on this project's machine no
/// slower than vgatherdps); the other lanes read base[0], a value the caller must not use.
FOVREF_AVX2_INLINE __m256 load_lanes(const float* base, __m256i index, __m256 mask) {
    alignas(32) int at[lanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at),
                       _mm256_and_si256(index, _mm256_castps_si256(mask)));
    return _mm256_setr_ps(base[at[0]], base[at[1]], base[at[2]], base[at[3]], base[at[4]],
                          base[at[5]], base[at[6]], base[at[7]]);
}
/// (AVX2) The three interleaved channels of pixels `pixel` of `rgb` (3 floats a pixel) into
/// out[0 .. 2], in the lanes set in `mask`; +0 in the others, which read nothing: masked gathers,
/// plain loads of the same floats.
FOVREF_AVX2_INLINE void gather3_lanes(const float* rgb, __m256i pixel, __m256 mask, __m256* out) {
    const __m256i first = _mm256_add_epi32(_mm256_add_epi32(pixel, pixel), pixel);
    for (int c = 0; c < 3; ++c) out[c] = _mm256_mask_i32gather_ps(zero(), rgb + c, first, mask, 4);
}

/// (AVX2) Eight consecutive pixels of three interleaved channels (m0, m1, m2: floats 0..7,
/// 8..15, 16..23) as one register per channel: the same floats, moved by blends and permutes.
FOVREF_AVX2_INLINE void split3_registers(__m256 m0, __m256 m1, __m256 m2, __m256* out) {
    // channel c of pixel l is float 3 l + c: m0 holds floats 0..7, m1 8..15, m2 16..23
    const __m256 r = _mm256_blend_ps(_mm256_blend_ps(m0, m1, 0b10010010), m2, 0b00100100);
    const __m256 g = _mm256_blend_ps(_mm256_blend_ps(m0, m1, 0b00100100), m2, 0b01001001);
    const __m256 b = _mm256_blend_ps(_mm256_blend_ps(m0, m1, 0b01001001), m2, 0b10010010);
    out[0] = _mm256_permutevar8x32_ps(r, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    out[1] = _mm256_permutevar8x32_ps(g, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    out[2] = _mm256_permutevar8x32_ps(b, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}
/// split3_registers of the 24 floats at p (the first pixel's first value).
FOVREF_AVX2_INLINE void split3_lanes(const float* p, __m256* out) {
    split3_registers(_mm256_loadu_ps(p), _mm256_loadu_ps(p + 8), _mm256_loadu_ps(p + 16), out);
}

/// (AVX2) The inverse of split3_lanes: one register per channel stored as eight consecutive
/// pixels of three interleaved channels at p (24 floats).
FOVREF_AVX2_INLINE void merge3_lanes(const __m256* in, float* p) {
    const __m256 r = _mm256_permutevar8x32_ps(in[0], _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    const __m256 g = _mm256_permutevar8x32_ps(in[1], _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
    const __m256 b = _mm256_permutevar8x32_ps(in[2], _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    _mm256_storeu_ps(p, _mm256_blend_ps(_mm256_blend_ps(r, g, 0b10010010), b, 0b00100100));
    _mm256_storeu_ps(p + 8, _mm256_blend_ps(_mm256_blend_ps(r, g, 0b00100100), b, 0b01001001));
    _mm256_storeu_ps(p + 16, _mm256_blend_ps(_mm256_blend_ps(r, g, 0b01001001), b, 0b10010010));
}

/// (AVX2) A value per pixel (lane l: pixel l) spread to the pixel's three interleaved floats:
/// out[k]'s lane f holds pixel (8 k + f) / 3's value, so out[0..2] line up with the three
/// registers of eight consecutive pixels' 24 floats as the image holds them.
FOVREF_AVX2_INLINE void spread3_lanes(__m256 v, __m256* out) {
    out[0] = _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(0, 0, 0, 1, 1, 1, 2, 2));
    out[1] = _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(2, 3, 3, 3, 4, 4, 4, 5));
    out[2] = _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(5, 5, 6, 6, 6, 7, 7, 7));
}

/// The four bilinear taps of eight points (tx, ty) whose corners (x0, y0), the floors of tx and
/// ty, the caller computes (each pass its own way, bit-equal to its scalar code): f = t - x0,
/// the weights (1 - fx)(1 - fy), fx (1 - fy), (1 - fx) fy, fx fy of the taps (x0, y0),
/// (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1), which of them lie on a W x H image (in the
/// `valid` lanes only: elsewhere the corner may be anything), and the corners as integers.
struct BilinearLanes {
    __m256 weight[4], on[4];
    int on_bits[4];  ///< on[k]'s lanes as bits
    alignas(32) int x0[lanes], y0[lanes];
    /// Tap k's pixel of lane l, (x0 + (k & 1), y0 + (k >> 1)), row-major in an image `width`
    /// pixels wide.
    std::size_t pixel(int k, int l, std::size_t width) const {
        return static_cast<std::size_t>(y0[l] + (k >> 1)) * width +
               static_cast<std::size_t>(x0[l] + (k & 1));
    }
};
FOVREF_AVX_INLINE void bilinear_lanes(__m256 tx, __m256 ty, __m256 x0, __m256 y0, __m256 valid,
                                      float width, float height, BilinearLanes& b) {
    const __m256 fx = _mm256_sub_ps(tx, x0), fy = _mm256_sub_ps(ty, y0);
    const __m256 gx = _mm256_sub_ps(set(1.0f), fx), gy = _mm256_sub_ps(set(1.0f), fy);
    b.weight[0] = _mm256_mul_ps(gx, gy);
    b.weight[1] = _mm256_mul_ps(fx, gy);
    b.weight[2] = _mm256_mul_ps(gx, fy);
    b.weight[3] = _mm256_mul_ps(fx, fy);
    const __m256 x1 = _mm256_add_ps(x0, set(1.0f)), y1 = _mm256_add_ps(y0, set(1.0f));
    const __m256 xs[2] = {x0, x1}, ys[2] = {y0, y1};
    for (int k = 0; k < 4; ++k) {
        const __m256 x = xs[k & 1], y = ys[k >> 1];
        b.on[k] = both(both(valid, both(at_least(x, zero()), at_least(y, zero()))),
                       both(less(x, set(width)), less(y, set(height))));
        b.on_bits[k] = bits(b.on[k]);
    }
    // Lanes outside `valid` convert a safe 0 (their corners may be far off or NaN).
    _mm256_store_si256(reinterpret_cast<__m256i*>(b.x0),
                       _mm256_cvttps_epi32(select(valid, x0, zero())));
    _mm256_store_si256(reinterpret_cast<__m256i*>(b.y0),
                       _mm256_cvttps_epi32(select(valid, y0, zero())));
}

/// The weighted sums over four bilinear taps of three channels, in tap order from +0:
/// h[c] = sum of weight[k] taps[k][c] and the returned total = sum of weight[k], over the taps
/// whose lanes are `on` (a tap that is off adds a selected +0 instead of being skipped: the same
/// bits, as a sum that starts at +0 is never -0).
FOVREF_AVX_INLINE __m256 tap_sums3(const __m256* on, const __m256* weight,
                                   const float (*taps)[3][lanes], __m256* h) {
    __m256 total = zero();
    for (int c = 0; c < 3; ++c) h[c] = zero();
    for (int k = 0; k < 4; ++k) {
        for (int c = 0; c < 3; ++c)
            h[c] = _mm256_add_ps(
                h[c], select(on[k], _mm256_mul_ps(weight[k], _mm256_load_ps(taps[k][c])), zero()));
        total = _mm256_add_ps(total, select(on[k], weight[k], zero()));
    }
    return total;
}

/// An 8 x 8 transpose of floats: register k's lane j goes to register j's lane k.
FOVREF_AVX_INLINE void transpose8_lanes(__m256* r) {
    __m256 t[8], u[8];
    for (int k = 0; k < 8; k += 2) {
        t[k] = _mm256_unpacklo_ps(r[k], r[k + 1]);
        t[k + 1] = _mm256_unpackhi_ps(r[k], r[k + 1]);
    }
    for (int k = 0; k < 8; k += 4) {
        u[k] = _mm256_shuffle_ps(t[k], t[k + 2], _MM_SHUFFLE(1, 0, 1, 0));
        u[k + 1] = _mm256_shuffle_ps(t[k], t[k + 2], _MM_SHUFFLE(3, 2, 3, 2));
        u[k + 2] = _mm256_shuffle_ps(t[k + 1], t[k + 3], _MM_SHUFFLE(1, 0, 1, 0));
        u[k + 3] = _mm256_shuffle_ps(t[k + 1], t[k + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
    for (int k = 0; k < 4; ++k) {
        r[k] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x20);
        r[k + 4] = _mm256_permute2f128_ps(u[k], u[k + 4], 0x31);
    }
}

}  // namespace fovref::avx
