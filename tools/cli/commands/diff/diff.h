// `fovref diff GOLDEN CANDIDATE` (issue 4, SPEC §11 "diff contract"): compares the buffers a GPU
// implementation wrote against a golden bundle (or one image against another), stage by stage in
// pipeline order, and reports per buffer the error figures, the worst pixels, the error ranges
// and pass/fail against per-buffer tolerances. Text summary on stdout, --json for machines,
// --html DIR for people. docs/diff.md describes the inputs and the report.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct DiffOptions {
    std::string golden;                   ///< bundle directory (manifest.json) or an image file
    std::string candidate;                ///< directory of buffers or one image file
    std::string profile = "bit-exact";    ///< tolerance profile: bit-exact, gpu-raster, gpu-rt
    std::vector<std::string> tolerances;  ///< NAME:abs=..,rel=..,ulp=..,pixels=..,edge=..
    std::string tolerance_file;
    std::string require;      ///< "all" or a comma-separated list: these must be present
    bool no_id_mask = false;  ///< compare value buffers everywhere, not only where ids agree
    std::string json_path;    ///< "-" = stdout
    std::string html_dir;
    std::string buffer;     ///< candidate is one file: the golden buffer it is (default final)
    int frame = -1;         ///< only this frame (default: all)
    double threshold = -1;  ///< "pixels over threshold" (< 0: count the pixels out of tolerance)
    int worst = 5;
    int margin = 0;  ///< leave out the pixels within this many of each value buffer's border
    // Raw binary32 candidates (.raw, .bin, .f32): the golden buffer's shape unless given.
    std::string raw_size;  ///< WxH or WxHxC
    bool raw_planar = false, raw_bottom_up = false, raw_big_endian = false;
    bool png_linear = false;  ///< PNG values / 255 as they are (default: sRGB-decode colour)
    // Error ranges.
    std::string gaze;  ///< "x,y" in pixels (default: the screen centre)
    int rings = 20;
    float max_range = 1.0f;
    float distance_px = 0.0f;  ///< viewing distance; default: the bundle's, else vfov 60 deg
    bool flip = false;         ///< LDR-FLIP of colour buffers (display space; slow at 4K)
    bool quiet = false;
};

/// Registers the command's options on `app`.
void add_diff_options(CLI::App& command, DiffOptions& options);

/// Runs the comparison. Returns 0 (all within tolerance) or 1 (some buffer out of tolerance);
/// throws fovref::Error for usage and input errors (the CLI exits 2).
int run_diff(const DiffOptions& options);

}  // namespace fovref
