// Buffer comparison for `fovref diff` (SPEC §11): ulp distances, tolerances, NaN rules, worst
// and first failing pixels, tolerance files and options.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "ref/golden/bundle.h"
#include "ref/metrics/compare.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

float next_up(float v) { return std::nextafter(v, std::numeric_limits<float>::infinity()); }

}  // namespace

TEST_CASE("ulp distance in the binary32 ordering") {
    CHECK(ulp_distance(1.0f, 1.0f) == 0);
    CHECK(ulp_distance(1.0f, next_up(1.0f)) == 1);
    CHECK(ulp_distance(0.0f, -0.0f) == 0);
    CHECK(ulp_distance(-0.0f, std::numeric_limits<float>::denorm_min()) == 1);
    CHECK(ulp_distance(-std::numeric_limits<float>::denorm_min(),
                       std::numeric_limits<float>::denorm_min()) == 2);
    CHECK(ulp_distance(1.0f, 2.0f) == (1 << 23));
    CHECK(ulp_distance(std::numeric_limits<float>::max(), std::numeric_limits<float>::infinity()) ==
          1);
}

TEST_CASE("compare_buffers: identical, one ulp, tolerances") {
    Image g(16, 12, 3, 0.5f);
    for (std::size_t i = 0; i < g.data.size(); ++i) g.data[i] = 0.01f * static_cast<float>(i % 97);
    BufferComparison same = compare_buffers("b", g, g, {});
    CHECK(same.pass);
    CHECK(same.max_abs == 0.0);
    CHECK(same.max_ulp == 0);
    CHECK(same.failing_pixels == 0);
    CHECK(std::isinf(same.psnr));
    REQUIRE(same.ssim);
    CHECK(*same.ssim == 1.0);
    CHECK(same.worst.empty());

    Image c = g;
    c.at(7, 5, 1) = next_up(c.at(7, 5, 1));
    BufferComparison one = compare_buffers("b", g, c, {});
    CHECK_FALSE(one.pass);  // default tolerance: bit-exact
    CHECK(one.max_ulp == 1);
    CHECK(one.failing_pixels == 1);
    CHECK(one.differing_elements == 1);
    REQUIRE(one.first_failing);
    CHECK(one.first_failing->x == 7);
    CHECK(one.first_failing->y == 5);
    CHECK(one.first_failing->golden[1] == g.at(7, 5, 1));
    CHECK(one.first_failing->candidate[1] == c.at(7, 5, 1));
    Tolerance ulp1;
    ulp1.ulp = 1;
    CHECK(compare_buffers("b", g, c, ulp1).pass);
    Tolerance abs;
    abs.abs = 1e-6;
    CHECK(compare_buffers("b", g, c, abs).pass);
    Tolerance pixels;
    pixels.max_failing_pixels = 1;
    CHECK(compare_buffers("b", g, c, pixels).pass);

    // A relative tolerance scales with |golden|.
    Image big = g;
    big.at(2, 2, 0) = 1000.0f;
    Image big_c = big;
    big_c.at(2, 2, 0) = 1000.01f;
    Tolerance rel;
    rel.rel = 1e-4;
    CHECK(compare_buffers("b", big, big_c, rel).pass);
    rel.rel = 1e-6;
    const BufferComparison tight = compare_buffers("b", big, big_c, rel);
    CHECK_FALSE(tight.pass);
    CHECK(tight.max_rel == doctest::Approx(1e-5).epsilon(0.01));
}

TEST_CASE("compare_buffers: NaN rules, worst pixels ordered, threshold share") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Image g(8, 8, 1, 0.0f), c(8, 8, 1, 0.0f);
    g.at(1, 1) = nan;
    c.at(1, 1) = nan;  // NaN vs NaN: equal
    BufferComparison r = compare_buffers("b", g, c, {});
    CHECK(r.pass);
    CHECK(r.nan_mismatches == 0);
    c.at(2, 2) = nan;  // NaN vs number: a failure no tolerance admits
    Tolerance loose;
    loose.abs = 1e30;
    loose.max_failing_pixels = 1000;
    r = compare_buffers("b", g, c, loose);
    CHECK_FALSE(r.pass);
    CHECK(r.nan_mismatches == 1);

    Image a(10, 1, 1, 0.0f), b(10, 1, 1, 0.0f);
    b.at(3, 0) = 0.5f;
    b.at(6, 0) = 0.5f;  // tie with (3, 0): row-major order decides
    b.at(8, 0) = 0.9f;
    b.at(9, 0) = 0.1f;
    CompareOptions options;
    options.worst_pixels = 3;
    options.threshold = 0.2;
    r = compare_buffers("b", a, b, {}, options);
    REQUIRE(r.worst.size() == 3);
    CHECK(r.worst[0].x == 8);
    CHECK(r.worst[1].x == 3);
    CHECK(r.worst[2].x == 6);
    CHECK(r.pixels_over_threshold == 3);
    CHECK(r.failing_pixels == 4);
    CHECK(r.first_failing->x == 3);
    CHECK(r.mean_abs == doctest::Approx((0.5 + 0.5 + 0.9 + 0.1) / 10).epsilon(1e-7));
    CHECK(!r.ssim);  // smaller than the SSIM window
}

TEST_CASE("compare_buffers: ring errors for image-like buffers") {
    Image g(40, 30, 3, 0.25f), c(40, 30, 3, 0.5f);
    const RingLayout layout = ring_layout(40, 30, {20, 15}, 35.0f);
    CompareOptions options;
    options.rings = &layout;
    const BufferComparison r = compare_buffers("final", g, c, {}, options);
    REQUIRE(r.rings.size() == 20);
    for (const RingStats& s : r.rings)
        if (s.pixels) CHECK(s.mse == 0.0625);
    CHECK(r.rmse == 0.25);
}

TEST_CASE("tolerance options and files: values and errors") {
    using test::contains;
    using test::error_message;
    ToleranceTable table;
    parse_tolerance_option("final:abs=1e-6,rel=0.5,ulp=3,pixels=10", table);
    parse_tolerance_option("*:ulp=1", table);
    CHECK(table.for_buffer("final").abs == 1e-6);
    CHECK(table.for_buffer("final").rel == 0.5);
    CHECK(table.for_buffer("final").ulp == 3);
    CHECK(table.for_buffer("final").max_failing_pixels == 10);
    CHECK(table.for_buffer("other").ulp == 1);
    CHECK(contains(error_message([&] { parse_tolerance_option("final", table); }), "NAME:abs"));
    CHECK(contains(error_message([&] { parse_tolerance_option("final:abs=x", table); }),
                   "not a valid value for abs"));
    CHECK(contains(error_message([&] { parse_tolerance_option("final:abs=-1", table); }), ">= 0"));
    CHECK(contains(error_message([&] { parse_tolerance_option("final:speed=1", table); }),
                   "unknown key 'speed'"));

    test::TempDir dir("tolerances");
    const std::string path = dir.file("t.json");
    test::write_bytes(path,
                      "{\n  \"final\": {\"abs\": 0.001, \"reason\": \"GPU pow\"},\n"
                      "  \"*\": {\"ulp\": 2}\n}\n");
    const ToleranceTable file = read_tolerance_file(path);
    CHECK(file.for_buffer("final").abs == 0.001);
    CHECK(file.for_buffer("final").reason == "GPU pow");
    CHECK(file.for_buffer("gbuffer_albedo").ulp == 2);
    test::write_bytes(path, "{\n  \"final\": {\"abs\": 0.001,\n    \"speed\": 1}\n}\n");
    CHECK(contains(error_message([&] { read_tolerance_file(path); }), "t.json:3"));
    CHECK(contains(error_message([&] { read_tolerance_file(path); }), "unknown key \"speed\""));
    test::write_bytes(path, "{\n  \"final\": {\"ulp\": 1.5}\n}\n");
    CHECK(contains(error_message([&] { read_tolerance_file(path); }), "must be an integer"));
    test::write_bytes(path, "{\n  \"final\": {\"abs\": 1e-3,,}\n}\n");
    CHECK(contains(error_message([&] { read_tolerance_file(path); }), "t.json:2"));
    CHECK(contains(error_message([&] { read_tolerance_file(dir.file("missing.json")); }),
                   "missing.json"));
}

TEST_CASE("compare_id_buffers: edge and interior mismatches, tolerances, the agree mask") {
    // Golden: id 1 on the left half, 2 on the right half of an 8x6 image (columns 3 | 4).
    Image g(8, 6, 1, 1.0f);
    for (int y = 0; y < 6; ++y)
        for (int x = 4; x < 8; ++x) g.at(x, y) = 2.0f;
    Image c = g;
    c.at(3, 2) = 2.0f;   // next to the boundary: an edge mismatch
    c.at(0, 0) = -1.0f;  // a corner whose in-image neighbours all show 1: interior
    c.at(6, 4) = 7.0f;   // interior
    IdComparison r = compare_id_buffers("gbuffer_primitive_id", g, c, {});
    CHECK(r.edge_pixels == 12);  // columns 3 and 4
    CHECK(r.edge_mismatches == 1);
    CHECK(r.interior_mismatches == 2);
    CHECK_FALSE(r.pass);
    REQUIRE(r.mismatches.size() == 3);
    CHECK(r.mismatches[0].x == 0);  // interior ones first, row-major
    CHECK(r.mismatches[1].x == 6);
    CHECK(r.mismatches[2].edge);
    CHECK(r.mismatches[2].x == 3);
    CHECK(r.agree[2 * 8 + 3] == 0);
    CHECK(r.agree[2 * 8 + 2] == 1);
    CHECK(r.mismatch_map.at(3, 2) == 1.0f);
    CHECK(r.mismatch_map.at(6, 4) == 2.0f);
    Tolerance t;
    t.max_interior_mismatches = 2;
    t.max_edge_mismatch_share = 0.1;  // floor(0.1 x 12) = 1 edge mismatch allowed
    r = compare_id_buffers("gbuffer_primitive_id", g, c, t);
    CHECK(r.allowed_edge_mismatches == 1);
    CHECK(r.pass);
    t.max_edge_mismatch_share = 0.08;  // floor(0.96) = 0
    CHECK_FALSE(compare_id_buffers("gbuffer_primitive_id", g, c, t).pass);
    // -0 equals +0, NaN equals NaN: the same id.
    Image a(2, 1, 1, 0.0f), b(2, 1, 1, -0.0f);
    a.at(1, 0) = b.at(1, 0) = std::numeric_limits<float>::quiet_NaN();
    CHECK(compare_id_buffers("m", a, b, {}).pass);
}

TEST_CASE(
    "compare_buffers: a mask leaves pixels out, non-finite values are a convention mismatch") {
    Image g(12, 12, 1, 2.0f), c = g;
    c.at(5, 5) = 3.0f;
    std::vector<std::uint8_t> mask(144, 1);
    mask[5 * 12 + 5] = 0;
    CompareOptions options;
    options.mask = &mask;
    BufferComparison r = compare_buffers("d", g, c, {}, options);
    CHECK(r.pass);
    CHECK(r.masked_pixels == 1);
    CHECK(r.max_abs == 0.0);
    CHECK(r.ssim == 1.0);  // the masked pixel takes the golden's value
    CHECK_FALSE(compare_buffers("d", g, c, {}).pass);

    // A depth cleared to +inf on the background: never within tolerance, no finite error figure
    // polluted by it.
    Image depth(4, 1, 1, 0.0f), inf_cleared = depth;
    depth.at(0, 0) = 1.5f;
    inf_cleared.at(0, 0) = 1.5f;
    for (int x = 1; x < 4; ++x) inf_cleared.at(x, 0) = std::numeric_limits<float>::infinity();
    Tolerance loose;
    loose.abs = 1e30;
    r = compare_buffers("d", depth, inf_cleared, loose);
    CHECK_FALSE(r.pass);
    CHECK(r.nonfinite_mismatches == 3);
    CHECK(r.nan_mismatches == 0);
    CHECK(r.max_abs == 0.0);
    CHECK(r.psnr == std::numeric_limits<double>::infinity());  // over the finite pairs only
    // Without a --threshold, "over threshold" counts the pixels out of tolerance.
    CHECK(r.pixels_over_threshold == r.failing_pixels);
    Image rel_g(3, 1, 1, 100.0f), rel_c(3, 1, 1, 100.001f);
    Tolerance rel;
    rel.rel = 1e-4;
    r = compare_buffers("d", rel_g, rel_c, rel);
    CHECK(r.pass);
    CHECK(r.pixels_over_threshold == 0);  // within the relative tolerance: not "over"
}

TEST_CASE("tolerance profiles: every entry has a reason, id limits from files and options") {
    for (const std::string& name : tolerance_profile_names()) {
        const ToleranceTable table = tolerance_profile(name);
        CAPTURE(name);
        CHECK_FALSE(table.fallback.reason.empty());
        for (const auto& entry : table.buffers) {
            const std::string& buffer = entry.first;
            CAPTURE(buffer);
            CHECK_FALSE(entry.second.reason.empty());
        }
    }
    CHECK(tolerance_profile("bit-exact").buffers.empty());
    const ToleranceTable raster = tolerance_profile("gpu-raster");
    CHECK(raster.for_buffer("gbuffer_primitive_id").max_edge_mismatch_share > 0.0);
    CHECK(raster.for_buffer("gbuffer_primitive_id").max_interior_mismatches == 0);
    CHECK(raster.for_buffer("gbuffer_view_depth").rel > 0.0);
    CHECK(raster.for_buffer("something_else").abs == 0.0);  // undeclared buffers stay bit-exact
    CHECK(test::contains(test::error_message([] { tolerance_profile("gpu-fast"); }),
                         "unknown profile"));

    ToleranceTable table = raster;
    parse_tolerance_option("gbuffer_primitive_id:edge=0.5,interior=3", table);
    CHECK(table.for_buffer("gbuffer_primitive_id").max_edge_mismatch_share == 0.5);
    CHECK(table.for_buffer("gbuffer_primitive_id").max_interior_mismatches == 3);
    CHECK(test::contains(
        test::error_message([&] { parse_tolerance_option("ids:edge=1.5", table); }), "[0, 1]"));
    test::TempDir dir("profiles");
    const std::string path = dir.file("t.json");
    test::write_bytes(path,
                      "{\"gbuffer_material_id\": {\"edge_mismatch_share\": 0.01, "
                      "\"interior_mismatches\": 2}}");
    read_tolerance_file(path, table);  // merged over the profile
    CHECK(table.for_buffer("gbuffer_material_id").max_interior_mismatches == 2);
    CHECK(table.for_buffer("gbuffer_view_depth").rel > 0.0);  // the profile's entry is kept
    CHECK(test::contains(table.for_buffer("gbuffer_material_id").reason, "t.json"));
}

TEST_CASE("tolerance patterns: exact name, then the most specific pattern, then the fallback") {
    CHECK(tolerance_pattern_matches("lp_*", "lp_color"));
    CHECK(tolerance_pattern_matches("*_valid", "gaze_valid"));
    CHECK(tolerance_pattern_matches("lp_*_id", "lp_gbuffer_primitive_id"));
    CHECK(tolerance_pattern_matches("*", ""));
    CHECK_FALSE(tolerance_pattern_matches("lp_*", "gaze_color"));
    CHECK_FALSE(tolerance_pattern_matches("lp_*_id", "lp_gbuffer_primitive"));
    ToleranceTable table;
    parse_tolerance_option("*:abs=1", table);
    parse_tolerance_option("lp_*:abs=2", table);
    parse_tolerance_option("lp_gbuffer_*:abs=3", table);
    parse_tolerance_option("lp_color:abs=4", table);
    CHECK(table.for_buffer("lp_color").abs == 4.0);
    CHECK(table.for_buffer("lp_gbuffer_albedo").abs == 3.0);
    CHECK(table.for_buffer("lp_valid").abs == 2.0);
    CHECK(table.for_buffer("final").abs == 1.0);
    CHECK(table.key_for("lp_valid") == "lp_*");
    parse_tolerance_option("taa_age:edge=0.1", table);
    CHECK(table.for_buffer("taa_age").integer);  // edge= compares as integers
}

TEST_CASE("GPU profiles: every buffer of every golden's rendering modes has its own entry") {
    // The building blocks (rng, halton, geometry, camera rays, the splat) and the converged
    // reference are not what a GPU port produces; every other buffer must be declared, with a
    // reason, so that a correct port is not failed by a bit-exact default.
    const std::vector<std::string> blocks = {"rng",         "halton", "geometry",
                                             "camera-rays", "splat",  "pathtrace-reference"};
    int checked = 0;
    for (const GoldenCase& c : load_golden_cases(FOVREF_SOURCE_DIR "/golden/cases.json")) {
        if (std::find(blocks.begin(), blocks.end(), c.mode) != blocks.end()) continue;
        const Manifest m = read_manifest(FOVREF_SOURCE_DIR "/golden/" + c.name);
        std::vector<std::string> names;
        for (const ManifestBuffer& b : m.buffers) names.push_back(b.name);
        for (const char* profile : {"gpu-raster", "gpu-rt"}) {
            const ToleranceTable table = tolerance_profile(profile, names);
            for (const std::string& name : names) {
                CAPTURE(c.name);
                CAPTURE(profile);
                CAPTURE(name);
                CHECK_FALSE(table.key_for(name).empty());
                ++checked;
            }
        }
    }
    CHECK(checked > 1000);
    // A golden that runs BMFR takes the denoised entries for what follows it
    const ToleranceTable plain = tolerance_profile("gpu-rt", {"final"});
    const ToleranceTable denoised = tolerance_profile("gpu-rt", {"final", "bmfr_taa"});
    CHECK(denoised.for_buffer("final").rel > plain.for_buffer("final").rel);
}
