// Image files (SPEC §1): PFM for float buffers, PNG for previews, EXR for exchange with GPU tools.
// Every reader validates the header and the size of the payload against the file, and throws
// fovref::Error naming the file and what is wrong; a truncated or corrupt file never crashes.
// Writers write to a temporary file beside the target and rename it, so a failed write never
// leaves a half-written file under the target name.
#pragma once

#include <string>

#include "ref/image/image.h"
#include "ref/image/srgb.h"

namespace fovref {

enum class Endian { little, big };

/// PFM: "PF" (3 channels) or "Pf" (1 channel), "W H", scale (negative = little-endian), rows
/// bottom-to-top in the file. Images with 2 or 4+ channels cannot be PFM and are rejected.
Image read_pfm(const std::string& path);
void write_pfm(const std::string& path, const Image& image, Endian endian = Endian::little);

/// PNG preview: 1 channel -> grey, 3 -> RGB, 4 -> RGBA; values clamped to [0,1] and sRGB-encoded
/// (the alpha channel is linear), 8 bits. 2-channel buffers are written as RG with B = 0.
void write_png(const std::string& path, const Image& image);

/// The PNG file write_png writes, in memory (for self-contained HTML reports). `path` only names
/// the image in error messages.
std::string encode_png(const Image& image, const std::string& path = "<png>");

/// PNG read: 8- or 16-bit, grey/grey-alpha/RGB/RGBA. With `srgb_decode` the colour channels are
/// decoded from sRGB to linear; otherwise the stored value / 255 (or / 65535) is returned.
Image read_png(const std::string& path, bool srgb_decode = true);

/// An image file held in memory (a texture embedded in a glTF file, or a file already read),
/// decoded by its first bytes, not by a name: PNG (89 50 4E 47 ...; exactly as read_png, with
/// the same checks), JPEG (FF D8 FF; baseline or progressive, 8 bits, stb_image's integer
/// decoder) or BMP ("BM"; stb_image). Channels as stored (grey, grey+alpha, RGB, RGBA); values
/// are stored / 255 (or / 65535 for 16-bit PNG); with `srgb_decode` the colour channels are
/// decoded from sRGB to linear (srgb.h; alpha stays linear). `name` names the image in errors.
/// Throws fovref::Error for anything else, a corrupt image, or a header whose size exceeds
/// FOVREF_MAX_IMAGE_PIXELS or what the data can hold.
Image decode_image_bytes(const std::string& bytes, const std::string& name,
                         bool srgb_decode = true);

/// "png", "jpeg" or "bmp" by the magic bytes decode_image_bytes reads; "" for anything else.
std::string image_format_of_bytes(const std::string& bytes);

/// EXR: written as 32-bit float channels (R,G,B / Y / R,G,B,A, or C0..Cn for other counts),
/// lossless (ZIP). Read: any pixel type converted to float; Y, RGB, RGBA or C0..Cn layouts.
Image read_exr(const std::string& path);
void write_exr(const std::string& path, const Image& image);

/// The extension of the last path component, dot included, in lower case ("a/B.PFM" -> ".pfm");
/// "" when it has none.
std::string lower_extension(const std::string& path);

/// Raw binary32 dumps as GPU tools write them (no header): the size and layout must be given.
struct RawLayout {
    int width = 0, height = 0, channels = 1;
    bool planar = false;      ///< all of channel 0, then channel 1, ... (else interleaved)
    bool bottom_up = false;   ///< first row in the file is the bottom row (else the top row)
    bool big_endian = false;  ///< else little-endian
};
/// Throws fovref::Error naming the file when its size is not exactly W*H*C*4 bytes.
Image read_raw(const std::string& path, const RawLayout& layout);

/// By extension: .pfm, .png, .exr (case-insensitive).
Image read_image(const std::string& path);
void write_image(const std::string& path, const Image& image);

/// Write `bytes` to `path` atomically (temporary file + rename). Throws fovref::Error.
void write_file_atomic(const std::string& path, const std::string& bytes);
/// Read a whole file. Throws fovref::Error naming the file when it cannot be opened.
std::string read_file(const std::string& path);

}  // namespace fovref
