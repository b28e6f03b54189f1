// Float images and buffers (SPEC §1): W x H pixels, origin top-left, row-major, top row first,
// channels interleaved. One type serves RGB images, single-channel buffers (depth, ids) and
// multi-channel buffers (world positions, offsets).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace fovref {

struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> data;  ///< width * height * channels floats, row-major, top row first.

    Image() = default;
    Image(int width_, int height_, int channels_, float fill = 0.0f);

    std::size_t pixel_count() const { return static_cast<std::size_t>(width) * height; }
    std::size_t index(int x, int y, int c = 0) const {
        return (static_cast<std::size_t>(y) * width + x) * channels + c;
    }
    float& at(int x, int y, int c = 0) { return data[index(x, y, c)]; }
    float at(int x, int y, int c = 0) const { return data[index(x, y, c)]; }
    bool empty() const { return data.empty(); }
    bool same_shape(const Image& o) const {
        return width == o.width && height == o.height && channels == o.channels;
    }
    bool operator==(const Image&) const = default;  ///< Compares values; NaN != NaN.
};

/// Storage for an output of width x height x channels that a pass writes every value of: `image`
/// itself (its storage and values) when it already has that shape, else a new image of zeros
/// (storage handed over from an earlier frame: FrameContext::recycled, TAA's history).
void keep_or_make(Image& image, int width, int height, int channels);

/// Bitwise equality of the float data (NaN payloads compared as bits; -0 differs from +0).
bool bit_equal(const Image& a, const Image& b);

/// Columns x0 .. x0 + width - 1 of `image` (every row and channel), e.g. one eye of a stereo
/// frame. Throws fovref::Error (a bug) when they are not all inside.
Image image_columns(const Image& image, int x0, int width);
/// Writes `part` into `image` at columns x0 .. x0 + part.width - 1 (same height and channels).
void set_image_columns(Image& image, int x0, const Image& part);

/// SHA-256 of the canonical float data (SPEC §1): row-major, top row first, little-endian
/// binary32, channels interleaved. Lower-case hex, 64 characters.
std::string canonical_sha256(const Image& image);

/// SHA-256 of raw bytes, lower-case hex.
std::string sha256_hex(const void* bytes, std::size_t size);

}  // namespace fovref
