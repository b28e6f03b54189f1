// libFuzzer target: PFM files (read_pfm). tests/fuzz/fuzz_util.h has the contract.
#include "ref/image/image_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("input.pfm", data, size);
    fovref::fuzz::expect_error_or_success([&] {
        const fovref::Image a = fovref::read_pfm(path);
        fovref::fuzz::require_same(a, fovref::read_pfm(path), "read_pfm");
    });
    return 0;
}
