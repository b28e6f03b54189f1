// The pieces of `fovref diff` its files share (tools/cli/commands/diff/): reading the golden and
// the candidate into items (input.cpp), comparing them (compare.cpp), the probe hint of a differing
// pixel (probe_hint.cpp) and the reports (console.cpp, json.cpp, html.cpp); diff.cpp runs them in
// that order; tools/cli/options/command_options.cpp registers the command's options.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ref/golden/bundle.h"
#include "ref/image/image.h"
#include "ref/metrics/compare.h"
#include "tools/cli/commands/diff/diff.h"
#include "tools/cli/commands/diff/report.h"

namespace fovref {

/// How the pooled FLIP values are accumulated (printed with them; docs/flip.md).
inline constexpr const char* flip_pooling_note =
    "binary64 sums (mean in row-major order; weighted percentiles over the values sorted "
    "ascending); NVlabs's tool sums in binary32, so its mean can differ in the 5th decimal";

// ---- input.cpp ------------------------------------------------------------------------------

/// What the comparison needs beside the report's items, per item: the SHA-256 of a golden buffer
/// kept only as a hash, and the golden's viewing distance (0: none).
struct ItemInputs {
    std::vector<std::string> expected_sha;
    std::vector<float> distances;
    int screen_width = 0, screen_height = 0;  ///< the golden case's (0: a plain image)
};

/// Reads a golden or candidate file. PNGs of colour buffers are sRGB-decoded (SPEC §11) unless
/// --png-linear; an RGBA file compared with an RGB buffer loses its alpha channel (noted).
Image load_image(const DiffOptions& o, const std::string& path, const std::string& kind, int width,
                 int height, int channels, std::string* note);

/// The items of a golden bundle in comparison order, each with its candidate file (a directory's
/// files, or the one candidate file as --buffer of --frame); candidate files that match no buffer
/// go to report.ignored.
void collect_bundle_items(const DiffOptions& o, const Manifest& manifest, bool candidate_dir,
                          DiffReport& report, ItemInputs& inputs);

/// A golden image: one item, the candidate image.
void collect_image_item(const DiffOptions& o, bool candidate_dir, DiffReport& report,
                        ItemInputs& inputs);

/// Up to `count` of `names` nearest to `name` (edit distance; ties in `names` order).
std::vector<std::string> nearest_names(const std::string& name,
                                       const std::vector<std::string>& names,
                                       std::size_t count = 3);

// ---- tolerances.cpp -------------------------------------------------------------------------

/// The tolerances of a diff: the profile's, then the tolerance file's and the --tolerance
/// options' entries over them. Each entry the user gave must name a buffer of `names` (a pattern
/// must match one): otherwise fovref::Error names the option or file and the nearest names.
ToleranceTable diff_tolerances(const DiffOptions& o, const std::vector<std::string>& names);

// ---- compare.cpp ----------------------------------------------------------------------------

/// Compares frame by frame: the id buffers of a frame first, then its other buffers where the
/// ids agree (unless --no-id-mask), each group in comparison order.
void compare_items(const DiffOptions& o, const ToleranceTable& tolerances, const ItemInputs& inputs,
                   DiffReport& report);

// ---- decisions.cpp --------------------------------------------------------------------------

/// The oracle's margins for decision buffer `item` (Tolerance::margin) among items [first, end)
/// of its frame: a golden buffer of the frame (loaded if the candidate lacks it) or one the diff
/// derives from the golden's screen points; null, with a note in `why`, when the frame lacks the
/// margin's input or its size differs (the buffer is then compared as plain ids).
const Image* decision_margin(const DiffOptions& o, const ItemInputs& inputs, DiffReport& report,
                             std::size_t first, std::size_t end, const DiffItem& item,
                             const Tolerance& tolerance, Image& storage, std::string& why);

/// After every buffer is compared: the failing pixels of value buffers that a near-threshold
/// decision flip explains (a flip at most 1 pixel away in a buffer of the same size, in this or
/// an earlier frame; or, for a screen-sized buffer, a flipped texel whose golden screen point
/// lies within 2 pixels) are attributed to it; a buffer whose other failing pixels are within
/// its allowance passes.
void attribute_to_decisions(const ItemInputs& inputs, DiffReport& report);

// ---- probe_hint.cpp -------------------------------------------------------------------------

/// The space of buffer `name` as the case's mode describes its buffers (ModeInfo::
/// buffer_families); a mode this fovref does not know (a bundle from another version): screen.
BufferSpace space_of(const std::string& mode, const std::string& name);

/// The `fovref probe` command that explains element (x, y) of `item` (empty without a case).
std::string probe_command(const Manifest& m, const DiffItem& item, int x, int y);

// ---- console.cpp, json.cpp ------------------------------------------------------------------

/// The report on stdout: a row per buffer, the first failing stage, the result.
void print_summary(const DiffReport& report);
/// The report as JSON (--json).
nlohmann::json report_json(const DiffOptions& o, const DiffReport& report);

}  // namespace fovref
