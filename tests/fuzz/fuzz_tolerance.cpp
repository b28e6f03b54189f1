// libFuzzer target: tolerance files of `fovref diff` (read_tolerance_file), and the same text
// as a --tolerance option. tests/fuzz/fuzz_util.h.
#include "ref/metrics/compare.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("tolerance.json", data, size);
    fovref::fuzz::expect_error_or_success([&] { fovref::read_tolerance_file(path); });
    fovref::fuzz::expect_error_or_success([&] {
        fovref::ToleranceTable table;
        fovref::parse_tolerance_option(std::string(reinterpret_cast<const char*>(data), size),
                                       table);
    });
    return 0;
}
