// A progress bar on stderr for work longer than a second, shown only when stderr is a terminal
// and --quiet is not given.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace fovref {

class Progress {
public:
    Progress(std::string label, bool quiet)
        : label_(std::move(label)),
          enabled_(!quiet && isatty(STDERR_FILENO) != 0),
          start_(std::chrono::steady_clock::now()) {}
    ~Progress() { finish(); }

    void update(double fraction) {
        if (!enabled_) return;
        const double elapsed = seconds();
        if (elapsed < 1.0) return;
        const int width = 30;
        const int filled = static_cast<int>(fraction * width + 0.5);
        std::string bar(static_cast<std::size_t>(filled), '#');
        bar.resize(width, ' ');
        // the estimated time left, once a few percent are done
        char eta[48] = "";
        if (fraction >= 0.02 && fraction < 1.0)
            std::snprintf(eta, sizeof eta, ", ETA %.0f s", elapsed * (1.0 - fraction) / fraction);
        std::fprintf(stderr, "\r\033[K%s [%s] %3d%% %.1f s%s", label_.c_str(), bar.c_str(),
                     static_cast<int>(fraction * 100 + 0.5), elapsed, eta);
        std::fflush(stderr);
        shown_ = true;
    }
    /// Erases the bar so that other output can be printed on a clean line.
    void clear() {
        if (shown_) std::fprintf(stderr, "\r\033[K");
        std::fflush(stderr);
        shown_ = false;
    }
    void finish() {
        if (shown_) std::fprintf(stderr, "\n");
        shown_ = false;
    }
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    std::string label_;
    bool enabled_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace fovref
