// libFuzzer target: a golden bundle's manifest.json (read_manifest). tests/fuzz/fuzz_util.h.
#include "ref/golden/bundle.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::filesystem::create_directories(fovref::fuzz::scratch() / "bundle");
    fovref::fuzz::write("bundle/manifest.json", data, size);
    fovref::fuzz::expect_error_or_success(
        [&] { fovref::read_manifest((fovref::fuzz::scratch() / "bundle").string()); });
    return 0;
}
