// Timing helpers shared by the benchmarks (`fovref bench ...`).
#pragma once

#include <algorithm>
#include <chrono>
#include <string>

namespace fovref {

using BenchClock = std::chrono::steady_clock;

inline double seconds_since(BenchClock::time_point start) {
    return std::chrono::duration<double>(BenchClock::now() - start).count();
}

/// The fastest of `repeats` runs of f (the machine is shared; the minimum is the most stable).
template <class F>
double best_time(int repeats, F&& f) {
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        const auto start = BenchClock::now();
        f();
        best = std::min(best, seconds_since(start));
    }
    return best;
}

/// What a bench's header adds for `--rounds`: nothing for one round, else before + N + after.
inline std::string rounds_note(int rounds, const char* before, const char* after) {
    return rounds > 1 ? before + std::to_string(rounds) + after : std::string();
}

}  // namespace fovref
