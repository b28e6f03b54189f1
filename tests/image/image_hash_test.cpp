// Image basics: construction, bitwise equality, SHA-256 and the canonical buffer hash (SPEC §1).
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <string>

#include "image_test_util.h"
#include "ref/image/image.h"

using namespace fovref;

TEST_CASE("image: constructor fills and sizes the buffer") {
    const Image image(4, 3, 2, 0.25f);
    CHECK(image.data.size() == 24);
    CHECK(image.pixel_count() == 12);
    for (float v : image.data) CHECK(v == 0.25f);
    CHECK(image.index(1, 2, 1) == (2 * 4 + 1) * 2 + 1);
    CHECK_THROWS_AS(Image(-1, 2, 3), Error);
}

TEST_CASE("image: bit_equal compares bit patterns, operator== compares values") {
    Image a(2, 1, 1), b(2, 1, 1);
    a.data = {0.0f, std::bit_cast<float>(0x7fc00001u)};
    b.data = {-0.0f, std::bit_cast<float>(0x7fc00001u)};
    CHECK_FALSE(bit_equal(a, b));  // +0 vs -0
    b.data[0] = 0.0f;
    CHECK(bit_equal(a, b));  // same NaN payload
    CHECK_FALSE(a == b);     // NaN != NaN as values
    b.data[1] = std::bit_cast<float>(0x7fc00002u);
    CHECK_FALSE(bit_equal(a, b));                            // different payload
    CHECK_FALSE(bit_equal(Image(2, 1, 1), Image(1, 2, 1)));  // shape counts
}

TEST_CASE("sha256_hex: FIPS 180-2 known vectors") {
    CHECK(sha256_hex("", 0) == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    CHECK(sha256_hex("abc", 3) ==
          "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    const std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    CHECK(sha256_hex(two_blocks.data(), two_blocks.size()) ==
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST_CASE("canonical_sha256: hash of the hand-serialised little-endian binary32 data") {
    // 2x1 pixels, 2 channels: (1, -2), (0.5, NaN with payload 1). Written out by hand:
    // 1.0f = 0x3f800000, -2.0f = 0xc0000000, 0.5f = 0x3f000000, NaN = 0x7fc00001, each
    // least significant byte first, pixels left to right, channels interleaved.
    Image image(2, 1, 2);
    image.data = {1.0f, -2.0f, 0.5f, std::bit_cast<float>(0x7fc00001u)};
    const unsigned char bytes[] = {0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0xc0,
                                   0x00, 0x00, 0x00, 0x3f, 0x01, 0x00, 0xc0, 0x7f};
    CHECK(canonical_sha256(image) == sha256_hex(bytes, sizeof(bytes)));
    CHECK(canonical_sha256(Image()) == sha256_hex("", 0));

    // Row order: top row first. Swapping the two rows of a 1x2 image changes the hash to the
    // hash of the swapped bytes.
    Image column(1, 2, 1);
    column.data = {1.0f, -2.0f};
    const unsigned char column_bytes[] = {0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0xc0};
    CHECK(canonical_sha256(column) == sha256_hex(column_bytes, sizeof(column_bytes)));
}

TEST_CASE("canonical_sha256: images larger than the internal 64 KiB buffer") {
    // 150x100x2 floats = 120000 bytes: crosses the serialisation buffer boundary once, with a
    // partial tail. Reference: one contiguous little-endian serialisation.
    test::SplitMix64 rng(7);
    Image image(150, 100, 2);
    std::string bytes;
    for (float& v : image.data) {
        const std::uint32_t bits = rng.next_u32();
        v = std::bit_cast<float>(bits);
        for (int i = 0; i < 4; ++i) bytes += static_cast<char>((bits >> (8 * i)) & 0xff);
    }
    CHECK(canonical_sha256(image) == sha256_hex(bytes.data(), bytes.size()));
    image.data[12345] = std::bit_cast<float>(std::bit_cast<std::uint32_t>(image.data[12345]) ^ 1u);
    CHECK(canonical_sha256(image) != sha256_hex(bytes.data(), bytes.size()));
}
