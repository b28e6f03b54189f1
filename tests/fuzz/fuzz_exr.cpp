// libFuzzer target: EXR files (read_exr, through OpenEXR). tests/fuzz/fuzz_util.h.
#include "ref/image/image_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("input.exr", data, size);
    fovref::fuzz::expect_error_or_success([&] {
        const fovref::Image a = fovref::read_exr(path);
        fovref::fuzz::require_same(a, fovref::read_exr(path), "read_exr");
    });
    return 0;
}
