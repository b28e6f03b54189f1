// `fovref bench metrics` (issue 4, point 6): single-thread time of each metric at 1280x720 and
// 3840x2160 on fixed synthetic images, and, where python3 with scikit-image is installed,
// scikit-image's SSIM with the reference settings on the same images in the same run (both
// values and the time ratio). A benchmark: it prints figures, it asserts nothing.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct BenchMetricsOptions {
    std::vector<std::string> sizes = {"1280x720", "3840x2160"};  ///< WxH of the test images
    int repeats = 3;     ///< each timing is the fastest of this many runs
    bool quiet = false;  ///< not read: the figures are printed with or without -q
};

/// Registers the command's options on `command`.
void add_bench_metrics_options(CLI::App& command, BenchMetricsOptions& options);

/// Runs the benchmark and prints its figures on stdout. Returns 0.
int run_bench_metrics(const BenchMetricsOptions& options);

}  // namespace fovref
