// What `fovref diff` found, shared by its text, JSON and HTML writers
// (tools/cli/commands/diff/diff.cpp, tools/cli/commands/diff/html.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ref/image/image.h"
#include "ref/metrics/compare.h"
#include "ref/metrics/flip.h"
#include "ref/metrics/rings.h"
#include "ref/stage/pipeline.h"

namespace fovref {

struct DiffItem {
    int frame = 0;
    std::string name, stage, kind;
    std::string golden_file, candidate_file;  ///< candidate_file "" = missing in the candidate
    bool compared = false;                    ///< both present and compared
    bool hash_only = false;                   ///< the golden keeps only a hash: compared by SHA-256
    bool required = false;                    ///< --require: missing fails
    bool is_id = false;  ///< an id or mask buffer: compared as integers (ids below)
    /// How its pixels relate to the screen: screen images get eccentricity rings, the others
    /// (foveation buffers, windows, sample lists) errors along their columns and rows.
    BufferSpace space = BufferSpace::screen;
    bool pass = true;
    std::string note;         ///< e.g. "alpha channel dropped", "golden stores only a hash"
    BufferComparison result;  ///< value buffers
    IdComparison ids;         ///< id buffers
    /// Value buffers compared only where these id buffers of the frame agree (empty: everywhere).
    std::vector<std::string> masked_by;
    std::int64_t margin_pixels = 0;  ///< --margin: border pixels left out (besides masked_by's)

    /// "pass", "FAIL", "missing" or "MISSING" (required).
    std::string status() const;
    /// The pixel the report points at: the first interior (else edge) id mismatch, or the worst
    /// value pixel; false when there is none.
    bool focus_pixel(int& x, int& y) const;
    Image golden, candidate;          ///< kept for the HTML report
    std::optional<RingLayout> rings;  ///< for image-like buffers
    std::optional<FlipResult> flip;   ///< --flip, colour buffers: LDR-FLIP in display space
    float flip_ppd = 0.0f;            ///< the pixels per degree FLIP used
    std::string flip_observer;        ///< where they came from (display model or default)
};

struct DiffReport {
    std::string golden, candidate;  ///< the paths as given
    std::string case_name, mode, scene;
    std::vector<DiffItem> items;            ///< frame then pipeline order
    std::vector<std::string> ignored;       ///< candidate files that match no golden buffer
    std::vector<std::string> ignored_hint;  ///< per ignored file: the closest buffer file name
    std::string profile;                    ///< the tolerance profile used
    /// The candidate's port.json (a GPU client's record of itself: device, driver, float
    /// controls, `precise` use, injected bug...), its members as "key: value" lines; empty when
    /// the candidate directory has none.
    std::vector<std::string> port;
    int first_failing = -1;     ///< index into items
    std::string probe_command;  ///< for the worst pixel of the first failing buffer
    bool pass = true;
    int compared = 0, failed = 0, missing = 0;
    int missing_required = 0;  ///< included in failed
    /// The buffers compared and found out of tolerance (failed less the missing required ones).
    int out_of_tolerance() const { return failed - missing_required; }
};

/// "25 compared, 1 out of tolerance, 0 missing in the candidate, 3 file(s) ignored": the counts
/// every report (console, HTML, JSON's "summary") states in the same words.
std::string result_counts(const DiffReport& report);

/// Writes DIR/index.html (self-contained: images as data: URIs, plots as inline SVG).
void write_diff_html(const DiffReport& report, const std::string& directory);

}  // namespace fovref
