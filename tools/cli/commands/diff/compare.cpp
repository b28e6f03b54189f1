#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/metrics/flip.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/rings.h"
#include "tools/cli/commands/diff/internal.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/number_text.h"

namespace fovref {

namespace {

std::string shape(int w, int h, int c) {
    return std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(c);
}

// Default viewing distance without a scene: the display subtends a 60 degree vertical field of
// view (docs/diff.md).
float default_distance_px(int height) {
    return 0.5f * static_cast<float>(height) / dm::tan(dm::radians(30.0f));
}

// What the candidate file itself suggests went wrong, beside the numbers: a PNG for a float
// buffer (quantised to 1/255), an HDR colour buffer clipped by a PNG, rows upside down.
std::string candidate_hints(const DiffItem& item, const Tolerance& tolerance) {
    std::vector<std::string> hints;
    const bool png = lower_extension(item.candidate_file) == ".png";
    if (png && item.kind != "color")
        hints.push_back(
            "a PNG for a float buffer holds 8- or 16-bit steps (value/255 or "
            "/65535), not this buffer's values: write PFM or EXR");
    if (png && item.kind == "color") {
        float brightest = 0.0f;
        for (const float v : item.golden.data)
            if (std::isfinite(v)) brightest = std::max(brightest, v);
        if (brightest > 1.0f)
            hints.push_back("the golden holds values above 1 (up to " +
                            number_text(brightest, "%.4g") +
                            "), which a PNG clips at 1: write PFM or EXR");
    }
    if (!item.result.pass && item.golden.height > 1) {
        // The same comparison with the candidate's rows reversed
        Image flipped = item.candidate;
        const std::size_t row = static_cast<std::size_t>(flipped.width) * flipped.channels;
        for (int y = 0; y < flipped.height / 2; ++y)
            std::swap_ranges(flipped.data.begin() + static_cast<std::ptrdiff_t>(y * row),
                             flipped.data.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                             flipped.data.end() - static_cast<std::ptrdiff_t>((y + 1) * row));
        CompareOptions plain;
        plain.worst_pixels = 0;
        const BufferComparison upside_down =
            compare_buffers(item.name, item.golden, flipped, tolerance, plain);
        if (upside_down.failing_pixels * 10 < item.result.failing_pixels)
            hints.push_back("the candidate matches far better upside down (" +
                            std::to_string(upside_down.failing_pixels) + " instead of " +
                            std::to_string(item.result.failing_pixels) +
                            " pixels out of tolerance): its rows are stored bottom-up? Row 0 is "
                            "the top (a PFM file stores the bottom row first; raw files: "
                            "--raw-bottom-up)");
    }
    std::string text;
    for (const std::string& h : hints) text += (text.empty() ? "" : "; ") + h;
    return text;
}

void compare_item(const DiffOptions& o, const ToleranceTable& tolerances, float distance_px,
                  DiffItem& item, const std::string& expected_sha,
                  const std::vector<std::uint8_t>* mask, const Image* margin) {
    const Tolerance& tolerance = tolerances.for_buffer(item.name);
    std::string note;
    if (item.hash_only) {
        // The golden keeps only a hash (buffers too large for the repository): bit-exact or not.
        item.candidate = load_image(o, item.candidate_file, item.kind, 0, 0, 0, &note);
        item.compared = true;
        item.pass = canonical_sha256(item.candidate) == expected_sha;
        item.note = item.pass ? "golden stores only a hash: the candidate matches it bit for bit"
                              : "golden stores only a hash, which the candidate does not match; "
                                "`fovref golden export` writes a bundle with every buffer's "
                                "values";
        return;
    }
    item.candidate = load_image(o, item.candidate_file, item.kind, item.golden.width,
                                item.golden.height, item.golden.channels, &note);
    if (!item.golden.same_shape(item.candidate))
        throw Error(item.candidate_file + ": size mismatch: buffer '" + item.name + "' is " +
                    shape(item.golden.width, item.golden.height, item.golden.channels) +
                    ", the candidate is " +
                    shape(item.candidate.width, item.candidate.height, item.candidate.channels));
    if (item.is_id) {
        item.ids =
            compare_id_buffers(item.name, item.golden, item.candidate, tolerance, o.worst, margin);
        item.compared = true;
        item.pass = item.ids.pass;
        item.note = note;
        return;
    }
    const bool image_like = (item.golden.channels == 1 || item.golden.channels == 3) &&
                            item.golden.width >= 11 && item.golden.height >= 11;
    // Eccentricity rings for screen images only: a buffer-space image is summarised along its
    // columns and rows (a log-polar buffer's u is the radius, v the angle)
    if (image_like && item.space == BufferSpace::screen) {
        RingSettings rs;
        rs.count = o.rings;
        rs.max_range = o.max_range;
        item.rings = ring_layout(
            item.golden.width, item.golden.height,
            parse_gaze(o.gaze, item.golden.width, item.golden.height),
            distance_px > 0.0f ? distance_px : default_distance_px(item.golden.height), rs);
    }
    CompareOptions options;
    options.threshold = o.threshold;
    options.worst_pixels = o.worst;
    options.rings = item.rings ? &*item.rings : nullptr;
    options.mask = mask;
    options.axis_errors = item.space != BufferSpace::screen && item.golden.height > 1;
    item.result = compare_buffers(item.name, item.golden, item.candidate, tolerance, options);
    const std::string hints = candidate_hints(item, tolerance);
    if (!hints.empty()) note += (note.empty() ? "" : "; ") + hints;
    if (item.result.nonfinite_mismatches > 0)
        note += std::string(note.empty() ? "" : "; ") +
                std::to_string(item.result.nonfinite_mismatches) +
                " value(s) non-finite on one side only: a convention mismatch? fovref writes 0 "
                "depth, 0 attributes and id -1 on background, never inf or NaN (docs/diff.md)";
    if (o.flip && item.kind == "color" && item.golden.channels == 3) {
        // LDR-FLIP on what a viewer sees (SPEC §10), pixels per degree from the display model.
        // Without a display model (two plain images): NVlabs's default observer, not the 60
        // degree field of view the error ranges assume (docs/diff.md).
        FlipParams fp;
        if (distance_px > 0.0f) {
            fp.pixels_per_degree = flip_pixels_per_degree(distance_px);
            item.flip_observer =
                "display model, viewing distance " + number_text(distance_px, "%.4g", "-") + " px";
        } else {
            item.flip_observer =
                "NVlabs default observer: 0.7 m from a 0.7 m wide 3840-pixel monitor";
        }
        item.flip_ppd = fp.pixels_per_degree;
        item.flip = ldr_flip(to_display(item.golden), to_display(item.candidate), fp);
    }
    item.compared = true;
    item.pass = item.result.pass;
    item.note = note;
}

// The mask of value buffer `item` among items [first, end) of one frame: the pixels where every
// compared id buffer of its size agrees (empty: none, or --no-id-mask); names them in
// item.masked_by. A decision buffer judged against its margin masks nothing: its far flips fail
// on their own, and the pixels its near flips change are attributed to them
// (attribute_to_decisions) rather than left out, so a wrong value beside a flip still shows.
std::vector<std::uint8_t> id_mask(const DiffOptions& o, DiffReport& report, std::size_t first,
                                  std::size_t end, DiffItem& item) {
    std::vector<std::uint8_t> mask;
    if (o.no_id_mask || item.hash_only || item.candidate_file.empty()) return mask;
    for (std::size_t i = first; i < end; ++i) {
        const DiffItem& ids = report.items[i];
        if (!ids.is_id || !ids.compared || ids.hash_only || !ids.ids.margin_source.empty() ||
            ids.golden.width != item.golden.width || ids.golden.height != item.golden.height)
            continue;
        if (mask.empty()) mask.assign(ids.ids.agree.size(), 1);
        for (std::size_t p = 0; p < mask.size(); ++p) mask[p] &= ids.ids.agree[p];
        item.masked_by.push_back(ids.name);
    }
    return mask;
}

// --margin N: the pixels within N of the image's border are left out (counted in
// item.margin_pixels).
void add_margin(const DiffOptions& o, DiffItem& item, std::vector<std::uint8_t>& mask) {
    const int w = item.golden.width, h = item.golden.height;
    if (o.margin <= 0 || item.hash_only || item.candidate_file.empty() || w == 0) return;
    if (mask.empty()) mask.assign(static_cast<std::size_t>(w) * h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool border =
                x < o.margin || y < o.margin || x >= w - o.margin || y >= h - o.margin;
            std::uint8_t& m = mask[static_cast<std::size_t>(y) * w + x];
            if (!border) continue;
            item.margin_pixels += m;  // only the pixels the ids had not left out already
            m = 0;
        }
}

}  // namespace

void compare_items(const DiffOptions& o, const ToleranceTable& tolerances, const ItemInputs& inputs,
                   DiffReport& report) {
    auto compare_at = [&](std::size_t k, const std::vector<std::uint8_t>* mask,
                          const Image* margin) {
        DiffItem& item = report.items[k];
        if (item.candidate_file.empty()) {
            ++report.missing;
            item.note = item.required ? "missing in the candidate, and required (--require)"
                                      : "missing in the candidate: not compared";
            if (item.required) {
                item.pass = false;
                ++report.missing_required;
            }
            return;
        }
        compare_item(o, tolerances, o.distance_px > 0.0f ? o.distance_px : inputs.distances[k],
                     item, inputs.expected_sha[k], mask, margin);
        ++report.compared;
    };
    for (std::size_t first = 0; first < report.items.size();) {
        std::size_t end = first;
        while (end < report.items.size() && report.items[end].frame == report.items[first].frame)
            ++end;
        for (std::size_t k = first; k < end; ++k) {
            if (!report.items[k].is_id) continue;
            const Tolerance& t = tolerances.for_buffer(report.items[k].name);
            Image storage;
            std::string why;
            const Image* margin = t.margin.empty() || report.items[k].candidate_file.empty()
                                      ? nullptr
                                      : decision_margin(o, inputs, report, first, end,
                                                        report.items[k], t, storage, why);
            compare_at(k, nullptr, margin);
            if (!why.empty())
                report.items[k].note += (report.items[k].note.empty() ? "" : "; ") + why;
        }
        for (std::size_t k = first; k < end; ++k) {
            if (report.items[k].is_id) continue;
            std::vector<std::uint8_t> mask = id_mask(o, report, first, end, report.items[k]);
            add_margin(o, report.items[k], mask);
            compare_at(k, mask.empty() ? nullptr : &mask, nullptr);
        }
        first = end;
    }
    attribute_to_decisions(inputs, report);
}

}  // namespace fovref
