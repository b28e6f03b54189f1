// `fovref bench metrics` (issue 4, point 6): single-thread time of each metric at 1280x720 and
// 3840x2160 on fixed synthetic images, and, where python3 with scikit-image is installed,
// scikit-image's SSIM with the reference settings on the same images in the same run (both
// values and the time ratio). A benchmark: it prints figures, it asserts nothing.
#pragma once

#include <string>
#include <vector>

namespace fovref {

struct BenchMetricsOptions {
    std::vector<std::string> sizes = {"1280x720", "3840x2160"};
    int repeats = 3;
    bool quiet = false;
};

int run_bench_metrics(const BenchMetricsOptions& options);

}  // namespace fovref
