// libFuzzer target: gaze track files of the foveated modes (read_gaze_track, the CSV of
// ref/gaze/gaze_track.h). tests/fuzz/fuzz_util.h.
#include "ref/gaze/gaze_track.h"
#include "tests/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = fovref::fuzz::write("gaze.csv", data, size);
    fovref::fuzz::expect_error_or_success([&] {
        const std::vector<fovref::GazeSample> track = fovref::read_gaze_track(path);
        fovref::gaze_at_frame(track, 0);
        fovref::gaze_at_frame(track, 1 << 30);
    });
    return 0;
}
