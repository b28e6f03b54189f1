// Image construction, bitwise comparison and the canonical SHA-256 of a buffer (SPEC §1).
#include "ref/image/image.h"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>

#include "ref/core/error.h"

namespace fovref {

Image::Image(int width_, int height_, int channels_, float fill)
    : width(width_), height(height_), channels(channels_) {
    if (width_ < 0 || height_ < 0 || channels_ < 0)
        throw Error("Image: negative size " + std::to_string(width_) + "x" +
                    std::to_string(height_) + "x" + std::to_string(channels_));
    data.assign(static_cast<std::size_t>(width_) * height_ * channels_, fill);
}

void keep_or_make(Image& image, int width, int height, int channels) {
    if (!(image.width == width && image.height == height && image.channels == channels &&
          image.data.size() == image.pixel_count() * static_cast<std::size_t>(channels)))
        image = Image(width, height, channels, 0.0f);
}

bool bit_equal(const Image& a, const Image& b) {
    if (!a.same_shape(b) || a.data.size() != b.data.size()) return false;
    // memcmp compares the binary32 bit patterns: NaN payloads and the sign of zero count.
    return a.data.empty() ||
           std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

// ---- SHA-256 via OpenSSL's EVP interface ---------------------------------------------------

namespace {

struct DigestContextDeleter {
    void operator()(EVP_MD_CTX* ctx) const { EVP_MD_CTX_free(ctx); }
};
using DigestContext = std::unique_ptr<EVP_MD_CTX, DigestContextDeleter>;

DigestContext sha256_begin() {
    DigestContext ctx(EVP_MD_CTX_new());
    if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1)
        throw Error("sha256: OpenSSL could not initialise the digest");
    return ctx;
}

void sha256_update(EVP_MD_CTX* ctx, const void* bytes, std::size_t size) {
    if (size > 0 && EVP_DigestUpdate(ctx, bytes, size) != 1)
        throw Error("sha256: OpenSSL digest update failed");
}

std::string sha256_finish(EVP_MD_CTX* ctx) {
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int length = 0;
    if (EVP_DigestFinal_ex(ctx, digest.data(), &length) != 1 || length != 32)
        throw Error("sha256: OpenSSL digest finalisation failed");
    static const char hex[] = "0123456789abcdef";
    std::string out(64, '0');
    for (unsigned int i = 0; i < length; ++i) {
        out[2 * i] = hex[digest[i] >> 4];
        out[2 * i + 1] = hex[digest[i] & 15];
    }
    return out;
}

}  // namespace

std::string sha256_hex(const void* bytes, std::size_t size) {
    DigestContext ctx = sha256_begin();
    sha256_update(ctx.get(), bytes, size);
    return sha256_finish(ctx.get());
}

std::string canonical_sha256(const Image& image) {
    // Canonical bytes: the floats in storage order (row-major, top row first, channels
    // interleaved), each as little-endian binary32 whatever the host's byte order. Serialised
    // through a fixed-size buffer so that hashing a large image needs no second copy of it.
    DigestContext ctx = sha256_begin();
    std::array<unsigned char, 1 << 16> buffer;
    std::size_t used = 0;
    for (float value : image.data) {
        const std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
        for (int byte = 0; byte < 4; ++byte)
            buffer[used++] = static_cast<unsigned char>(bits >> (8 * byte));
        if (used == buffer.size()) {
            sha256_update(ctx.get(), buffer.data(), used);
            used = 0;
        }
    }
    sha256_update(ctx.get(), buffer.data(), used);
    return sha256_finish(ctx.get());
}

Image image_columns(const Image& image, int x0, int width) {
    FOVREF_CHECK(x0 >= 0 && width >= 0 && x0 + width <= image.width, "columns outside the image");
    Image part(width, image.height, image.channels, 0.0f);
    const std::size_t row = static_cast<std::size_t>(width) * image.channels;
    for (int y = 0; y < image.height; ++y)
        std::copy_n(&image.data[image.index(x0, y)], row, &part.data[part.index(0, y)]);
    return part;
}

void set_image_columns(Image& image, int x0, const Image& part) {
    FOVREF_CHECK(x0 >= 0 && x0 + part.width <= image.width && part.height == image.height &&
                     part.channels == image.channels,
                 "columns outside the image");
    const std::size_t row = static_cast<std::size_t>(part.width) * part.channels;
    for (int y = 0; y < image.height; ++y)
        std::copy_n(&part.data[part.index(0, y)], row, &image.data[image.index(x0, y)]);
}

}  // namespace fovref
