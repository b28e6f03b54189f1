// libFuzzer target: raw binary32 dumps (read_raw). The first 4 bytes choose the layout (width,
// height and channels 1..64, 1..64, 1..4; planar, bottom-up and big-endian flags); the rest is
// the file. tests/fuzz/fuzz_util.h.
#include "ref/image/image_io.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 4) return 0;
    fovref::RawLayout layout;
    layout.width = 1 + data[0] % 64;
    layout.height = 1 + data[1] % 64;
    layout.channels = 1 + data[2] % 4;
    layout.planar = (data[3] & 1) != 0;
    layout.bottom_up = (data[3] & 2) != 0;
    layout.big_endian = (data[3] & 4) != 0;
    const std::string path = fovref::fuzz::write("input.raw", data + 4, size - 4);
    fovref::fuzz::expect_error_or_success([&] {
        const fovref::Image a = fovref::read_raw(path, layout);
        fovref::fuzz::require_same(a, fovref::read_raw(path, layout), "read_raw");
    });
    return 0;
}
