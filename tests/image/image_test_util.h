// Helpers shared by the image tests: a per-test temporary directory, raw file I/O, a fixed-seed
// bit generator and a probe that returns a fovref::Error's message.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "ref/core/error.h"
#include "ref/image/image.h"

namespace fovref::test {

/// temp_directory_path()/fovref-test-<pid>-<tag>, created empty and removed with its contents.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& tag)
        : path(std::filesystem::temp_directory_path() /
               ("fovref-test-" + std::to_string(static_cast<long>(::getpid())) + "-" + tag)) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
    /// Writes `bytes` to file(name) and returns that path.
    std::string write(const std::string& name, const std::string& bytes) const;
};

/// Storage for a pass that writes every value (a stage's recycled output), filled with a value no
/// output takes, so that a value the pass leaves unwritten shows in a comparison.
inline Image unwritten_storage(int width, int height, int channels) {
    return Image(width, height, channels, -7.25e30f);
}

/// bit_equal, NaN payloads aside: the same shape, every value bit for bit or NaN in both (where
/// two different NaNs meet in an addition the result's payload depends on the operand order a
/// compiler chose, docs/determinism.md "SIMD paths").
inline bool same_bits_nan_aside(const Image& a, const Image& b) {
    if (!a.same_shape(b)) return false;
    for (std::size_t i = 0; i < a.data.size(); ++i)
        if (std::memcmp(&a.data[i], &b.data[i], sizeof(float)) != 0 &&
            !(std::isnan(a.data[i]) && std::isnan(b.data[i])))
            return false;
    return true;
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string TempDir::write(const std::string& name, const std::string& bytes) const {
    write_bytes(file(name), bytes);
    return file(name);
}

/// splitmix64 (Steele et al. 2014): a fixed, platform-independent stream for test data.
struct SplitMix64 {
    std::uint64_t state;
    explicit SplitMix64(std::uint64_t seed) : state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    std::uint32_t next_u32() { return static_cast<std::uint32_t>(next() >> 32); }
    /// Uniform in [0, n) (modulo bias is irrelevant for test data).
    std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
    /// Uniform in [0, 1), 24 bits.
    float unit() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
    /// lo + (hi - lo) k 2^-20 for k uniform in [0, 2^20) (test data on a 2^-20 grid).
    float uniform(float lo, float hi) {
        return lo + (hi - lo) * static_cast<float>(below(1 << 20)) * 0x1p-20f;
    }
    /// A float with all 24 significand bits random, a magnitude in [2^-8, 2^8) and either sign:
    /// sums of a few of these round, so a sum taken in another order gives other bits (values on
    /// a coarse grid, as uniform() gives, would add exactly in any order).
    float full_float() {
        const float m = static_cast<float>(below(std::size_t{1} << 24) | (1u << 23)) * 0x1p-23f;
        const float v = std::ldexp(m, static_cast<int>(below(16)) - 8);
        return below(2) == 0 ? v : -v;
    }
};

/// The message of the fovref::Error that `f` throws; "<no exception>" or "<other exception: ...>"
/// otherwise, so that a CHECK on the message also fails for a wrong or missing exception.
template <class F>
std::string error_message(F&& f) {
    try {
        f();
    } catch (const fovref::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        return std::string("<other exception: ") + e.what() + ">";
    } catch (...) {
        return "<other exception>";
    }
    return "<no exception>";
}

inline bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

}  // namespace fovref::test
