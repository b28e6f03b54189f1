// `fovref stress` (issue 17): the numerical stress suite. Runs extreme cases (docs/stress.md) and
// reports per case whether the output is finite, deterministic (computed twice, the same bits)
// and within a stated error of a binary64 evaluation or of the same computation at a benign
// setting; cases without a bound report how far precision degrades. Exit 1 when a case breaks
// its bound, is not finite or not deterministic, or an out-of-range parameter is not refused.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace fovref {

struct StressOptions {
    bool fast = false;   ///< only the fast cases (what CI runs)
    std::string filter;  ///< only the cases whose group contains this text
    std::string json;    ///< also write the rows as JSON here
    bool quiet = false;
};

void add_stress_options(CLI::App& command, StressOptions& options);

/// Throws fovref::Error for usage errors. Returns 0, or 1 when a case failed.
int run_stress(const StressOptions& options);

}  // namespace fovref
