// libFuzzer target: PNG files (read_png, sRGB-decoded and linear). tests/fuzz/fuzz_util.h.
#include "ref/image/image_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("input.png", data, size);
    fovref::fuzz::expect_error_or_success([&] {
        const fovref::Image a = fovref::read_png(path, true);
        fovref::fuzz::require_same(a, fovref::read_png(path, true), "read_png");
        fovref::read_png(path, false);
    });
    return 0;
}
