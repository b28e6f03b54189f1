// EXR (SPEC §1): bit-exact float round trips for the channel layouts we write, and fixed files
// written by OpenEXR 3.1 itself with HALF and UINT channels for the read conversions.
#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include <ImfRgbaFile.h>
#include <ImfTiledRgbaFile.h>
#include "image_test_util.h"

#include "ref/image/image_io.h"

using namespace fovref;

namespace {

// 3x2 image, channels R,G,B of type HALF, NO_COMPRESSION, written by OpenEXR 3.1.5 from the
// values in the test below (all exactly representable in half).
const char half_rgb_exr[] =
    "\x76\x2f\x31\x01\x02\x00\x00\x00\x63\x68\x61\x6e\x6e\x65\x6c\x73\x00\x63\x68\x6c\x69\x73\x74"
    "\x00"
    "\x37\x00\x00\x00\x42\x00\x01\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x47"
    "\x00"
    "\x01\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x52\x00\x01\x00\x00\x00\x00"
    "\x00"
    "\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x00\x63\x6f\x6d\x70\x72\x65\x73\x73\x69\x6f\x6e\x00"
    "\x63"
    "\x6f\x6d\x70\x72\x65\x73\x73\x69\x6f\x6e\x00\x01\x00\x00\x00\x00\x64\x61\x74\x61\x57\x69\x6e"
    "\x64"
    "\x6f\x77\x00\x62\x6f\x78\x32\x69\x00\x10\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x02\x00"
    "\x00"
    "\x00\x01\x00\x00\x00\x64\x69\x73\x70\x6c\x61\x79\x57\x69\x6e\x64\x6f\x77\x00\x62\x6f\x78\x32"
    "\x69"
    "\x00\x10\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x02\x00\x00\x00\x01\x00\x00\x00\x6c\x69"
    "\x6e"
    "\x65\x4f\x72\x64\x65\x72\x00\x6c\x69\x6e\x65\x4f\x72\x64\x65\x72\x00\x01\x00\x00\x00\x00\x70"
    "\x69"
    "\x78\x65\x6c\x41\x73\x70\x65\x63\x74\x52\x61\x74\x69\x6f\x00\x66\x6c\x6f\x61\x74\x00\x04\x00"
    "\x00"
    "\x00\x00\x00\x80\x3f\x73\x63\x72\x65\x65\x6e\x57\x69\x6e\x64\x6f\x77\x43\x65\x6e\x74\x65\x72"
    "\x00"
    "\x76\x32\x66\x00\x08\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x73\x63\x72\x65\x65\x6e\x57"
    "\x69"
    "\x6e\x64\x6f\x77\x57\x69\x64\x74\x68\x00\x66\x6c\x6f\x61\x74\x00\x04\x00\x00\x00\x00\x00\x80"
    "\x3f"
    "\x00\x49\x01\x00\x00\x00\x00\x00\x00\x63\x01\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x12\x00"
    "\x00"
    "\x00\x00\x64\x00\x80\x00\xb0\x00\xc0\x00\x00\x00\x42\x00\x38\xff\x7b\x00\x34\x01\x00\x00\x00"
    "\x12"
    "\x00\x00\x00\x00\x44\x00\x3a\x40\x56\x00\x40\x00\x4c\x00\xbe\x00\x3c\x00\x48\x00\x18";

// 2x2 image, one UINT channel named "id", data window (5,7)-(6,8), NO_COMPRESSION, values
// 0, 1, 2^24, 2^32-1.
const char uint_id_exr[] =
    "\x76\x2f\x31\x01\x02\x00\x00\x00\x63\x68\x61\x6e\x6e\x65\x6c\x73\x00\x63\x68\x6c\x69\x73\x74"
    "\x00"
    "\x14\x00\x00\x00\x69\x64\x00\x00\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00"
    "\x00"
    "\x63\x6f\x6d\x70\x72\x65\x73\x73\x69\x6f\x6e\x00\x63\x6f\x6d\x70\x72\x65\x73\x73\x69\x6f\x6e"
    "\x00"
    "\x01\x00\x00\x00\x00\x64\x61\x74\x61\x57\x69\x6e\x64\x6f\x77\x00\x62\x6f\x78\x32\x69\x00\x10"
    "\x00"
    "\x00\x00\x05\x00\x00\x00\x07\x00\x00\x00\x06\x00\x00\x00\x08\x00\x00\x00\x64\x69\x73\x70\x6c"
    "\x61"
    "\x79\x57\x69\x6e\x64\x6f\x77\x00\x62\x6f\x78\x32\x69\x00\x10\x00\x00\x00\x00\x00\x00\x00\x00"
    "\x00"
    "\x00\x00\x01\x00\x00\x00\x01\x00\x00\x00\x6c\x69\x6e\x65\x4f\x72\x64\x65\x72\x00\x6c\x69\x6e"
    "\x65"
    "\x4f\x72\x64\x65\x72\x00\x01\x00\x00\x00\x00\x70\x69\x78\x65\x6c\x41\x73\x70\x65\x63\x74\x52"
    "\x61"
    "\x74\x69\x6f\x00\x66\x6c\x6f\x61\x74\x00\x04\x00\x00\x00\x00\x00\x80\x3f\x73\x63\x72\x65\x65"
    "\x6e"
    "\x57\x69\x6e\x64\x6f\x77\x43\x65\x6e\x74\x65\x72\x00\x76\x32\x66\x00\x08\x00\x00\x00\x00\x00"
    "\x00"
    "\x00\x00\x00\x00\x00\x73\x63\x72\x65\x65\x6e\x57\x69\x6e\x64\x6f\x77\x57\x69\x64\x74\x68\x00"
    "\x66"
    "\x6c\x6f\x61\x74\x00\x04\x00\x00\x00\x00\x00\x80\x3f\x00\x26\x01\x00\x00\x00\x00\x00\x00\x36"
    "\x01"
    "\x00\x00\x00\x00\x00\x00\x07\x00\x00\x00\x08\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x08"
    "\x00"
    "\x00\x00\x08\x00\x00\x00\x00\x00\x00\x01\xff\xff\xff\xff";

}  // namespace

TEST_CASE("exr: bit-exact float round trips for 1, 2, 3, 4 and 5 channels") {
    test::TempDir dir("exr-roundtrip");
    test::SplitMix64 rng(5);
    for (int channels : {1, 2, 3, 4, 5}) {
        CAPTURE(channels);
        Image image(9, 7, channels);
        // Random bit patterns: every float class, including NaN payloads, -0 and subnormals.
        for (float& v : image.data) v = std::bit_cast<float>(rng.next_u32());
        image.data[0] = -0.0f;
        image.data[1] = std::bit_cast<float>(0x00000001u);
        const std::string path = dir.file("round.exr");
        write_exr(path, image);
        const Image back = read_exr(path);
        CHECK(back.same_shape(image));
        CHECK(bit_equal(back, image));
    }
}

TEST_CASE("exr: written files are ZIP-compressed (smaller than raw for smooth data)") {
    test::TempDir dir("exr-zip");
    Image image(64, 64, 3, 0.5f);
    const std::string path = dir.file("flat.exr");
    write_exr(path, image);
    // Raw float data is 49152 bytes; ZIP of a constant image is a small fraction of that.
    CHECK(read_file(path).size() < 4096);
    CHECK(bit_equal(read_exr(path), image));
}

TEST_CASE("exr: HALF and UINT channels are converted to float") {
    test::TempDir dir("exr-types");
    const std::string half_path = dir.file("half.exr");
    test::write_bytes(half_path, std::string(half_rgb_exr, sizeof(half_rgb_exr) - 1));
    const Image rgb = read_exr(half_path);
    REQUIRE(rgb.same_shape(Image(3, 2, 3)));
    CHECK(rgb.data == std::vector<float>{0.5f, -2.0f, 1024.0f, 65504.0f, 0.0f, -0.0f, 0.25f, 3.0f,
                                         -0.125f, 1.0f, 2.0f, 4.0f, 8.0f, 16.0f, 0.75f,
                                         0.001953125f, -1.5f, 100.0f});
    CHECK(std::bit_cast<std::uint32_t>(rgb.at(1, 0, 2)) == 0x80000000u);  // -0 kept

    const std::string uint_path = dir.file("uint.exr");
    test::write_bytes(uint_path, std::string(uint_id_exr, sizeof(uint_id_exr) - 1));
    const Image id = read_exr(uint_path);
    REQUIRE(id.same_shape(Image(2, 2, 1)));  // the data window's offset is dropped
    CHECK(id.data == std::vector<float>{0.0f, 1.0f, 16777216.0f, 4294967296.0f});
}

TEST_CASE("exr: read_image / write_image dispatch on the extension, any case") {
    test::TempDir dir("exr-dispatch");
    Image image(3, 2, 4);
    for (std::size_t i = 0; i < image.data.size(); ++i) image.data[i] = static_cast<float>(i);
    for (const char* name : {"a.exr", "b.EXR", "c.pfm", "d.Pfm"}) {
        CAPTURE(name);
        Image written = image;
        if (test::contains(name, "pfm") || test::contains(name, "Pfm"))
            written = Image(3, 2, 3, 1.5f);
        write_image(dir.file(name), written);
        CHECK(bit_equal(read_image(dir.file(name)), written));
    }
    Image grey(2, 2, 1, 1.0f);
    write_image(dir.file("e.PNG"), grey);
    CHECK(read_image(dir.file("e.PNG")).data == grey.data);
    const std::string message = test::error_message([&] { write_image(dir.file("f.bmp"), grey); });
    CHECK(test::contains(message, "f.bmp"));
    CHECK(test::contains(message, ".bmp"));
    CHECK(test::contains(test::error_message([&] { read_image(dir.file("noext")); }), "noext"));
}

TEST_CASE("exr: a forged data window fails before allocating") {
    // Patch the UINT fixture's data window to (0,0)-(99999,99999): 10^10 pixels on a 326-byte
    // file. The reader must throw fovref::Error (a 40 GB allocation would throw bad_alloc).
    test::TempDir dir("exr-forged");
    std::string bytes(uint_id_exr, sizeof(uint_id_exr) - 1);
    const std::string key = std::string("dataWindow\0box2i\0", 17);
    const std::size_t at = bytes.find(key);
    REQUIRE(at != std::string::npos);
    const std::size_t box = at + key.size() + 4;                  // after the attribute's byte size
    const std::string corner = {'\x9f', '\x86', '\x01', '\x00'};  // 99999 little-endian
    bytes.replace(box, 16, std::string(8, '\0') + corner + corner);
    const std::string path = dir.file("forged.exr");
    test::write_bytes(path, bytes);
    const std::string message = test::error_message([&] { read_exr(path); });
    CHECK(test::contains(message, "forged.exr"));
    CAPTURE(message);
    CHECK_FALSE(test::contains(message, "<"));
}

TEST_CASE("exr: tiled files (OpenEXR's tiled writer, ZIP, HALF) read like scan-line files") {
    test::TempDir dir("exr-tiled");
    const int w = 37, h = 21;  // not multiples of the 16x8 tiles: partial tiles at the edges
    std::vector<Imf::Rgba> pixels(static_cast<std::size_t>(w * h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            pixels[static_cast<std::size_t>(y * w + x)] =
                Imf::Rgba(static_cast<float>(x) * 0.25f, static_cast<float>(y), -1.0f, 0.5f);
    const std::string path = dir.file("tiled.exr");
    {
        Imf::TiledRgbaOutputFile out(path.c_str(), w, h, 16, 8, Imf::ONE_LEVEL, Imf::ROUND_DOWN,
                                     Imf::WRITE_RGBA, 1.0f, Imath::V2f(0, 0), 1.0f,
                                     Imf::INCREASING_Y, Imf::ZIP_COMPRESSION);
        out.setFrameBuffer(pixels.data(), 1, static_cast<std::size_t>(w));
        out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
    }
    const Image image = read_exr(path);
    REQUIRE(image.same_shape(Image(w, h, 4)));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            CAPTURE(x);
            CAPTURE(y);
            CHECK(image.at(x, y, 0) == static_cast<float>(x) * 0.25f);
            CHECK(image.at(x, y, 1) == static_cast<float>(y));
            CHECK(image.at(x, y, 2) == -1.0f);
            CHECK(image.at(x, y, 3) == 0.5f);
        }
}

TEST_CASE("exr: a ZIP chunk that inflates short is refused, never read from undefined memory") {
    // Found by fuzzing (tools/scripts/fuzz.sh): a 528x1 ZIP file whose chunk decompresses to fewer
    // bytes than its lines need. OpenEXR 3.1's C++ reader filled the rest from an uninitialised
    // buffer (another image on each read); the core decoder fovref uses checks the size.
    const std::string path =
        std::string(FOVREF_SOURCE_DIR) + "/tests/fuzz/regressions/fuzz_exr/zip_chunk_short.exr";
    const std::string message = test::error_message([&] { read_exr(path); });
    CHECK(test::contains(message, "zip_chunk_short.exr: cannot read EXR"));
}
