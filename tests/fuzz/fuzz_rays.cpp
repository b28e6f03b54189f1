// libFuzzer target: ray and hit files (read_rays, read_hits, read_occlusion).
// tests/fuzz/fuzz_util.h.
#include "ref/trace/rays_file.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("input.rays", data, size);
    fovref::fuzz::expect_error_or_success([&] { fovref::read_rays(path); });
    fovref::fuzz::expect_error_or_success([&] { fovref::read_hits(path); });
    fovref::fuzz::expect_error_or_success([&] { fovref::read_occlusion(path); });
    return 0;
}
