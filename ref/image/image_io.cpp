// Image files (SPEC §1): PFM, PNG (stb_image / stb_image_write) and EXR (OpenEXR 3.1), the sRGB
// transfer functions, and whole-file read / atomic write.
//
// Hardening, shared by every reader: the whole file is read into memory first, so that each
// header can be checked against the real file size BEFORE any pixel buffer is allocated (a forged
// "100000 100000" header on a 20-byte file fails at once instead of asking for 120 GB), and every
// failure becomes a fovref::Error whose message starts with the file name.
#include "ref/image/image_io.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <openexr.h>
#include <zlib.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/limits.h"

namespace fovref {

namespace {

Error io_error(const std::string& path, const std::string& message) {
    return file_error(path, 0, message);
}

std::string errno_text(int error) { return std::generic_category().message(error); }

/// Printable form of a few bytes of a (possibly binary) header, for error messages.
std::string quoted(std::string_view text, std::size_t max_length = 16) {
    std::string out = "\"";
    for (std::size_t i = 0; i < text.size() && i < max_length; ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
            out += static_cast<char>(c);
        } else {
            static const char hex[] = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (text.size() > max_length) out += "...";
    return out + "\"";
}

std::string shape_text(std::uint64_t width, std::uint64_t height, std::uint64_t channels) {
    return std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels);
}

/// Writers refuse images whose data does not match their shape, and empty images (no format
/// here can store a 0-pixel image, and our readers reject one).
void check_writable(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
        throw io_error(path,
                       "cannot write an empty image (" +
                           shape_text(static_cast<std::uint64_t>(std::max(image.width, 0)),
                                      static_cast<std::uint64_t>(std::max(image.height, 0)),
                                      static_cast<std::uint64_t>(std::max(image.channels, 0))) +
                           ")");
    const std::size_t expected = image.pixel_count() * static_cast<std::size_t>(image.channels);
    if (image.data.size() != expected)
        throw io_error(path, "image data holds " + std::to_string(image.data.size()) +
                                 " floats, its shape " +
                                 shape_text(static_cast<std::uint64_t>(image.width),
                                            static_cast<std::uint64_t>(image.height),
                                            static_cast<std::uint64_t>(image.channels)) +
                                 " needs " + std::to_string(expected));
}

}  // namespace

// ---- File names --------------------------------------------------------------------------------

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    for (char& c : ext)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    return ext;
}

// ---- Whole files -------------------------------------------------------------------------------

std::string read_file(const std::string& path) {
    // POSIX open + fstat: the kind and size of what is opened decide how it is read, before any
    // allocation. A regular file is read whole after its size is checked against the limit; a
    // pipe (e.g. `<(...)`) is read up to the limit; a device (/dev/zero: unbounded) or a
    // directory is refused.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw io_error(path, "cannot open: " + errno_text(errno));
    struct FdCloser {
        int fd;
        ~FdCloser() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0) throw io_error(path, "cannot stat: " + errno_text(errno));
    const std::uint64_t limit = input_limits().max_file_bytes;
    if (S_ISDIR(info.st_mode)) throw io_error(path, "is a directory, not a file");
    if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode))
        throw io_error(path, "is a device, not a file (refused: a device can be unbounded)");
    const bool regular = S_ISREG(info.st_mode);
    if (regular)
        check_limit(path, static_cast<std::uint64_t>(info.st_size), limit, "bytes",
                    "FOVREF_MAX_FILE_BYTES");
    std::string bytes;
    if (regular) bytes.reserve(static_cast<std::size_t>(info.st_size));
    std::array<char, 1 << 16> buffer;
    while (true) {
        const ssize_t got = ::read(fd, buffer.data(), buffer.size());
        if (got < 0) {
            if (errno == EINTR) continue;
            throw io_error(path, "read error: " + errno_text(errno));
        }
        if (got == 0) break;
        bytes.append(buffer.data(), static_cast<std::size_t>(got));
        // A pipe (or a file growing while it is read) stops at the limit.
        if (bytes.size() > limit)
            check_limit(path, bytes.size(), limit, "bytes (and more)", "FOVREF_MAX_FILE_BYTES");
    }
    return bytes;
}

namespace {

// The file a write to `path` lands in: symlinks are followed (the link stays, its target is
// replaced), relative targets resolved against the link's directory; at most 40 hops.
std::string resolve_write_target(const std::string& path) {
    std::string target = path;
    for (int hop = 0; hop < 40; ++hop) {
        struct stat info {};
        if (::lstat(target.c_str(), &info) != 0 || !S_ISLNK(info.st_mode)) return target;
        std::array<char, 4096> link{};
        const ssize_t length = ::readlink(target.c_str(), link.data(), link.size() - 1);
        if (length <= 0)
            throw io_error(path, "cannot read the symbolic link: " + errno_text(errno));
        const std::string destination(link.data(), static_cast<std::size_t>(length));
        const std::size_t slash = target.find_last_of('/');
        target = destination.front() == '/' || slash == std::string::npos
                     ? destination
                     : target.substr(0, slash + 1) + destination;
    }
    throw io_error(path, "too many levels of symbolic links");
}

}  // namespace

void write_file_atomic(const std::string& path, const std::string& bytes) {
    const std::string target = resolve_write_target(path);
    struct stat info {};
    if (::stat(target.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
        if (S_ISDIR(info.st_mode)) throw io_error(path, "is a directory, not a file");
        // A device or a pipe (/dev/stdout, /dev/null, a FIFO): written directly, never replaced
        // by a regular file. A write error (/dev/full) is reported, not ignored.
        std::FILE* file = std::fopen(target.c_str(), "wb");
        if (!file) throw io_error(path, "cannot open for writing: " + errno_text(errno));
        const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
        const bool flushed = std::fflush(file) == 0;
        const int error = errno;
        const bool closed = std::fclose(file) == 0;
        if (!written || !flushed || !closed)
            throw io_error(path, "write error: " + errno_text(error));
        return;
    }
    // A regular file (or none yet): a temporary file in the target's directory, so the final
    // std::rename never crosses a file system and replaces the target in one step (POSIX rename
    // semantics); a failure leaves the old file as it was.
    const std::string temporary = target + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (!file) throw io_error(path, "cannot create " + temporary + ": " + errno_text(errno));
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    const bool flushed = std::fflush(file) == 0;
    const int error = errno;
    const bool closed = std::fclose(file) == 0;
    if (!written || !flushed || !closed) {
        std::remove(temporary.c_str());
        throw io_error(path, "write error: " + errno_text(error));
    }
    if (std::rename(temporary.c_str(), target.c_str()) != 0) {
        const int rename_error = errno;
        std::remove(temporary.c_str());
        throw io_error(path, "cannot rename " + temporary + " to it: " + errno_text(rename_error));
    }
}

// ---- PFM ---------------------------------------------------------------------------------------
//
// Header (Debevec's PFM, netpbm whitespace rules): "PF" or "Pf", whitespace, width, whitespace,
// height, whitespace, scale, then EXACTLY ONE whitespace character, then the raster. Whitespace is
// space, TAB, CR, LF, VT or FF. No comments, no signs on the sizes. The scale's sign gives the
// byte order (negative = little-endian); its magnitude is ignored on read and written as 1.
// The raster is W*H*C binary32 values, rows from the BOTTOM of the image to the top, each row
// left to right with channels interleaved. The file must end exactly after the raster.

namespace {

bool is_pfm_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

struct PfmHeader {
    int width = 0;
    int height = 0;
    int channels = 0;
    Endian endian = Endian::little;
    std::size_t raster_offset = 0;
};

class PfmHeaderParser {
public:
    PfmHeaderParser(const std::string& path, const std::string& bytes)
        : path_(path), bytes_(bytes) {}

    PfmHeader parse() {
        PfmHeader header;
        // Magic.
        if (bytes_.empty()) throw io_error(path_, "empty file (expected a PFM header)");
        const std::string_view start(bytes_.data(), std::min<std::size_t>(bytes_.size(), 3));
        if (bytes_.size() < 3 || bytes_[0] != 'P' || (bytes_[1] != 'F' && bytes_[1] != 'f') ||
            !is_pfm_space(bytes_[2]))
            throw io_error(path_, "not a PFM file: bad magic " + quoted(start) +
                                      " (expected \"PF\" or \"Pf\" followed by whitespace)");
        header.channels = bytes_[1] == 'F' ? 3 : 1;
        pos_ = 2;

        // Sizes.
        header.width = parse_size("width");
        header.height = parse_size("height");

        // Scale: a finite, non-zero decimal number; its sign is the byte order.
        skip_space("scale");
        const std::string_view token = next_token("scale");
        double scale = 0.0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), scale);
        if (ec != std::errc() || end != token.data() + token.size() || !std::isfinite(scale) ||
            scale == 0.0)
            throw io_error(path_,
                           "PFM scale " + quoted(token) + " is not a finite non-zero number");
        header.endian = scale < 0.0 ? Endian::little : Endian::big;

        // Exactly one whitespace character separates the scale from the raster.
        if (pos_ >= bytes_.size())
            throw io_error(path_, "PFM header ends after the scale (no raster follows)");
        ++pos_;  // next_token stopped on whitespace.
        header.raster_offset = pos_;
        return header;
    }

private:
    void skip_space(const char* field) {
        const std::size_t begin = pos_;
        while (pos_ < bytes_.size() && is_pfm_space(bytes_[pos_])) ++pos_;
        if (pos_ == bytes_.size())
            throw io_error(path_, std::string("PFM header ends before the ") + field);
        if (pos_ == begin)
            throw io_error(path_,
                           std::string("PFM header: expected whitespace before the ") + field);
    }

    std::string_view next_token(const char* field) {
        // A header field is short; a long run of non-space bytes is binary garbage.
        constexpr std::size_t max_token = 32;
        const std::size_t begin = pos_;
        while (pos_ < bytes_.size() && !is_pfm_space(bytes_[pos_]) && pos_ - begin <= max_token)
            ++pos_;
        const std::string_view token(bytes_.data() + begin, pos_ - begin);
        if (token.size() > max_token)
            throw io_error(path_, std::string("PFM ") + field + " " + quoted(token) +
                                      " is not a number (field too long)");
        return token;
    }

    int parse_size(const char* field) {
        skip_space(field);
        const std::string_view token = next_token(field);
        // Accept an optional sign only to report a negative size precisely.
        std::size_t i = 0;
        const bool negative = token[0] == '-';
        if (token[0] == '-' || token[0] == '+') i = 1;
        if (i == token.size())
            throw io_error(
                path_, std::string("PFM ") + field + " " + quoted(token) + " is not an integer");
        std::int64_t value = 0;
        for (; i < token.size(); ++i) {
            if (token[i] < '0' || token[i] > '9')
                throw io_error(path_, std::string("PFM ") + field + " " + quoted(token) +
                                          " is not an integer");
            value = std::min<std::int64_t>(value * 10 + (token[i] - '0'), std::int64_t{1} << 40);
        }
        if (negative || value == 0)
            throw io_error(path_, std::string("PFM ") + field + " " + std::string(token) +
                                      " must be positive");
        if (value > std::numeric_limits<int>::max())
            throw io_error(
                path_, std::string("PFM ") + field + " " + std::string(token) + " is too large");
        return static_cast<int>(value);
    }

    const std::string& path_;
    const std::string& bytes_;
    std::size_t pos_ = 0;
};

std::uint32_t load_u32(const char* p, Endian endian) {
    const auto b = [p](int i) {
        return static_cast<std::uint32_t>(static_cast<unsigned char>(p[i]));
    };
    if (endian == Endian::little) return b(0) | b(1) << 8 | b(2) << 16 | b(3) << 24;
    return b(3) | b(2) << 8 | b(1) << 16 | b(0) << 24;
}

void store_u32(char* p, std::uint32_t bits, Endian endian) {
    for (int i = 0; i < 4; ++i) {
        const int shift = endian == Endian::little ? 8 * i : 8 * (3 - i);
        p[i] = static_cast<char>(static_cast<unsigned char>(bits >> shift));
    }
}

}  // namespace

Image read_pfm(const std::string& path) {
    const std::string bytes = read_file(path);
    const PfmHeader header = PfmHeaderParser(path, bytes).parse();

    // Size check before allocating: W*H*C*4 must equal what is left of the file. W and H are
    // below 2^31, so W*H*C < 3*2^62 fits in 64 bits; the byte count may not, hence the division.
    const std::uint64_t floats = static_cast<std::uint64_t>(header.width) *
                                 static_cast<std::uint64_t>(header.height) *
                                 static_cast<std::uint64_t>(header.channels);
    const std::uint64_t remaining = bytes.size() - header.raster_offset;
    const std::string floats_text = "header says " +
                                    shape_text(static_cast<std::uint64_t>(header.width),
                                               static_cast<std::uint64_t>(header.height),
                                               static_cast<std::uint64_t>(header.channels)) +
                                    " floats (" +
                                    (floats <= std::numeric_limits<std::uint64_t>::max() / 4
                                         ? std::to_string(floats * 4)
                                         : std::to_string(floats) + " x 4") +
                                    " bytes), file has " + std::to_string(remaining) +
                                    " bytes after the header";
    if (floats > remaining / 4) throw io_error(path, "truncated: " + floats_text);
    if (floats * 4 < remaining) throw io_error(path, "trailing bytes: " + floats_text);
    check_limit(path, static_cast<std::uint64_t>(header.width) * header.height,
                input_limits().max_image_pixels, "pixels", "FOVREF_MAX_IMAGE_PIXELS");

    Image image(header.width, header.height, header.channels);
    const std::size_t row_floats =
        static_cast<std::size_t>(header.width) * static_cast<std::size_t>(header.channels);
    const char* raster = bytes.data() + header.raster_offset;
    for (int file_row = 0; file_row < header.height; ++file_row) {
        // File row 0 is the bottom row of the image.
        const int y = header.height - 1 - file_row;
        const char* src = raster + static_cast<std::size_t>(file_row) * row_floats * 4;
        float* dst = image.data.data() + static_cast<std::size_t>(y) * row_floats;
        for (std::size_t i = 0; i < row_floats; ++i)
            dst[i] = std::bit_cast<float>(load_u32(src + 4 * i, header.endian));
    }
    return image;
}

void write_pfm(const std::string& path, const Image& image, Endian endian) {
    check_writable(path, image);
    if (image.channels != 1 && image.channels != 3)
        throw io_error(
            path, "PFM stores 1 or 3 channels, the image has " + std::to_string(image.channels));
    std::string bytes = std::string(image.channels == 3 ? "PF" : "Pf") + "\n" +
                        std::to_string(image.width) + " " + std::to_string(image.height) + "\n" +
                        (endian == Endian::little ? "-1.0" : "1.0") + "\n";
    const std::size_t header_size = bytes.size();
    const std::size_t row_floats =
        static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.channels);
    bytes.resize(header_size + image.data.size() * 4);
    for (int file_row = 0; file_row < image.height; ++file_row) {
        const int y = image.height - 1 - file_row;
        const float* src = image.data.data() + static_cast<std::size_t>(y) * row_floats;
        char* dst =
            bytes.data() + header_size + static_cast<std::size_t>(file_row) * row_floats * 4;
        for (std::size_t i = 0; i < row_floats; ++i)
            store_u32(dst + 4 * i, std::bit_cast<std::uint32_t>(src[i]), endian);
    }
    write_file_atomic(path, bytes);
}

// ---- PNG ---------------------------------------------------------------------------------------

namespace {

constexpr unsigned char png_signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};

/// Colour channels are sRGB-coded, alpha (channel 1 of grey+alpha, 3 of RGBA) is linear.
bool is_colour_channel(int channel, int channels) {
    return !((channels == 2 && channel == 1) || (channels == 4 && channel == 3));
}

/// Rejects, from the IHDR chunk, a PNG whose raster could not come out of its compressed data:
/// deflate expands at most 1032:1 (a 258-byte match coded in 2 bits), so a raster of more than
/// about 1032 x the file size is a forged header. This runs before stb_image allocates the
/// output (stb_image allocates W*H*C before checking that enough data follows).
void check_png_header(const std::string& path, const std::string& bytes) {
    const auto u8 = [&](std::size_t i) { return static_cast<unsigned char>(bytes[i]); };
    const auto u32 = [&](std::size_t i) {
        return static_cast<std::uint64_t>(u8(i)) << 24 |
               static_cast<std::uint64_t>(u8(i + 1)) << 16 |
               static_cast<std::uint64_t>(u8(i + 2)) << 8 | static_cast<std::uint64_t>(u8(i + 3));
    };
    if (bytes.empty()) throw io_error(path, "empty file (expected a PNG)");
    if (bytes.size() < 8 || std::memcmp(bytes.data(), png_signature, 8) != 0)
        throw io_error(path, "not a PNG file: bad signature " + quoted(bytes.substr(0, 8)));
    if (bytes.size() < 33 || bytes.compare(12, 4, "IHDR") != 0) return;  // stb_image reports it.
    const std::uint64_t width = u32(16), height = u32(20), depth = u8(24), colour_type = u8(25);
    const std::uint64_t samples = colour_type == 2   ? 3
                                  : colour_type == 4 ? 2
                                  : colour_type == 6 ? 4
                                                     : 1;
    // Lower bound of the raster's bytes (filter bytes left out), in double: W*H*C*depth can
    // exceed 2^64 in a forged header, and a bound needs no exactness.
    const double raster_bytes = static_cast<double>(width) * static_cast<double>(height) *
                                static_cast<double>(samples * depth) / 8.0;
    check_limit(path + ": PNG header says " + std::to_string(width) + "x" + std::to_string(height),
                width * height, input_limits().max_image_pixels, "pixels",
                "FOVREF_MAX_IMAGE_PIXELS");  // width, height < 2^32: the product fits
    const double max_bytes = 1032.0 * static_cast<double>(bytes.size()) + 65536.0;
    if (raster_bytes > max_bytes)
        throw io_error(path, "PNG header says " + std::to_string(width) + "x" +
                                 std::to_string(height) + " pixels (" + std::to_string(samples) +
                                 " x " + std::to_string(depth) + "-bit samples), more than a " +
                                 std::to_string(bytes.size()) + "-byte file can hold");
}

/// What check_png_data reads from a PNG's chunks: the IHDR's fields, the PLTE's entry count and
/// the IDAT chunks' data, joined.
struct PngChunks {
    std::uint64_t width = 0, height = 0, depth = 0, colour_type = 0, interlace = 0;
    std::uint64_t palette_entries = 0;
    std::string idat;
};

/// Walks the chunks after the signature up to IEND. Empty when an IHDR chunk is not the first
/// chunk or is too short (stb_image reports it). Throws where a chunk before IEND declares more
/// bytes than the file has left: stb_image would fail on it anyway, but only after growing its
/// IDAT buffer to the declared length (2 GiB for a 231-byte file: a fuzzer finding).
std::optional<PngChunks> read_png_chunks(const std::string& path, const std::string& bytes) {
    const auto u8 = [&](std::size_t i) { return static_cast<unsigned char>(bytes[i]); };
    const auto u32 = [&](std::size_t i) {
        return static_cast<std::uint64_t>(u8(i)) << 24 |
               static_cast<std::uint64_t>(u8(i + 1)) << 16 |
               static_cast<std::uint64_t>(u8(i + 2)) << 8 | static_cast<std::uint64_t>(u8(i + 3));
    };
    PngChunks chunks;
    for (std::size_t pos = 8; pos + 12 <= bytes.size();) {
        const std::uint64_t length = u32(pos);
        const std::string type = bytes.substr(pos + 4, 4);
        const std::size_t data = pos + 8;
        // stb_image stops at IEND without reading its data, so IEND's length may be anything.
        if (type == "IEND") break;
        if (length > bytes.size() - pos - 12)
            throw io_error(path, "truncated PNG: chunk " + quoted(type, 4) + " at byte " +
                                     std::to_string(pos) + " declares " + std::to_string(length) +
                                     " data bytes, but only " +
                                     std::to_string(bytes.size() - pos - 8) +
                                     " bytes follow its header (data and 4-byte CRC)");
        if (type == "IHDR") {
            // Only the first chunk may be IHDR; stb_image reports "multiple IHDR" (a second one
            // once sent this check's buffer to terabytes: a fuzzer finding).
            if (pos != 8 || length < 13) return std::nullopt;
            chunks.width = u32(data);
            chunks.height = u32(data + 4);
            chunks.depth = u8(data + 8);
            chunks.colour_type = u8(data + 9);
            chunks.interlace = u8(data + 12);
        } else if (type == "PLTE") {
            chunks.palette_entries = length / 3;
        } else if (type == "IDAT") {
            chunks.idat.append(bytes, data, static_cast<std::size_t>(length));
        }
        pos = data + static_cast<std::size_t>(length) + 4;
    }
    return chunks;
}

/// One pass of a PNG raster: the pixels (x0 + i dx, y0 + j dy).
struct PngPass {
    std::uint64_t x0, y0, dx, dy;
};

/// The passes of a raster: Adam7's seven when interlaced, else one covering every pixel.
std::vector<PngPass> png_passes(std::uint64_t interlace) {
    return interlace == 1
               ? std::vector<PngPass>{{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                      {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}}
               : std::vector<PngPass>{{0, 0, 1, 1}};
}

/// The size of the inflated raster in bytes: each row of each non-empty pass, plus its filter
/// byte.
std::uint64_t png_raster_bytes(const std::vector<PngPass>& passes, std::uint64_t width,
                               std::uint64_t height, std::uint64_t pixel_bits) {
    std::uint64_t raster = 0;
    for (const PngPass& p : passes) {
        const std::uint64_t pw = width > p.x0 ? (width - p.x0 + p.dx - 1) / p.dx : 0;
        const std::uint64_t ph = height > p.y0 ? (height - p.y0 + p.dy - 1) / p.dy : 0;
        if (pw && ph) raster += ph * (1 + (pw * pixel_bits + 7) / 8);
    }
    return raster;
}

/// Inflates the IDAT data with zlib into `inflated`, which has the raster's size, then checks
/// the rest of the stream. Throws where zlib rejects the stream, or where it goes on for more
/// than 1 MiB beyond the raster; returns false where it ends before the raster is complete.
bool inflate_png_raster(const std::string& path, std::string& idat,
                        std::vector<unsigned char>& inflated) {
    z_stream stream{};
    if (inflateInit(&stream) != Z_OK) throw io_error(path, "cannot start zlib");
    // zlib counts in uInt: feed at most 1 GiB of input and output per call.
    auto* input = reinterpret_cast<Bytef*>(idat.data());
    stream.next_in = input;
    auto feed = [&] {
        const std::size_t consumed = static_cast<std::size_t>(stream.next_in - input);
        stream.avail_in =
            static_cast<uInt>(std::min<std::size_t>(idat.size() - consumed, 1u << 30));
    };
    auto input_left = [&] {
        return static_cast<std::size_t>(stream.next_in - input) < idat.size();
    };
    std::size_t out_done = 0;
    int result = Z_OK;
    while (out_done < inflated.size()) {
        feed();
        const std::size_t out_step = std::min<std::size_t>(inflated.size() - out_done, 1u << 30);
        stream.next_out = inflated.data() + out_done;
        stream.avail_out = static_cast<uInt>(out_step);
        result = inflate(&stream, Z_NO_FLUSH);
        out_done += out_step - stream.avail_out;
        if (result != Z_OK) break;  // Z_STREAM_END, or an error
        if (!input_left()) break;   // input used up
    }
    // The raster is complete: the rest of the stream (data beyond the raster, which the PNG
    // format does not allow but decoders tolerate) must still be valid deflate and short, since
    // stb_image inflates all of it (a garbage tail made it reallocate 2 GiB: a fuzzer finding).
    constexpr std::size_t max_extra = std::size_t{1} << 20;
    std::size_t extra = 0;
    std::array<unsigned char, 1 << 14> scratch;
    while (out_done == inflated.size() && result == Z_OK && extra <= max_extra && input_left()) {
        feed();
        stream.next_out = scratch.data();
        stream.avail_out = static_cast<uInt>(scratch.size());
        const uInt before = stream.avail_in;
        result = inflate(&stream, Z_NO_FLUSH);
        extra += scratch.size() - stream.avail_out;
        if (result == Z_BUF_ERROR) result = Z_OK;  // no progress possible
        if (stream.avail_out == scratch.size() && stream.avail_in == before) break;  // stuck
    }
    const std::string zlib_message = stream.msg ? stream.msg : "";
    inflateEnd(&stream);
    const bool data_error = result == Z_DATA_ERROR || result == Z_NEED_DICT ||
                            result == Z_STREAM_ERROR || result == Z_MEM_ERROR;
    if (data_error)
        throw io_error(path, "corrupt PNG image data: " +
                                 (zlib_message.empty() ? std::string("invalid deflate stream")
                                                       : zlib_message) +
                                 " (after " + std::to_string(out_done + extra) + " bytes; the " +
                                 "raster needs " + std::to_string(inflated.size()) + ")");
    if (out_done < inflated.size()) return false;
    if (extra > max_extra)
        throw io_error(path, "PNG image data inflates to more than 1 MiB beyond the " +
                                 std::to_string(inflated.size()) +
                                 " bytes its header describes; refused");
    return true;
}

/// Undoes a row's PNG filter (1 to 4; 0 is none) into `row`, from the row's filtered bytes `in`
/// and the unfiltered row above it, `previous` (zeros above a pass's first row). A filter unit
/// is one byte (as for palette pixels, at most 8 bits).
void unfilter_png_row(unsigned filter, const unsigned char* in,
                      const std::vector<unsigned char>& previous, std::vector<unsigned char>& row) {
    for (std::size_t i = 0; i < row.size(); ++i) {
        const int a = i > 0 ? row[i - 1] : 0, b = previous[i], c = i > 0 ? previous[i - 1] : 0;
        int predictor = 0;
        switch (filter) {
            case 1: predictor = a; break;
            case 2: predictor = b; break;
            case 3: predictor = (a + b) / 2; break;
            case 4: {
                const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
                predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
                break;
            }
            default: break;
        }
        row[i] = static_cast<unsigned char>(in[i] + predictor);
    }
}

/// Refuses a palette image with a pixel that indexes beyond its PLTE chunk: unfilters each
/// pass of the inflated raster and compares every index with the palette's length. Leaves a row
/// with an invalid filter type to stb_image.
void check_palette_indices(const std::string& path, const PngChunks& png,
                           const std::vector<PngPass>& passes,
                           const std::vector<unsigned char>& inflated) {
    const std::uint64_t width = png.width, height = png.height, depth = png.depth;
    const unsigned char* in = inflated.data();
    std::size_t offset = 0;
    std::uint64_t largest = 0;
    for (const PngPass& p : passes) {
        const std::uint64_t pw = width > p.x0 ? (width - p.x0 + p.dx - 1) / p.dx : 0;
        const std::uint64_t ph = height > p.y0 ? (height - p.y0 + p.dy - 1) / p.dy : 0;
        if (!pw || !ph) continue;
        const std::size_t row_bytes = static_cast<std::size_t>((pw * depth + 7) / 8);
        std::vector<unsigned char> previous(row_bytes, 0), row(row_bytes, 0);
        for (std::uint64_t y = 0; y < ph; ++y) {
            const unsigned filter = in[offset++];
            if (filter > 4) return;  // stb_image: "invalid filter"
            unfilter_png_row(filter, in + offset, previous, row);
            offset += row_bytes;
            for (std::uint64_t x = 0; x < pw; ++x) {
                const std::uint64_t bit = x * depth;
                const unsigned byte = row[static_cast<std::size_t>(bit / 8)];
                const unsigned index =
                    (byte >> (8 - depth - bit % 8)) & ((1u << depth) - 1u);  // MSB first
                largest = std::max<std::uint64_t>(largest, index);
            }
            previous.swap(row);
        }
    }
    if (largest >= png.palette_entries)
        throw io_error(path, "palette PNG: a pixel uses palette index " + std::to_string(largest) +
                                 " but the PLTE chunk has only " +
                                 std::to_string(png.palette_entries) +
                                 " entries (the colour is undefined; refused)");
}

/// The image data of a PNG is checked before stb_image decodes it, because stb_image reads
/// memory it never wrote on two kinds of bad input (different values on each read; an oracle
/// never reads undefined data; both found by fuzzing):
///  - a deflate stream with an invalid distance code (30 or 31): stb_image copies from distance
///    0, i.e. from its uninitialised output buffer. So every PNG's IDAT data is inflated with
///    zlib into exactly the raster's size: a stream zlib rejects before the raster is complete
///    is refused (bytes beyond the raster are never used);
///  - a palette image whose pixels index beyond its PLTE chunk: stb_image reads uninitialised
///    palette entries. So where the PLTE has fewer than 2^depth entries the inflated rows are
///    unfiltered and every index compared with the palette's length.
/// Anything else malformed (a short stream, a bad filter type, a bad header) is left to
/// stb_image to report.
void check_png_data(const std::string& path, const std::string& bytes) {
    std::optional<PngChunks> chunks = read_png_chunks(path, bytes);
    if (!chunks) return;
    PngChunks& png = *chunks;
    const std::uint64_t samples = png.colour_type == 0   ? 1
                                  : png.colour_type == 2 ? 3
                                  : png.colour_type == 3 ? 1
                                  : png.colour_type == 4 ? 2
                                  : png.colour_type == 6 ? 4
                                                         : 0;
    if (samples == 0 || png.width == 0 || png.height == 0 || png.idat.empty()) return;
    // check_png_header enforced the pixel limit on the first IHDR (the one read here).
    if (png.width * png.height > input_limits().max_image_pixels) return;
    if (png.depth != 1 && png.depth != 2 && png.depth != 4 && png.depth != 8 && png.depth != 16)
        return;
    const std::uint64_t pixel_bits = samples * png.depth;

    // The passes (one, or Adam7's seven) and the raster's size.
    const std::vector<PngPass> passes = png_passes(png.interlace);
    const std::uint64_t raster = png_raster_bytes(passes, png.width, png.height, pixel_bits);
    // check_png_header bounded the pixels; the raster fits in memory and in zlib's uInt steps.
    std::vector<unsigned char> inflated(static_cast<std::size_t>(raster));
    // Ending early: stb_image reports "not enough pixels".
    if (!inflate_png_raster(path, png.idat, inflated)) return;

    if (png.colour_type != 3 || png.palette_entries == 0 || png.depth > 8) return;
    if (png.palette_entries >= (std::uint64_t{1} << png.depth)) return;  // every index is in range
    check_palette_indices(path, png, passes, inflated);
}

struct StbFree {
    void operator()(void* pixels) const { stbi_image_free(pixels); }
};

// stb_image's failure reason in words. Its reasons are terse ("bad ctype"), sometimes empty, and
// one embeds the raw bytes of an unknown chunk type: those are shown escaped.
std::string stb_reason() {
    const char* raw = stbi_failure_reason();
    const std::string reason = raw ? raw : "";
    static const std::pair<const char*, const char*> words[] = {
        {"bad png sig", "not a PNG file (bad signature)"},
        {"first not IHDR", "the first chunk is not IHDR"},
        {"multiple IHDR", "more than one IHDR chunk"},
        {"bad IHDR len", "the IHDR chunk has the wrong length"},
        {"too large", "the image is too large (corrupt header?)"},
        {"1/2/4/8/16-bit only", "unsupported bit depth (PNG allows 1, 2, 4, 8 or 16 bits)"},
        {"bad ctype", "invalid colour type for this bit depth"},
        {"bad comp method", "unknown compression method"},
        {"bad filter method", "unknown filter method"},
        {"bad interlace method", "unknown interlace method"},
        {"0-pixel image", "the header says 0 pixels"},
        {"invalid PLTE", "invalid PLTE (palette) chunk"},
        {"no PLTE", "a palette image without a PLTE chunk"},
        {"tRNS after IDAT", "tRNS chunk after the image data"},
        {"tRNS before PLTE", "tRNS chunk before the palette"},
        {"bad tRNS len", "tRNS chunk of the wrong length"},
        {"tRNS with alpha", "tRNS chunk in an image that has alpha"},
        {"no IDAT", "no image data (IDAT) chunk"},
        {"outofdata", "the file ends inside the image data"},
        {"not enough pixels", "the image data is shorter than the header's size"},
        {"invalid filter", "a row has an invalid filter type"},
        {"outofmem", "out of memory"},
        {"bad zlib header", "the image data is not a zlib stream (bad header)"},
        {"no preset dict", "the zlib stream needs a preset dictionary"},
        {"bad compression", "the image data uses an invalid deflate block type"},
        {"bad codelengths", "corrupt deflate data (bad code lengths)"},
        {"bad sizes", "corrupt deflate data (bad sizes)"},
        {"bad huffman code", "corrupt deflate data (bad Huffman code)"},
        {"bad dist", "corrupt deflate data (bad distance)"},
        {"read past buffer", "corrupt deflate data (reads past its data)"},
        {"zlib corrupt", "corrupt deflate data"},
        {"output buffer limit", "the image data inflates to more than expected"},
        {"unknown image type", "not a PNG the decoder can read"},
    };
    for (const auto& [code, text] : words)
        if (reason == code) return text;
    if (reason.size() >= 4 && reason.find(" PNG chunk not known") == 4)
        return "unknown critical chunk type " + quoted(reason.substr(0, 4)) +
               " (a decoder must not skip it)";
    if (reason.empty()) return "corrupt data (the decoder gave no reason)";
    return "corrupt data (" + quoted(reason, 64) + ")";
}

void append_to_string(void* context, void* data, int size) {
    if (size > 0)
        static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                   static_cast<std::size_t>(size));
}

}  // namespace

namespace {

/// Stored 8-bit value / 255 (correctly rounded division), colour channels optionally
/// sRGB-decoded through a 256-entry table of the same function (alpha stays linear).
Image image_from_8bit(const stbi_uc* src, int width, int height, int channels,
                      bool srgb_decode_colour) {
    std::array<float, 256> linear, decoded;
    for (int k = 0; k < 256; ++k) {
        linear[k] = static_cast<float>(k) / 255.0f;
        decoded[k] = srgb_decode(linear[k]);
    }
    Image image(width, height, channels);
    const std::size_t count = image.data.size();
    for (std::size_t i = 0; i < count; ++i) {
        const bool colour = is_colour_channel(static_cast<int>(i % channels), channels);
        image.data[i] = srgb_decode_colour && colour ? decoded[src[i]] : linear[src[i]];
    }
    return image;
}

void check_decoded_shape(const std::string& path, const char* format, int width, int height,
                         int channels) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        throw io_error(path, std::string(format) + " decoder returned an unusable shape " +
                                 shape_text(static_cast<std::uint64_t>(std::max(width, 0)),
                                            static_cast<std::uint64_t>(std::max(height, 0)),
                                            static_cast<std::uint64_t>(std::max(channels, 0))));
}

Image decode_png_bytes(const std::string& bytes, const std::string& path, bool srgb_decode_colour) {
    check_png_header(path, bytes);
    check_png_data(path, bytes);
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw io_error(
            path, "PNG file too large for the reader (" + std::to_string(bytes.size()) + " bytes)");
    const auto* buffer = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int length = static_cast<int>(bytes.size());

    int width = 0, height = 0, channels = 0;
    const bool sixteen_bit = stbi_is_16_bit_from_memory(buffer, length) != 0;
    std::unique_ptr<void, StbFree> pixels(
        sixteen_bit ? static_cast<void*>(
                          stbi_load_16_from_memory(buffer, length, &width, &height, &channels, 0))
                    : static_cast<void*>(
                          stbi_load_from_memory(buffer, length, &width, &height, &channels, 0)));
    if (!pixels) throw io_error(path, "cannot decode PNG: " + stb_reason());
    check_decoded_shape(path, "PNG", width, height, channels);

    // Stored value / 255 (or / 65535), correctly rounded division; colour channels optionally
    // sRGB-decoded. 8-bit values go through a 256-entry table of the same function.
    if (!sixteen_bit)
        return image_from_8bit(static_cast<const stbi_uc*>(pixels.get()), width, height, channels,
                               srgb_decode_colour);
    Image image(width, height, channels);
    const std::size_t count = image.data.size();
    const auto* src = static_cast<const std::uint16_t*>(pixels.get());
    for (std::size_t i = 0; i < count; ++i) {
        const float value = static_cast<float>(src[i]) / 65535.0f;
        const bool colour = is_colour_channel(static_cast<int>(i % channels), channels);
        image.data[i] = srgb_decode_colour && colour ? srgb_decode(value) : value;
    }
    return image;
}

/// JPEG (FF D8 FF) or BMP ("BM"), 8 bits per channel, by stb_image. The caller has checked the
/// magic bytes, so stb_image's format probing cannot pick another decoder (in particular not
/// its Radiance HDR reader, which converts with libm's pow). The header's size is checked
/// before stb_image allocates: against the pixel limit, and against what the file can hold
/// (1024 pixels per byte of file; a baseline JPEG needs at least 2 bits per 8x8 block and
/// component, i.e. at most 256 pixels per byte; an uncompressed BMP at least 1 bit per pixel).
Image decode_stb_8bit(const std::string& bytes, const std::string& path, const char* format,
                      bool srgb_decode_colour) {
    if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw io_error(path, std::string(format) + " file too large for the reader (" +
                                 std::to_string(bytes.size()) + " bytes)");
    const auto* buffer = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int length = static_cast<int>(bytes.size());
    int width = 0, height = 0, channels = 0;
    if (stbi_info_from_memory(buffer, length, &width, &height, &channels) == 0)
        throw io_error(path, std::string("cannot decode ") + format + ": " + stb_reason());
    check_decoded_shape(path, format, width, height, channels);
    const std::uint64_t pixels_claimed =
        static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
    check_limit(path + ": " + format + " header says " + std::to_string(width) + "x" +
                    std::to_string(height),
                pixels_claimed, input_limits().max_image_pixels, "pixels",
                "FOVREF_MAX_IMAGE_PIXELS");
    if (pixels_claimed > 1024 * static_cast<std::uint64_t>(bytes.size()) + 65536)
        throw io_error(path, std::string(format) + " header says " + std::to_string(width) + "x" +
                                 std::to_string(height) + " pixels, more than a " +
                                 std::to_string(bytes.size()) + "-byte file can hold");
    std::unique_ptr<void, StbFree> pixels(
        stbi_load_from_memory(buffer, length, &width, &height, &channels, 0));
    if (!pixels) throw io_error(path, std::string("cannot decode ") + format + ": " + stb_reason());
    check_decoded_shape(path, format, width, height, channels);
    return image_from_8bit(static_cast<const stbi_uc*>(pixels.get()), width, height, channels,
                           srgb_decode_colour);
}

bool starts_with_bytes(const std::string& bytes, const char* magic, std::size_t length) {
    return bytes.size() >= length && std::memcmp(bytes.data(), magic, length) == 0;
}

}  // namespace

Image read_png(const std::string& path, bool srgb_decode_colour) {
    return decode_png_bytes(read_file(path), path, srgb_decode_colour);
}

std::string image_format_of_bytes(const std::string& bytes) {
    if (starts_with_bytes(bytes, reinterpret_cast<const char*>(png_signature), 8)) return "png";
    if (starts_with_bytes(bytes, "\xFF\xD8\xFF", 3)) return "jpeg";
    if (starts_with_bytes(bytes, "BM", 2)) return "bmp";
    return "";
}

Image decode_image_bytes(const std::string& bytes, const std::string& name,
                         bool srgb_decode_colour) {
    const std::string format = image_format_of_bytes(bytes);
    if (format == "png") return decode_png_bytes(bytes, name, srgb_decode_colour);
    if (format == "jpeg") return decode_stb_8bit(bytes, name, "JPEG", srgb_decode_colour);
    if (format == "bmp") return decode_stb_8bit(bytes, name, "BMP", srgb_decode_colour);
    if (bytes.empty()) throw io_error(name, "empty image data (expected PNG, JPEG or BMP)");
    throw io_error(name, "not a PNG, JPEG or BMP image: first bytes " + quoted(bytes.substr(0, 8)));
}

void write_png(const std::string& path, const Image& image) {
    write_file_atomic(path, encode_png(image, path));
}

std::string encode_png(const Image& image, const std::string& path) {
    check_writable(path, image);
    if (image.channels > 4)
        throw io_error(
            path, "PNG stores 1 to 4 channels, the image has " + std::to_string(image.channels));
    // 2-channel buffers (e.g. offsets) are previewed as RG with B = 0.
    const int in_channels = image.channels;
    const int out_channels = in_channels == 2 ? 3 : in_channels;
    if (image.width > std::numeric_limits<int>::max() / out_channels)
        throw io_error(path, "PNG row too wide (" + std::to_string(image.width) + " pixels)");

    // Clamp to [0,1] (NaN -> 0), sRGB-encode colour channels, round to nearest 8-bit code.
    const auto quantize = [](float value, bool colour) {
        float v = value > 0.0f ? value : 0.0f;
        v = v < 1.0f ? v : 1.0f;
        if (colour) v = srgb_encode(v);
        return static_cast<unsigned char>(std::floor(v * 255.0f + 0.5f));
    };
    std::vector<unsigned char> pixels(image.pixel_count() * static_cast<std::size_t>(out_channels),
                                      0);
    for (std::size_t p = 0; p < image.pixel_count(); ++p)
        for (int c = 0; c < in_channels; ++c)
            pixels[p * static_cast<std::size_t>(out_channels) + static_cast<std::size_t>(c)] =
                quantize(image.data[p * static_cast<std::size_t>(in_channels) +
                                    static_cast<std::size_t>(c)],
                         is_colour_channel(c, in_channels));

    std::string bytes;
    if (stbi_write_png_to_func(append_to_string, &bytes, image.width, image.height, out_channels,
                               pixels.data(), image.width * out_channels) == 0)
        throw io_error(path, "PNG encoder failed");
    return bytes;
}

// ---- EXR ---------------------------------------------------------------------------------------
//
// OpenEXR runs without worker threads (SPEC §0: single-threaded reference path) and reads from /
// writes to memory: reading sees the file size up front, writing ends in write_file_atomic.

namespace {

class MemoryIStream final : public Imf::IStream {
public:
    MemoryIStream(const std::string& path, const std::string& bytes)
        : Imf::IStream(path.c_str()), bytes_(bytes) {}
    bool read(char c[], int n) override {
        if (n < 0 || pos_ > bytes_.size() || static_cast<std::uint64_t>(n) > bytes_.size() - pos_)
            throw Iex::InputExc("unexpected end of file");
        if (n > 0) std::memcpy(c, bytes_.data() + pos_, static_cast<std::size_t>(n));
        pos_ += static_cast<std::uint64_t>(n);
        return pos_ < bytes_.size();
    }
    std::uint64_t tellg() override { return pos_; }
    void seekg(std::uint64_t pos) override { pos_ = pos; }  // read() checks the range.
    void clear() override {}

private:
    const std::string& bytes_;
    std::uint64_t pos_ = 0;
};

class MemoryOStream final : public Imf::OStream {
public:
    explicit MemoryOStream(const std::string& path) : Imf::OStream(path.c_str()) {}
    void write(const char c[], int n) override {
        if (n <= 0) return;
        const std::size_t end = static_cast<std::size_t>(pos_) + static_cast<std::size_t>(n);
        if (end > bytes_.size()) bytes_.resize(end);
        std::memcpy(bytes_.data() + pos_, c, static_cast<std::size_t>(n));
        pos_ = end;
    }
    std::uint64_t tellp() override { return pos_; }
    void seekp(std::uint64_t pos) override { pos_ = pos; }
    const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
    std::uint64_t pos_ = 0;
};

std::vector<std::string> exr_channel_names(int channels) {
    if (channels == 1) return {"Y"};
    if (channels == 3) return {"R", "G", "B"};
    if (channels == 4) return {"R", "G", "B", "A"};
    std::vector<std::string> names;
    for (int c = 0; c < channels; ++c) names.push_back("C" + std::to_string(c));
    return names;
}

/// The file's channels in our order, if they form one of the accepted layouts: Y, R G B,
/// R G B A, C0..Cn, or any single channel.
std::vector<std::string> exr_layout(const std::string& path,
                                    const std::vector<std::string>& present) {
    if (present.empty()) throw io_error(path, "EXR file has no channels");
    if (present.size() == 1) return present;
    std::vector<std::string> wanted = exr_channel_names(static_cast<int>(present.size()));
    std::vector<std::string> sorted_wanted = wanted;
    std::sort(sorted_wanted.begin(), sorted_wanted.end());
    if (sorted_wanted == present) return wanted;
    if (present.size() == 3 || present.size() == 4) {  // C0..C2 / C0..C3 are accepted too.
        std::vector<std::string> numbered;
        for (std::size_t c = 0; c < present.size(); ++c)
            numbered.push_back("C" + std::to_string(c));
        if (numbered == present) return numbered;
    }
    std::string names;
    for (const std::string& name : present) names += (names.empty() ? "" : ",") + name;
    throw io_error(path, "unsupported EXR channel layout (" + names +
                             "); expected Y, R,G,B, R,G,B,A, C0..Cn or one channel");
}

}  // namespace

namespace {

// Reading EXR with OpenEXRCore (the C API of OpenEXR 3), whose decoder checks that every chunk
// decompresses to exactly the size it must have. (The C++ InputFile of OpenEXR 3.1 does not:
// on a corrupt ZIP chunk it filled pixels from its uninitialised decompression buffer, a
// different image on each read; a fuzzer finding.)
struct ExrMemory {
    const std::string* bytes = nullptr;
    std::string message;  // the core library's last error message
};

int64_t exr_memory_read(exr_const_context_t, void* user, void* buffer, uint64_t size,
                        uint64_t offset, exr_stream_error_func_ptr_t) {
    const std::string& bytes = *static_cast<ExrMemory*>(user)->bytes;
    if (offset >= bytes.size()) return 0;
    const uint64_t n = std::min<uint64_t>(size, bytes.size() - offset);
    std::memcpy(buffer, bytes.data() + offset, static_cast<std::size_t>(n));
    return static_cast<int64_t>(n);
}

int64_t exr_memory_size(exr_const_context_t, void* user) {
    return static_cast<int64_t>(static_cast<ExrMemory*>(user)->bytes->size());
}

void exr_memory_error(exr_const_context_t ctxt, exr_result_t, const char* message) {
    void* user = nullptr;
    if (exr_get_user_data(ctxt, &user) == EXR_ERR_SUCCESS && user && message)
        static_cast<ExrMemory*>(user)->message = message;
}

/// An OpenEXRCore read context on a file held in memory (closed when this is destroyed);
/// check() turns a failed call into a fovref::Error naming what was being read, with the core
/// library's last error message.
class ExrReadContext {
public:
    ExrReadContext(const std::string& path, const std::string& bytes) : path_(path) {
        memory_.bytes = &bytes;
    }
    ExrReadContext(const ExrReadContext&) = delete;
    ExrReadContext& operator=(const ExrReadContext&) = delete;
    ~ExrReadContext() {
        if (context_) exr_finish(&context_);
    }

    /// Reads the header.
    void start() {
        exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
        init.user_data = &memory_;
        init.read_fn = exr_memory_read;
        init.size_fn = exr_memory_size;
        init.error_handler_fn = exr_memory_error;
        check(exr_start_read(&context_, path_.c_str(), &init), "header");
    }

    void check(exr_result_t result, const char* what) const {
        if (result == EXR_ERR_SUCCESS) return;
        const std::string reason =
            memory_.message.empty() ? exr_get_default_error_message(result) : memory_.message;
        throw io_error(path_, std::string("cannot read EXR (") + what + "): " + reason);
    }

    exr_context_t get() const { return context_; }
    const std::string& path() const { return path_; }

private:
    const std::string& path_;
    ExrMemory memory_;
    exr_context_t context_ = nullptr;
};

/// What read_exr reads of part 0 before decoding it.
struct ExrPart {
    exr_storage_t storage = EXR_STORAGE_SCANLINE;
    exr_attr_box2i_t window{};
    std::int64_t width = 0;
    std::int64_t height = 0;
    std::vector<std::string> names;  ///< the channels, in our order (exr_layout)
};

/// Part 0's channel names as the file lists them (sorted by name); refuses subsampled channels.
std::vector<std::string> exr_channels_present(const ExrReadContext& exr) {
    const exr_attr_chlist_t* list = nullptr;
    exr.check(exr_get_channels(exr.get(), 0, &list), "channels");
    std::vector<std::string> present;
    for (int c = 0; list && c < list->num_channels; ++c) {
        const exr_attr_chlist_entry_t& entry = list->entries[c];
        const std::string name(entry.name.str, static_cast<std::size_t>(entry.name.length));
        if (entry.x_sampling != 1 || entry.y_sampling != 1)
            throw io_error(exr.path(), "EXR channel " + name + " is subsampled (not supported)");
        present.push_back(name);
    }
    return present;
}

/// Reads part 0's layout, and refuses it (in this order) where it is deep data, where its data
/// window is empty or has more pixels than the limit, where its channels are not an accepted
/// layout, or where its decoded size is implausible for a file of `file_bytes` bytes.
ExrPart read_exr_part(const ExrReadContext& exr, std::size_t file_bytes) {
    const std::string& path = exr.path();
    ExrPart part;
    // Part 0: scan lines or tiles of flat (not deep) data.
    exr.check(exr_get_storage(exr.get(), 0, &part.storage), "storage");
    if (part.storage != EXR_STORAGE_SCANLINE && part.storage != EXR_STORAGE_TILED)
        throw io_error(path, "EXR with deep data (not supported)");
    exr.check(exr_get_data_window(exr.get(), 0, &part.window), "data window");
    const std::int64_t width = std::int64_t{part.window.max.x} - part.window.min.x + 1;
    const std::int64_t height = std::int64_t{part.window.max.y} - part.window.min.y + 1;
    if (width <= 0 || height <= 0)
        throw io_error(path, "EXR data window has no pixels (" + std::to_string(width) + "x" +
                                 std::to_string(height) + ")");
    // Limits checked before allocating: the image pixel limit (docs/limits.md), and no more
    // decoded bytes than 16384 x the file size (far above what OpenEXR's codecs reach on real
    // images; ZIP peaks near 1032:1) plus 4 MiB, so a forged header on a small file cannot make
    // us allocate gigabytes.
    check_limit(path + ": EXR data window " + std::to_string(width) + "x" + std::to_string(height),
                static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height),
                input_limits().max_image_pixels, "pixels", "FOVREF_MAX_IMAGE_PIXELS");
    part.width = width;
    part.height = height;
    part.names = exr_layout(path, exr_channels_present(exr));
    const int channels = static_cast<int>(part.names.size());
    const double decoded_bytes =
        static_cast<double>(width) * static_cast<double>(height) * channels * 4.0;
    if (decoded_bytes > 16384.0 * static_cast<double>(file_bytes) + 4.0 * 1024 * 1024)
        throw io_error(path, "EXR data window " + std::to_string(width) + "x" +
                                 std::to_string(height) + "x" + std::to_string(channels) +
                                 " is implausibly large for a " + std::to_string(file_bytes) +
                                 "-byte file");
    return part;
}

/// Calls decode(chunk, x0, y0) for each chunk of a scan-line part, first line first; (x0, y0)
/// is the chunk's first pixel relative to the data window.
template <class Decode>
void for_each_exr_scanline_chunk(const ExrReadContext& exr, const ExrPart& part, Decode&& decode) {
    int32_t lines = 0;
    exr.check(exr_get_scanlines_per_chunk(exr.get(), 0, &lines), "scan lines per chunk");
    if (lines < 1) throw io_error(exr.path(), "EXR with no scan lines per chunk");
    for (std::int64_t y = part.window.min.y; y <= part.window.max.y; y += lines) {
        exr_chunk_info_t chunk{};
        exr.check(exr_read_scanline_chunk_info(exr.get(), 0, static_cast<int>(y), &chunk),
                  "scan lines");
        // A scan-line chunk gives its first line (in data window coordinates).
        decode(chunk, 0, std::int64_t{chunk.start_y} - part.window.min.y);
    }
}

/// Calls decode(chunk, x0, y0) for each tile of a tiled part (level 0), row by row; (x0, y0) is
/// the tile's first pixel relative to the data window.
template <class Decode>
void for_each_exr_tile(const ExrReadContext& exr, const ExrPart& part, Decode&& decode) {
    int32_t tile_w = 0, tile_h = 0;
    exr.check(exr_get_tile_sizes(exr.get(), 0, 0, 0, &tile_w, &tile_h), "tile size");
    if (tile_w < 1 || tile_h < 1) throw io_error(exr.path(), "EXR with empty tiles");
    for (std::int64_t ty = 0; ty * tile_h < part.height; ++ty)
        for (std::int64_t tx = 0; tx * tile_w < part.width; ++tx) {
            exr_chunk_info_t chunk{};
            exr.check(exr_read_tile_chunk_info(exr.get(), 0, static_cast<int>(tx),
                                               static_cast<int>(ty), 0, 0, &chunk),
                      "tiles");
            // A tile chunk gives its tile indices, not pixels.
            decode(chunk, tx * tile_w, ty * tile_h);
        }
}

/// Decodes part 0 as float into one plane per channel (plane k holds part.names[k]). Each
/// channel pointer is on its own plane, so no interleaving fast path of the core library is
/// chosen (OpenEXRCore 3.1's RGBA one wrote the channels in the file's order).
std::vector<float> decode_exr_planes(const ExrReadContext& exr, const ExrPart& part) {
    const std::int64_t width = part.width, height = part.height;
    const std::vector<std::string>& names = part.names;
    const std::size_t plane = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    std::vector<float> planes(plane * names.size(), 0.0f);
    const std::size_t line_stride = static_cast<std::size_t>(width) * sizeof(float);
    exr_decode_pipeline_t decoder{};  // EXR_DECODE_PIPELINE_INITIALIZER: all zero
    struct Destroy {
        exr_context_t context;
        exr_decode_pipeline_t* decoder;
        bool active = false;
        ~Destroy() {
            if (active) exr_decoding_destroy(context, decoder);
        }
    } destroy{exr.get(), &decoder};
    // Decodes one chunk (a band of scan lines or a tile) into the planes; (x0, y0) is its first
    // pixel relative to the data window.
    auto decode = [&](const exr_chunk_info_t& chunk, std::int64_t x0, std::int64_t y0) {
        if (!destroy.active) {
            exr.check(exr_decoding_initialize(exr.get(), 0, &chunk, &decoder), "decoder");
            destroy.active = true;
        } else {
            exr.check(exr_decoding_update(exr.get(), 0, &chunk, &decoder), "decoder");
        }
        if (x0 < 0 || y0 < 0 || x0 + chunk.width > width || y0 + chunk.height > height)
            throw io_error(exr.path(), "EXR chunk outside the data window");
        for (int c = 0; c < decoder.channel_count; ++c) {
            exr_coding_channel_info_t& channel = decoder.channels[c];
            const auto k = static_cast<std::size_t>(
                std::find(names.begin(), names.end(), channel.channel_name) - names.begin());
            channel.decode_to_ptr = reinterpret_cast<uint8_t*>(
                planes.data() + k * plane + static_cast<std::size_t>(y0) * width + x0);
            channel.user_pixel_stride = static_cast<int32_t>(sizeof(float));
            channel.user_line_stride = static_cast<int32_t>(line_stride);
            channel.user_data_type = EXR_PIXEL_FLOAT;
            channel.user_bytes_per_element = 4;
        }
        exr.check(exr_decoding_choose_default_routines(exr.get(), 0, &decoder), "decoder");
        exr.check(exr_decoding_run(exr.get(), 0, &decoder), "pixel data");
    };
    if (part.storage == EXR_STORAGE_SCANLINE)
        for_each_exr_scanline_chunk(exr, part, decode);
    else
        for_each_exr_tile(exr, part, decode);
    return planes;
}

}  // namespace

Image read_exr(const std::string& path) {
    const std::string bytes = read_file(path);
    if (bytes.empty()) throw io_error(path, "empty file (expected an EXR)");
    ExrReadContext exr(path, bytes);
    exr.start();
    const ExrPart part = read_exr_part(exr, bytes.size());
    const std::vector<float> planes = decode_exr_planes(exr, part);
    // The planes, interleaved.
    const int channels = static_cast<int>(part.names.size());
    const std::size_t plane =
        static_cast<std::size_t>(part.width) * static_cast<std::size_t>(part.height);
    Image image(static_cast<int>(part.width), static_cast<int>(part.height), channels);
    for (std::size_t p = 0; p < plane; ++p)
        for (std::size_t c = 0; c < static_cast<std::size_t>(channels); ++c)
            image.data[p * channels + c] = planes[c * plane + p];
    return image;
}

void write_exr(const std::string& path, const Image& image) {
    check_writable(path, image);
    Imf::setGlobalThreadCount(0);
    std::string bytes;
    try {
        const std::vector<std::string> names = exr_channel_names(image.channels);
        Imf::Header header(image.width, image.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const std::string& name : names)
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        // OpenEXR's Slice takes a mutable pointer even for output; the data is only read.
        char* base = const_cast<char*>(reinterpret_cast<const char*>(image.data.data()));
        const std::size_t x_stride = static_cast<std::size_t>(image.channels) * sizeof(float);
        const std::size_t y_stride = x_stride * static_cast<std::size_t>(image.width);
        Imf::FrameBuffer frame_buffer;
        for (int c = 0; c < image.channels; ++c)
            frame_buffer.insert(
                names[static_cast<std::size_t>(c)],
                Imf::Slice(Imf::FLOAT, base + c * sizeof(float), x_stride, y_stride));
        MemoryOStream stream(path);
        {
            // The line offset table is written when the file object is destroyed.
            Imf::OutputFile file(stream, header, 0);
            file.setFrameBuffer(frame_buffer);
            file.writePixels(image.height);
        }
        bytes = stream.bytes();
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw io_error(path, std::string("cannot write EXR: ") + e.what());
    } catch (...) {
        throw io_error(path, "cannot write EXR: unknown exception");
    }
    write_file_atomic(path, bytes);
}

// ---- Dispatch by extension ---------------------------------------------------------------------

// ---- raw binary32 ------------------------------------------------------------------------------

Image read_raw(const std::string& path, const RawLayout& layout) {
    if (layout.width < 1 || layout.height < 1 || layout.channels < 1 || layout.width > 65536 ||
        layout.height > 65536 || layout.channels > 64)
        throw io_error(path,
                       "raw layout " +
                           shape_text(static_cast<std::uint64_t>(std::max(layout.width, 0)),
                                      static_cast<std::uint64_t>(std::max(layout.height, 0)),
                                      static_cast<std::uint64_t>(std::max(layout.channels, 0))) +
                           " is out of range (1..65536 pixels per side, 1..64 channels)");
    const std::uint64_t pixels =
        static_cast<std::uint64_t>(layout.width) * static_cast<std::uint64_t>(layout.height);
    check_limit(
        path + ": raw " + std::to_string(layout.width) + "x" + std::to_string(layout.height),
        pixels, input_limits().max_image_pixels, "pixels", "FOVREF_MAX_IMAGE_PIXELS");
    const std::uint64_t expected = pixels * static_cast<std::uint64_t>(layout.channels) * 4u;
    const std::string bytes = read_file(path);
    // The size is checked before the image is allocated (a short file never costs W*H*C*4).
    if (bytes.size() != expected)
        throw io_error(path, "raw binary32 " +
                                 shape_text(static_cast<std::uint64_t>(layout.width),
                                            static_cast<std::uint64_t>(layout.height),
                                            static_cast<std::uint64_t>(layout.channels)) +
                                 " needs " + std::to_string(expected) + " bytes, the file has " +
                                 std::to_string(bytes.size()));
    Image image(layout.width, layout.height, layout.channels);
    const auto w = static_cast<std::size_t>(layout.width);
    const auto h = static_cast<std::size_t>(layout.height);
    const auto c = static_cast<std::size_t>(layout.channels);
    for (std::size_t file_row = 0; file_row < h; ++file_row) {
        const std::size_t y = layout.bottom_up ? h - 1 - file_row : file_row;
        for (std::size_t x = 0; x < w; ++x)
            for (std::size_t ch = 0; ch < c; ++ch) {
                // Element index in the file: interleaved (row, x, channel) or planar (channel, row,
                // x).
                const std::size_t element =
                    layout.planar ? (ch * h + file_row) * w + x : (file_row * w + x) * c + ch;
                std::uint32_t bits = 0;
                for (int b = 0; b < 4; ++b)
                    bits |= static_cast<std::uint32_t>(static_cast<unsigned char>(
                                bytes[element * 4 + static_cast<std::size_t>(b)]))
                            << (layout.big_endian ? 8 * (3 - b) : 8 * b);
                float v = 0.0f;
                std::memcpy(&v, &bits, 4);
                image.data[(y * w + x) * c + ch] = v;
            }
    }
    return image;
}

Image read_image(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".pfm") return read_pfm(path);
    if (ext == ".png") return read_png(path);
    if (ext == ".exr") return read_exr(path);
    throw io_error(path,
                   "unknown image extension " + quoted(ext, 32) + " (expected .pfm, .png or .exr)");
}

void write_image(const std::string& path, const Image& image) {
    const std::string ext = lower_extension(path);
    if (ext == ".pfm") return write_pfm(path, image);
    if (ext == ".png") return write_png(path, image);
    if (ext == ".exr") return write_exr(path, image);
    throw io_error(path,
                   "unknown image extension " + quoted(ext, 32) + " (expected .pfm, .png or .exr)");
}

}  // namespace fovref
