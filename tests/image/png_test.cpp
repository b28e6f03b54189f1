// PNG previews (SPEC §1): 8-bit sRGB write with clamping and round-to-nearest, read with optional
// sRGB decode, 16-bit read, and the sRGB transfer functions themselves.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "image_test_util.h"
#include "ref/image/image_io.h"

using namespace fovref;

namespace {

// ---- A minimal PNG encoder for 16-bit test files (stb_image_write only writes 8-bit) --------
// Stored (uncompressed) deflate block inside a zlib stream; CRC-32 and Adler-32 per RFC 2083 /
// RFC 1950, computed here so that the file is valid for any decoder.

std::uint32_t crc32(const std::string& bytes) {
    std::uint32_t crc = 0xffffffffu;
    for (unsigned char byte : bytes) {
        crc ^= byte;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return crc ^ 0xffffffffu;
}

std::string be32(std::uint32_t v) {
    return {static_cast<char>(v >> 24), static_cast<char>((v >> 16) & 0xff),
            static_cast<char>((v >> 8) & 0xff), static_cast<char>(v & 0xff)};
}

std::string chunk(const std::string& type, const std::string& data) {
    return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(crc32(type + data));
}

/// PNG with 16-bit samples; `raster` holds each row's filter byte (0) and big-endian samples.
std::string png16(std::uint32_t width, std::uint32_t height, char colour_type,
                  const std::string& raster) {
    std::string ihdr = be32(width) + be32(height) + std::string{16, colour_type, 0, 0, 0};
    std::uint32_t a = 1, b = 0;
    for (unsigned char byte : raster) {
        a = (a + byte) % 65521u;
        b = (b + a) % 65521u;
    }
    const auto n = static_cast<std::uint16_t>(raster.size());
    std::string zlib = {0x78,
                        0x01,
                        0x01,
                        static_cast<char>(n & 0xff),
                        static_cast<char>(n >> 8),
                        static_cast<char>(~n & 0xff),
                        static_cast<char>((~n >> 8) & 0xff)};
    zlib += raster + be32((b << 16) | a);
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", zlib) +
           chunk("IEND", "");
}

}  // namespace

TEST_CASE("srgb: IEC 61966-2-1 values and inverse") {
    CHECK(srgb_encode(0.0f) == 0.0f);
    CHECK(srgb_decode(0.0f) == 0.0f);
    // 1 maps to 1 within 1 ulp of 1 (1.055f - 0.055f is not exactly 1 in binary32).
    CHECK(std::fabs(srgb_encode(1.0f) - 1.0f) <= 6e-8f);
    CHECK(std::fabs(srgb_decode(1.0f) - 1.0f) <= 1.2e-7f);
    // Linear segment.
    CHECK(srgb_encode(0.001f) == 12.92f * 0.001f);
    CHECK(srgb_decode(0.02f) == 0.02f / 12.92f);
    // Against the binary64 formula (libm, allowed in tests): dm::pow is within 1 ulp and the
    // surrounding float operations add a few more roundings, so 4e-7 relative (~3 ulp).
    for (int i = 1; i <= 1000; ++i) {
        const float x = static_cast<float>(i) / 1000.0f;
        const double encoded = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055;
        const double decoded = x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4);
        CAPTURE(x);
        CHECK(std::fabs(srgb_encode(x) - encoded) <= 4e-7 * encoded);
        CHECK(std::fabs(srgb_decode(x) - decoded) <= 4e-7 * decoded);
        CHECK(std::fabs(srgb_decode(srgb_encode(x)) - x) <= 1e-6f * x);
    }
}

TEST_CASE("png: every 8-bit code round-trips exactly") {
    // Values that are exact in 8 bits: linear = srgb_decode(k/255). Writing encodes them back to
    // code k (the encode/decode error is ~1e-6, far below half a code), so reading reproduces
    // the same floats bit for bit; alpha is stored linearly.
    test::TempDir dir("png-codes");
    Image image(256, 1, 4);
    for (int k = 0; k < 256; ++k) {
        const float code = static_cast<float>(k) / 255.0f;
        image.at(k, 0, 0) = srgb_decode(code);
        image.at(k, 0, 1) = srgb_decode(static_cast<float>(255 - k) / 255.0f);
        image.at(k, 0, 2) = srgb_decode(static_cast<float>((k * 7) % 256) / 255.0f);
        image.at(k, 0, 3) = code;
    }
    const std::string path = dir.file("codes.png");
    write_png(path, image);
    CHECK(bit_equal(read_png(path), image));
    const Image raw = read_png(path, false);
    for (int k = 0; k < 256; ++k) {
        CHECK(raw.at(k, 0, 0) == static_cast<float>(k) / 255.0f);
        CHECK(raw.at(k, 0, 3) == static_cast<float>(k) / 255.0f);
    }
}

TEST_CASE("png: arbitrary values round-trip to the nearest code") {
    test::TempDir dir("png-values");
    test::SplitMix64 rng(3);
    Image image(37, 11, 3);
    for (float& v : image.data) v = rng.unit();
    const std::string path = dir.file("values.png");
    write_png(path, image);
    const Image raw = read_png(path, false);
    const Image decoded = read_png(path);
    REQUIRE(raw.same_shape(image));
    for (std::size_t i = 0; i < image.data.size(); ++i) {
        // Round to nearest: the stored code is within half a code of the encoded value (plus
        // 1e-6 for the float rounding of encode and of k/255).
        CHECK(std::fabs(raw.data[i] - srgb_encode(image.data[i])) <= 0.5f / 255.0f + 1e-6f);
        // In linear terms the decode slope is at most 2.4/1.055 * (1.055/1.055)^1.4 = 2.275 (at
        // 1), so the error is at most 2.275 * 0.5/255 < 1.14/255.
        CHECK(std::fabs(decoded.data[i] - image.data[i]) <= 1.14f / 255.0f);
    }
}

TEST_CASE("png: clamping, channel layouts") {
    test::TempDir dir("png-layout");
    const std::string path = dir.file("layout.png");

    // Grey: NaN and negatives -> 0, above 1 -> 1.
    Image grey(4, 1, 1);
    grey.data = {-1.0f, std::nanf(""), 2.0f, std::numeric_limits<float>::infinity()};
    write_png(path, grey);
    Image back = read_png(path, false);
    REQUIRE(back.same_shape(grey));
    CHECK(back.data == std::vector<float>{0.0f, 0.0f, 1.0f, 1.0f});

    // Two channels are written as RGB with B = 0 and read back as 3 channels.
    Image two(2, 1, 2);
    two.data = {1.0f, 0.0f, 0.0f, 1.0f};
    write_png(path, two);
    back = read_png(path, false);
    REQUIRE(back.same_shape(Image(2, 1, 3)));
    CHECK(back.data == std::vector<float>{1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f});

    // Top row first: a 1x2 image with white on top.
    Image column(1, 2, 1);
    column.data = {1.0f, 0.0f};
    write_png(path, column);
    CHECK(read_png(path, false).data == std::vector<float>{1.0f, 0.0f});

    CHECK(test::contains(test::error_message([&] { write_png(path, Image(1, 1, 5)); }),
                         "layout.png"));
}

TEST_CASE("png: 16-bit files") {
    test::TempDir dir("png-16");
    const std::string path = dir.file("sixteen.png");
    // Grey 3x1: 0x0000, 0xffff, 0x8000.
    test::write_bytes(path, png16(3, 1, 0, std::string("\0\0\0\xff\xff\x80\0", 7)));
    Image image = read_png(path, false);
    REQUIRE(image.same_shape(Image(3, 1, 1)));
    CHECK(image.data == std::vector<float>{0.0f, 1.0f, 32768.0f / 65535.0f});
    CHECK(read_png(path, true).at(2, 0) == srgb_decode(32768.0f / 65535.0f));

    // RGBA 1x1: colour decoded, alpha linear.
    test::write_bytes(path, png16(1, 1, 6, std::string("\0\x80\0\x40\0\xff\xff\x80\0", 9)));
    image = read_png(path, true);
    REQUIRE(image.same_shape(Image(1, 1, 4)));
    CHECK(image.data[0] == srgb_decode(32768.0f / 65535.0f));
    CHECK(image.data[1] == srgb_decode(16384.0f / 65535.0f));
    CHECK(image.data[2] == srgb_decode(1.0f));
    CHECK(image.data[3] == 32768.0f / 65535.0f);
}
