// What `fovref diff` found, shared by its text, JSON and HTML writers (tools/diff.cpp,
// tools/diff_html.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ref/image/image.h"
#include "ref/metrics/compare.h"
#include "ref/metrics/flip.h"
#include "ref/metrics/rings.h"

namespace fovref {

struct DiffItem {
    int frame = 0;
    std::string name, stage, kind;
    std::string golden_file, candidate_file;  ///< candidate_file "" = missing in the candidate
    bool compared = false;                    ///< both present and compared
    bool hash_only = false;                   ///< the golden keeps only a hash: compared by SHA-256
    bool pass = true;
    std::string note;  ///< e.g. "alpha channel dropped", "golden stores only a hash"
    BufferComparison result;
    Image golden, candidate;          ///< kept for the HTML report
    std::optional<RingLayout> rings;  ///< for image-like buffers
    std::optional<FlipResult> flip;   ///< --flip, colour buffers: LDR-FLIP in display space
};

struct DiffReport {
    std::string golden, candidate;  ///< the paths as given
    std::string case_name, mode, scene;
    std::vector<DiffItem> items;       ///< frame then pipeline order
    std::vector<std::string> ignored;  ///< candidate files that match no golden buffer
    int first_failing = -1;            ///< index into items
    std::string probe_command;         ///< for the worst pixel of the first failing buffer
    bool pass = true;
    int compared = 0, failed = 0, missing = 0;
};

/// Writes DIR/index.html (self-contained: images as data: URIs, plots as inline SVG).
void write_diff_html(const DiffReport& report, const std::string& directory);

}  // namespace fovref
