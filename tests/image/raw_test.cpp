// Raw binary32 dumps (what GPU tools write): interleaved/planar, top/bottom first, endianness,
// exact size checks.
#include <doctest/doctest.h>

#include <cstring>

#include "ref/image/image_io.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

std::string floats_bytes(const std::vector<float>& values, bool big_endian) {
    std::string bytes;
    for (const float v : values) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &v, 4);
        for (int b = 0; b < 4; ++b)
            bytes += static_cast<char>((bits >> (big_endian ? 8 * (3 - b) : 8 * b)) & 0xff);
    }
    return bytes;
}

}  // namespace

TEST_CASE("raw binary32: layouts") {
    test::TempDir dir("raw");
    const std::string path = dir.file("a.raw");
    // A 2x2 RGB image: pixel (x, y) channel c = 100 y + 10 x + c.
    Image expected(2, 2, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x)
            for (int c = 0; c < 3; ++c)
                expected.at(x, y, c) = static_cast<float>(100 * y + 10 * x + c);
    RawLayout layout;
    layout.width = 2;
    layout.height = 2;
    layout.channels = 3;
    test::write_bytes(path, floats_bytes(expected.data, false));
    CHECK(read_raw(path, layout) == expected);
    // Planar, bottom row first, big-endian.
    std::vector<float> planar;
    for (int c = 0; c < 3; ++c)
        for (int y = 1; y >= 0; --y)
            for (int x = 0; x < 2; ++x) planar.push_back(expected.at(x, y, c));
    test::write_bytes(path, floats_bytes(planar, true));
    layout.planar = layout.bottom_up = layout.big_endian = true;
    CHECK(read_raw(path, layout) == expected);
}

TEST_CASE("raw binary32: wrong sizes are errors naming the file") {
    using test::contains;
    using test::error_message;
    test::TempDir dir("raw-errors");
    const std::string path = dir.file("b.raw");
    test::write_bytes(path, std::string(47, '\0'));
    RawLayout layout;
    layout.width = 2;
    layout.height = 2;
    layout.channels = 3;
    CHECK(contains(error_message([&] { read_raw(path, layout); }),
                   "needs 48 bytes, the file has 47"));
    CHECK(contains(error_message([&] { read_raw(path, layout); }), "b.raw"));
    layout.width = 0;
    CHECK(contains(error_message([&] { read_raw(path, layout); }), "out of range"));
    layout.width = 2;
    CHECK(contains(error_message([&] { read_raw(dir.file("none.raw"), layout); }), "none.raw"));
    test::write_bytes(path, "");
    CHECK(contains(error_message([&] { read_raw(path, layout); }), "the file has 0"));
}
