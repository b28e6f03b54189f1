#include "ref/core/halton.h"

#include <cstdint>

#include "ref/core/error.h"

namespace fovref {

namespace {

// Radical inverse as an exact fraction numerator / denominator.
struct Fraction {
    std::uint64_t numerator = 0;
    std::uint64_t denominator = 1;
};

Fraction radical_inverse(std::uint32_t index, std::uint32_t base) {
    Fraction f;
    while (index > 0) {
        f.numerator = f.numerator * base + index % base;
        f.denominator *= base;
        index /= base;
    }
    return f;
}

}  // namespace

float halton(std::uint32_t index, std::uint32_t base) {
    if (base != 2 && base != 3)
        throw Error("halton: base must be 2 or 3, got " + std::to_string(base));
    Fraction f = radical_inverse(index, base);
    // numerator, denominator < 2^53: the quotient is rounded once in binary64, then to float.
    return static_cast<float>(static_cast<double>(f.numerator) /
                              static_cast<double>(f.denominator));
}

std::array<Offset2, 16> halton23_points16() {
    std::array<Offset2, 16> points;
    for (std::uint32_t i = 0; i < 16; ++i) points[i] = {halton(i + 1, 2), halton(i + 1, 3)};
    return points;
}

std::array<Offset2, 16> halton23_offsets16() {
    // Points 1..16 of base 2 are multiples of 1/32 and of base 3 multiples of 1/27, so each axis
    // is n_i / D with integer n_i. Lund eq. 3.11 scales by 0.5 / mean, i.e. o_i = 8 n_i / sum(n).
    // Quantise to 2^-20: floor each 8 n_i 2^20 / N, then hand the remaining units (fewer than 16)
    // to the largest remainders, ties to the lower index, so the offsets sum to exactly 8.
    constexpr std::uint64_t quantum = 1u << 20;
    std::array<Offset2, 16> offsets;
    for (int axis = 0; axis < 2; ++axis) {
        const std::uint32_t base = axis == 0 ? 2 : 3;
        const std::uint64_t denominator = axis == 0 ? 32 : 27;
        std::uint64_t n[16];
        std::uint64_t total = 0;
        for (std::uint32_t i = 0; i < 16; ++i) {
            Fraction f = radical_inverse(i + 1, base);
            n[i] = f.numerator * (denominator / f.denominator);
            total += n[i];
        }
        std::uint64_t units[16], remainder[16];
        std::uint64_t assigned = 0;
        for (int i = 0; i < 16; ++i) {
            units[i] = 8 * n[i] * quantum / total;
            remainder[i] = 8 * n[i] * quantum % total;
            assigned += units[i];
        }
        std::uint64_t deficit = 8 * quantum - assigned;
        FOVREF_CHECK(deficit < 16, "halton quantisation deficit " + std::to_string(deficit));
        bool bumped[16] = {};
        for (std::uint64_t k = 0; k < deficit; ++k) {
            int best = -1;
            for (int i = 0; i < 16; ++i)
                if (!bumped[i] && (best < 0 || remainder[i] > remainder[best])) best = i;
            bumped[best] = true;
            units[best] += 1;
        }
        for (int i = 0; i < 16; ++i) {
            float value = static_cast<float>(units[i]) / static_cast<float>(quantum);  // exact
            (axis == 0 ? offsets[i].x : offsets[i].y) = value;
        }
    }
    return offsets;
}

Offset2 halton_jitter(std::uint32_t frame, std::uint32_t start) {
    static const std::array<Offset2, 16> offsets = halton23_offsets16();
    return offsets[(static_cast<std::uint64_t>(frame) + start) % 16];
}

}  // namespace fovref
