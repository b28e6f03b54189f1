// The files fovref's GPU clients (tools/clients/) read and write, depending on nothing of
// fovref's: a bundle's manifest (text) and PFM buffers, the format a bundle stores them in. Rows
// are kept as the file stores them, bottom row first (OpenGL's glReadPixels order); the Vulkan
// client flips them to fovref's top-down rows.
#pragma once

#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fovref_client {

struct PfmImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> bottom_up;  ///< little-endian binary32, bottom row first
};

/// The whole file as text. Throws std::runtime_error naming the file.
inline std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

/// Writes a 1- or 3-channel image (bottom row first). Throws std::runtime_error.
inline void write_pfm(const std::string& path, int width, int height, int channels,
                      const std::vector<float>& bottom_up) {
    std::ofstream out(path, std::ios::binary);
    out << (channels == 3 ? "PF" : "Pf") << "\n" << width << " " << height << "\n-1\n";
    out.write(reinterpret_cast<const char*>(bottom_up.data()),
              static_cast<std::streamsize>(bottom_up.size() * sizeof(float)));
    if (!out) throw std::runtime_error(path + ": cannot write");
}

/// Reads `count` raw little-endian binary32 values, exactly the file's size.
inline std::vector<float> read_binary32(const std::string& path, std::size_t count) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw std::runtime_error(path + ": cannot open");
    if (static_cast<std::size_t>(in.tellg()) != count * sizeof(float))
        throw std::runtime_error(path + ": expected " + std::to_string(count) + " binary32 values");
    in.seekg(0);
    std::vector<float> values(count);
    in.read(reinterpret_cast<char*>(values.data()),
            static_cast<std::streamsize>(count * sizeof(float)));
    return values;
}

/// Writes raw little-endian binary32 values.
inline void write_binary32(const std::string& path, const std::vector<float>& values) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(values.data()),
              static_cast<std::streamsize>(values.size() * sizeof(float)));
    if (!out) throw std::runtime_error(path + ": cannot write");
}

/// Reads a little-endian PFM (scale < 0). Throws std::runtime_error naming the file.
inline PfmImage read_pfm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::string kind;
    PfmImage image;
    double scale = 0.0;
    in >> kind >> image.width >> image.height >> scale;
    in.get();  // the single whitespace after the scale
    if (!in || (kind != "PF" && kind != "Pf") || image.width < 1 || image.height < 1 ||
        image.width > 16384 || image.height > 16384 || !(scale < 0.0))
        throw std::runtime_error(path + ": not a little-endian PFM file");
    image.channels = kind == "PF" ? 3 : 1;
    image.bottom_up.resize(static_cast<std::size_t>(image.width) * image.height * image.channels);
    in.read(reinterpret_cast<char*>(image.bottom_up.data()),
            static_cast<std::streamsize>(image.bottom_up.size() * sizeof(float)));
    if (!in) throw std::runtime_error(path + ": truncated");
    return image;
}

}  // namespace fovref_client
