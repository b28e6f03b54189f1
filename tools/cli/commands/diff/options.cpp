#include <CLI/CLI.hpp>

#include "tools/cli/commands/diff/diff.h"
#include "tools/cli/common/cli_common.h"

namespace fovref {

void add_diff_options(CLI::App& c, DiffOptions& o) {
    c.add_option("GOLDEN", o.golden, "golden bundle directory (manifest.json) or image file")
        ->required();
    c.add_option("CANDIDATE", o.candidate,
                 "directory of buffers named as in the manifest (f000_final.pfm or final.pfm, "
                 "...) or one image file")
        ->required();
    c.add_option("--profile", o.profile,
                 "tolerance profile: bit-exact (0 everywhere), gpu-raster (a correct GPU port "
                 "with a hardware rasterizer), gpu-rt (with GPU ray tracing); each covers every "
                 "buffer family (G-buffers, foveation buffers, filters, TAA, BMFR, Visual-Polar); "
                 "the tolerance file and --tolerance override it per buffer (docs/diff.md)")
        ->capture_default_str();
    c.add_option("--tolerance", o.tolerances,
                 "NAME:abs=X,rel=X,ulp=N,pixels=N,share=X; edge=SHARE,interior=N compare as "
                 "integers (ids, masks, counts); NAME is a buffer or a pattern ('lp_*', '*'), "
                 "which must match a buffer of the golden; repeatable");
    c.add_option("--tolerance-file", o.tolerance_file,
                 "JSON: {\"buffer\": {\"abs\": x, \"rel\": x, \"ulp\": n, "
                 "\"max_failing_pixels\": n, \"max_failing_share\": x, "
                 "\"edge_mismatch_share\": x, \"interior_mismatches\": n, \"integer\": b, "
                 "\"reason\": \"...\"}} (keys: buffers or patterns)");
    c.add_option("--require", o.require,
                 "'all' or a comma-separated list of buffer names or patterns ('bmfr_*') that "
                 "must be in the candidate (a missing one fails)");
    c.add_flag("--no-id-mask", o.no_id_mask,
               "compare depth, position, ... everywhere, not only where the frame's id buffers "
               "agree");
    c.add_option("--json", o.json_path, "write the JSON report to FILE ('-' = stdout)");
    c.add_option("--html", o.html_dir, "write a self-contained HTML report to DIR/index.html");
    c.add_option("--buffer", o.buffer,
                 "candidate is one file: the golden buffer it is compared with (default final)");
    c.add_option("--frame", o.frame, "compare only this frame")->check(CLI::Range(0, 1000000));
    c.add_option("--threshold", o.threshold,
                 "count the pixels whose error exceeds this absolute value (default: count the "
                 "pixels out of the buffer's tolerance)");
    c.add_option("--margin", o.margin,
                 "leave out the value buffers' pixels within N of the border (a port with other "
                 "border handling, e.g. BMFR's mirrored blocks); the reports say how many")
        ->check(CLI::Range(0, 100000));
    c.add_option("--worst", o.worst, "worst pixels to list per buffer")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    c.add_option("--raw-size", o.raw_size,
                 "size of raw binary32 files WxH[xC] (default: the golden buffer's)");
    c.add_flag("--raw-planar", o.raw_planar, "raw files store channel planes, not interleaved");
    c.add_flag("--raw-bottom-up", o.raw_bottom_up, "raw files store the bottom row first");
    c.add_flag("--raw-big-endian", o.raw_big_endian, "raw files are big-endian");
    c.add_flag("--png-linear", o.png_linear,
               "use PNG values / 255 as they are (default: sRGB-decode colour buffers)");
    c.add_option("--gaze", o.gaze,
                 "gaze point X,Y in pixels for the error ranges (default: "
                 "the centre)");
    add_ring_options(c, o.rings, o.max_range);
    c.add_flag("--flip", o.flip,
               "also LDR-FLIP (NVlabs v1.x) of colour buffers, in display space (about 0.25 s "
               "per 1280x720 pair); pixels per degree from the display model, else NVlabs's "
               "default observer (67.02)");
    c.add_option("--distance-px", o.distance_px,
                 "viewing distance in pixels (default: the bundle's display model, else a 60 "
                 "degree vertical field of view for the error ranges and NVlabs's default "
                 "observer for --flip)")
        ->check(CLI::Range(1e-3, 1e9));
}

}  // namespace fovref
