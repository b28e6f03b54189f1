// PFM reading and writing (SPEC §1): bit-exact round trips in both byte orders, and hand-built
// files that pin the bottom-to-top row order, the byte order and the header syntax.
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <string>

#include "image_test_util.h"
#include "ref/image/image_io.h"

using namespace fovref;

namespace {

/// Special values first (signed zeros, subnormals, infinities, NaNs with payloads and sign,
/// extremes), then random bit patterns, which cover every class of binary32 value.
Image special_image(int width, int height, int channels, std::uint64_t seed) {
    Image image(width, height, channels);
    const std::uint32_t specials[] = {
        0x00000000u,  // +0
        0x80000000u,  // -0
        0x00000001u,  // smallest subnormal
        0x807fffffu,  // largest negative subnormal
        0x7f800000u,  // +inf
        0xff800000u,  // -inf
        0x7fc00000u,  // quiet NaN
        0x7fc12345u,  // quiet NaN with payload
        0xffc00001u,  // negative NaN with payload
        0x7f800001u,  // signalling NaN
        0x7f7fffffu,  // FLT_MAX
        0x00800000u,  // FLT_MIN
        0x3f800000u,  // 1
        0xbf800000u,  // -1
    };
    test::SplitMix64 rng(seed);
    for (std::size_t i = 0; i < image.data.size(); ++i)
        image.data[i] =
            std::bit_cast<float>(i < std::size(specials) ? specials[i] : rng.next_u32());
    return image;
}

std::string le(float v) {
    const std::uint32_t b = std::bit_cast<std::uint32_t>(v);
    return {static_cast<char>(b & 0xff), static_cast<char>((b >> 8) & 0xff),
            static_cast<char>((b >> 16) & 0xff), static_cast<char>(b >> 24)};
}

std::string be(float v) {
    std::string s = le(v);
    return {s[3], s[2], s[1], s[0]};
}

}  // namespace

TEST_CASE("pfm: bit-exact round trips, PF and Pf, both byte orders") {
    test::TempDir dir("pfm-roundtrip");
    for (int channels : {1, 3}) {
        for (Endian endian : {Endian::little, Endian::big}) {
            CAPTURE(channels);
            CAPTURE(static_cast<int>(endian));
            const Image image = special_image(7, 5, channels, 11 + static_cast<unsigned>(channels));
            const std::string path = dir.file("a.pfm");
            write_pfm(path, image, endian);
            const Image back = read_pfm(path);
            CHECK(back.same_shape(image));
            CHECK(bit_equal(back, image));
            // The file size is header + exactly the raster.
            const std::string bytes = read_file(path);
            const std::string header = std::string(channels == 3 ? "PF" : "Pf") + "\n7 5\n" +
                                       (endian == Endian::little ? "-1.0\n" : "1.0\n");
            CHECK(bytes.substr(0, header.size()) == header);
            CHECK(bytes.size() == header.size() + image.data.size() * 4);
        }
    }
}

TEST_CASE("pfm: hand-built files pin row order (bottom to top) and byte order") {
    test::TempDir dir("pfm-hand");
    // Pf, 2x2, little-endian. File rows: bottom row (1, 2) first, then top row (3, 4).
    const std::string path = dir.file("hand.pfm");
    test::write_bytes(path, "Pf\n2 2\n-1\n" + le(1) + le(2) + le(3) + le(4));
    Image image = read_pfm(path);
    REQUIRE(image.width == 2);
    REQUIRE(image.height == 2);
    REQUIRE(image.channels == 1);
    CHECK(image.at(0, 0) == 3.0f);  // top-left
    CHECK(image.at(1, 0) == 4.0f);
    CHECK(image.at(0, 1) == 1.0f);  // bottom-left
    CHECK(image.at(1, 1) == 2.0f);

    // The writer produces exactly these bytes (scale written as -1.0).
    write_pfm(dir.file("out.pfm"), image, Endian::little);
    CHECK(read_file(dir.file("out.pfm")) == "Pf\n2 2\n-1.0\n" + le(1) + le(2) + le(3) + le(4));

    // PF, 1x2, big-endian (positive scale; its magnitude 4.5 is ignored), interleaved RGB.
    test::write_bytes(path,
                      "PF\n1 2\n4.5\n" + be(0.5f) + be(-1) + be(2) + be(10) + be(20) + be(30));
    image = read_pfm(path);
    REQUIRE(image.same_shape(Image(1, 2, 3)));
    CHECK(image.at(0, 0, 0) == 10.0f);  // top row came last in the file
    CHECK(image.at(0, 0, 1) == 20.0f);
    CHECK(image.at(0, 0, 2) == 30.0f);
    CHECK(image.at(0, 1, 0) == 0.5f);
    CHECK(image.at(0, 1, 1) == -1.0f);
    CHECK(image.at(0, 1, 2) == 2.0f);
    write_pfm(dir.file("out.pfm"), image, Endian::big);
    CHECK(read_file(dir.file("out.pfm")) ==
          "PF\n1 2\n1.0\n" + be(0.5f) + be(-1) + be(2) + be(10) + be(20) + be(30));
}

TEST_CASE("pfm: header whitespace rules") {
    test::TempDir dir("pfm-space");
    const std::string path = dir.file("ws.pfm");
    const std::string raster = le(1) + le(2);
    // Any run of whitespace between fields; exactly one whitespace byte before the raster.
    test::write_bytes(path, "Pf \t\r\n2\n\n 1  -1.000000\n" + raster);
    Image image = read_pfm(path);
    CHECK(image.width == 2);
    CHECK(image.at(1, 0) == 2.0f);
    test::write_bytes(path, "Pf\n2 1\n-1 " + raster);  // a space ends the scale as well
    CHECK(read_pfm(path).at(0, 0) == 1.0f);
    // A second whitespace byte after the scale is raster data, so the size no longer matches.
    test::write_bytes(path, "Pf\n2 1\n-1\n\n" + raster);
    CHECK(test::contains(test::error_message([&] { read_pfm(path); }), "trailing bytes"));
    // A raster that starts with whitespace-like bytes is read as data: 0x20202020 as a float.
    test::write_bytes(path, "Pf\n1 1\n-1\n    ");
    CHECK(std::bit_cast<std::uint32_t>(read_pfm(path).at(0, 0)) == 0x20202020u);
}

TEST_CASE("pfm: writer rejects what PFM cannot hold") {
    test::TempDir dir("pfm-write");
    const std::string path = dir.file("two.pfm");
    CHECK(test::contains(test::error_message([&] { write_pfm(path, Image(2, 2, 2)); }), "two.pfm"));
    CHECK(test::contains(test::error_message([&] { write_pfm(path, Image(0, 0, 3)); }), "empty"));
    Image broken(2, 2, 3);
    broken.data.pop_back();
    CHECK(test::contains(test::error_message([&] { write_pfm(path, broken); }), "needs 12"));
    CHECK_FALSE(std::filesystem::exists(path));
}
