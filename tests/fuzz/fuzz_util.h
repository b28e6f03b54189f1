// Shared pieces of the libFuzzer targets (tests/fuzz/fuzz_*.cpp, tools/scripts/fuzz.sh). Each
// target feeds its input to one of fovref's loaders through a file, as a user's file would arrive.
// The contract it checks: bad input throws fovref::Error (expected, ignored); anything else — a
// crash, a sanitizer report, another exception type (std::bad_alloc, nlohmann's), a timeout, a
// leak — is a finding, and libFuzzer saves the input that caused it. Loaders that succeed are run
// twice and must give the same bits (no uninitialised or nondeterministic reads).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "ref/core/error.h"
#include "ref/image/image.h"

namespace fovref::fuzz {

/// A per-process scratch directory (created once, removed at exit).
inline const std::filesystem::path& scratch() {
    static const std::filesystem::path dir = [] {
        const std::filesystem::path d =
            std::filesystem::temp_directory_path() / ("fovref-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                            ("fovref-fuzz-" + std::to_string(::getpid())),
                                        ignored);
        });
        return d;
    }();
    return dir;
}

/// Writes `bytes` to scratch()/name and returns the path.
inline std::string write(const std::string& name, const void* bytes, std::size_t size) {
    const std::string path = (scratch() / name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(size));
    return path;
}
inline std::string write(const std::string& name, const std::string& text) {
    return write(name, text.data(), text.size());
}

/// Runs `load`; fovref::Error is the documented outcome of bad input.
template <class Load>
void expect_error_or_success(Load&& load) {
    try {
        load();
    } catch (const fovref::Error&) {
    }
}

/// Aborts (a finding) when two loads of the same input differ in any bit.
inline void require_same(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels ||
        (!a.data.empty() && std::memcmp(a.data.data(), b.data.data(), a.data.size() * 4) != 0)) {
        std::fprintf(stderr, "fuzz: %s gave different results for the same input\n", what);
        std::abort();
    }
}

}  // namespace fovref::fuzz
