// decode_image_bytes (PNG, JPEG, BMP from memory, by magic bytes) and JPEG/BMP texture files.
#include <doctest/doctest.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/scene/obj_loader.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

void append(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<std::size_t>(size));
}

// A w x h RGB image of 8-bit values, as stb_image_write writes it.
std::string encode_8bit(const std::vector<unsigned char>& pixels, int w, int h, bool jpeg) {
    std::string bytes;
    if (jpeg)
        stbi_write_jpg_to_func(append, &bytes, w, h, 3, pixels.data(), 100);
    else
        stbi_write_bmp_to_func(append, &bytes, w, h, 3, pixels.data());
    return bytes;
}

std::string decode_error(const std::string& bytes) {
    try {
        decode_image_bytes(bytes, "img.bin");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("image bytes: BMP decodes losslessly, sRGB-decoded like PNG") {
    std::vector<unsigned char> pixels;
    for (int i = 0; i < 4 * 3 * 3; ++i) pixels.push_back(static_cast<unsigned char>(i * 7));
    const std::string bmp = encode_8bit(pixels, 4, 3, false);
    CHECK(image_format_of_bytes(bmp) == "bmp");
    const Image decoded = decode_image_bytes(bmp, "a.bmp");
    REQUIRE(decoded.width == 4);
    REQUIRE(decoded.height == 3);
    REQUIRE(decoded.channels == 3);
    for (std::size_t i = 0; i < pixels.size(); ++i)
        CHECK(decoded.data[i] == srgb_decode(static_cast<float>(pixels[i]) / 255.0f));
    const Image linear = decode_image_bytes(bmp, "a.bmp", /*srgb_decode=*/false);
    for (std::size_t i = 0; i < pixels.size(); ++i)
        CHECK(linear.data[i] == static_cast<float>(pixels[i]) / 255.0f);
}

TEST_CASE("image bytes: a flat JPEG decodes to its colour, PNG bytes decode like read_png") {
    const std::vector<unsigned char> pixels(16 * 16 * 3, 128);
    const std::string jpeg = encode_8bit(pixels, 16, 16, true);
    CHECK(image_format_of_bytes(jpeg) == "jpeg");
    const Image decoded = decode_image_bytes(jpeg, "a.jpg", false);
    REQUIRE(decoded.width == 16);
    REQUIRE(decoded.height == 16);
    for (float v : decoded.data) CHECK(std::abs(v * 255.0f - 128.0f) <= 1.0f);
    // Twice the same bits.
    CHECK(bit_equal(decoded, decode_image_bytes(jpeg, "a.jpg", false)));

    test::TempDir dir("image-bytes");
    Image image(3, 2, 4);
    for (std::size_t i = 0; i < image.data.size(); ++i)
        image.data[i] = static_cast<float>(i) / 23.0f;
    const std::string png = encode_png(image, "p.png");
    test::write_bytes(dir.file("p.png"), png);
    CHECK(bit_equal(decode_image_bytes(png, "p.png"), read_png(dir.file("p.png"))));

    // JPEG texture files: .jpg and .jpeg, sRGB-decoded.
    test::write_bytes(dir.file("t.jpg"), jpeg);
    test::write_bytes(dir.file("t.JPEG"), jpeg);
    Scene scene;
    TextureCache cache;
    const int a = load_texture_file(scene, dir.file("t.jpg"), "t.jpg", cache, "");
    const int b = load_texture_file(scene, dir.file("t.JPEG"), "t.JPEG", cache, "");
    REQUIRE(scene.textures.size() == 2);
    CHECK(bit_equal(scene.textures[static_cast<std::size_t>(a)].image,
                    scene.textures[static_cast<std::size_t>(b)].image));
    CHECK(scene.textures[0].image.at(0, 0, 0) ==
          srgb_decode(decoded.at(0, 0, 0)));  // stored/255 then the sRGB table
}

TEST_CASE("image bytes: unknown, empty, corrupt and forged images throw naming the image") {
    CHECK(test::contains(decode_error(""), "img.bin: empty image data"));
    CHECK(test::contains(decode_error("GIF89a...."), "not a PNG, JPEG or BMP"));
    std::string jpeg = "\xFF\xD8\xFF\xE0";
    CHECK(test::contains(decode_error(jpeg), "img.bin"));
    // A baseline JPEG header claiming 65535 x 65535 pixels in a few bytes.
    const std::vector<unsigned char> pixels(8 * 8 * 3, 10);
    std::string small = encode_8bit(pixels, 8, 8, true);
    const std::size_t sof = small.find("\xFF\xC0");
    REQUIRE(sof != std::string::npos);
    small[sof + 5] = '\xFF';
    small[sof + 6] = '\xFF';
    small[sof + 7] = '\xFF';
    small[sof + 8] = '\xFF';
    const std::string message = decode_error(small);
    CHECK(test::contains(message, "img.bin"));
    CHECK(test::contains(message, "65535x65535"));
}
