// libFuzzer target: golden/cases.json (load_golden_cases). tests/fuzz/fuzz_util.h.
#include "ref/golden/bundle.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("cases.json", data, size);
    fovref::fuzz::expect_error_or_success([&] { fovref::load_golden_cases(path); });
    return 0;
}
