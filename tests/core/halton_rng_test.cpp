#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "ref/core/halton.h"
#include "ref/core/rng.h"

using namespace fovref;

TEST_CASE("halton radical inverse: known values") {
    CHECK(halton(1, 2) == 0.5f);
    CHECK(halton(2, 2) == 0.25f);
    CHECK(halton(3, 2) == 0.75f);
    CHECK(halton(16, 2) == 1.0f / 32.0f);
    CHECK(halton(1, 3) == static_cast<float>(1.0 / 3.0));
    CHECK(halton(5, 3) == static_cast<float>(7.0 / 9.0));  // 5 = 12_3 -> 0.21_3 = 7/9
    CHECK(halton(0, 2) == 0.0f);
}

TEST_CASE("halton offsets: mean exactly 0.5 per axis (Lund eq. 3.11)") {
    auto offsets = halton23_offsets16();
    auto points = halton23_points16();
    double sum_x = 0, sum_y = 0, raw_x = 0, raw_y = 0;
    for (int i = 0; i < 16; ++i) {
        sum_x += offsets[i].x;
        sum_y += offsets[i].y;
        raw_x += points[i].x;
        raw_y += points[i].y;
        // Offsets stay inside the pixel and within one quantum of the exact scaled value.
        CHECK(offsets[i].x > 0.0f);
        CHECK(offsets[i].x < 1.0f);
        CHECK(offsets[i].y > 0.0f);
        CHECK(offsets[i].y < 1.0f);
    }
    CHECK(sum_x / 16.0 == 0.5);
    CHECK(sum_y / 16.0 == 0.5);
    // The unscaled mean is not 0.5 (that is why Lund scales): 7.53125/16 and 200/27/16.
    CHECK(raw_x / 16.0 == doctest::Approx(7.53125 / 16.0).epsilon(1e-7));
    CHECK(raw_x / 16.0 != 0.5);
    CHECK(raw_y / 16.0 == doctest::Approx(200.0 / 27.0 / 16.0).epsilon(1e-7));
    for (int i = 0; i < 16; ++i) {
        double exact_x = static_cast<double>(points[i].x) * 0.5 / (7.53125 / 16.0);
        CHECK(std::abs(offsets[i].x - exact_x) <= 1.0 / (1 << 20));
    }
}

TEST_CASE("halton jitter cycles with period 16 from the start index") {
    auto offsets = halton23_offsets16();
    CHECK(halton_jitter(0, 0) == offsets[0]);
    CHECK(halton_jitter(17, 0) == offsets[1]);
    CHECK(halton_jitter(3, 5) == offsets[8]);
}

TEST_CASE("pcg, wang and jenkins hashes: published reference values") {
    // Values from an independent Python transcription of the published listings (Jenkins':
    // the six shifts as in the BMFR authors' bmfr.cl, unsigned 32-bit wrap-around).
    CHECK(pcg_hash(0u) == 129708002u);
    CHECK(wang_hash(0u) == 3232319850u);
    CHECK(wang_hash(1u) == 663891101u);
    CHECK(jenkins_hash(0u) == 1800329511u);
    CHECK(jenkins_hash(1u) == 3028713910u);
    CHECK(jenkins_hash(1024u) == 1170470466u);
    CHECK(jenkins_hash(13317u) == 3356915122u);
    CHECK(jenkins_hash(4294967295u) == 4268016002u);
}

TEST_CASE(
    "rand: independent of evaluation order, distinct across dimensions, in the unit interval") {
    std::set<std::uint32_t> seen;
    double sum = 0;
    const int n = 1 << 16;
    for (int p = 0; p < n; ++p) {
        float u = rand_unit(3, static_cast<std::uint32_t>(p), 1);
        CHECK(u >= 0.0f);
        CHECK(u < 1.0f);
        sum += u;
        seen.insert(rand_u32(3, static_cast<std::uint32_t>(p), 1));
    }
    CHECK(seen.size() > static_cast<std::size_t>(n - 4));  // 32-bit birthday collisions: ~0.5
    CHECK(sum / n == doctest::Approx(0.5).epsilon(0.01));
    CHECK(rand_u32(0, 0, 0) != rand_u32(0, 0, 1));
    CHECK(rand_u32(0, 0, 0) != rand_u32(1, 0, 0));
    CHECK(rand_u32(0, 1, 0) != rand_u32(0, 0, 1));
    CHECK(u32_to_unit(0xffffffffu) == 1.0f - 1.0f / 16777216.0f);
}
