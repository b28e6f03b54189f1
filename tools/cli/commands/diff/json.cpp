#include <cmath>
#include <nlohmann/json.hpp>

#include "tools/cli/commands/diff/internal.h"
#include "tools/cli/report/json_values.h"

namespace fovref {

namespace {

using json = nlohmann::json;

json tolerance_json(const Tolerance& t, bool is_id) {
    if (is_id) {
        json j{{"edge_mismatch_share", t.max_edge_mismatch_share},
               {"interior_mismatches", t.max_interior_mismatches},
               {"reason", t.reason}};
        if (!t.margin.empty()) j["margin"] = t.margin, j["margin_epsilon"] = t.margin_epsilon;
        return j;
    }
    return {{"abs", t.abs},
            {"rel", t.rel},
            {"ulp", t.ulp},
            {"max_failing_pixels", t.max_failing_pixels},
            {"max_failing_share", t.max_failing_share},
            {"reason", t.reason}};
}

json pixel_json(const PixelDifference& d) {
    return json{{"x", d.x},
                {"y", d.y},
                {"abs_error", number_json(d.abs_error)},
                {"golden", d.golden},
                {"candidate", d.candidate}};
}

// An id buffer's comparison: the counts and every listed mismatch.
void add_ids_json(const IdComparison& r, json& j) {
    j["width"] = r.width;
    j["height"] = r.height;
    j["channels"] = r.channels;
    j["tolerance"] = tolerance_json(r.tolerance, true);
    j["edge_pixels"] = r.edge_pixels;
    j["edge_mismatches"] = r.edge_mismatches;
    j["allowed_edge_mismatches"] = r.allowed_edge_mismatches;
    j["interior_mismatches"] = r.interior_mismatches;
    if (!r.margin_source.empty()) {
        j["decision_margin"] = r.margin_source;
        j["near_threshold_flips"] = r.near_threshold;
        j["near_threshold_max_margin"] = number_json(r.near_max_margin);
        j["far_flip_min_margin"] = number_json(r.far_min_margin);
    }
    j["mismatches"] = json::array();
    for (const IdMismatch& m : r.mismatches)
        j["mismatches"].push_back({{"x", m.x},
                                   {"y", m.y},
                                   {"edge", m.edge},
                                   {"golden", m.golden},
                                   {"candidate", m.candidate}});
}

// A value buffer's LDR-FLIP and its ring statistics (when it has them).
void add_flip_and_rings_json(const DiffItem& item, json& j) {
    const BufferComparison& r = item.result;
    if (item.flip)
        j["flip"] = {{"mean", item.flip->mean},
                     {"weighted_median", item.flip->weighted_median},
                     {"first_quartile", item.flip->first_quartile},
                     {"third_quartile", item.flip->third_quartile},
                     {"min", item.flip->min},
                     {"max", item.flip->max},
                     {"pixels_per_degree", item.flip_ppd},
                     {"observer", item.flip_observer},
                     {"pooling", flip_pooling_note}};
    if (!r.column_rmse.empty()) {
        // NaN (no compared element) as null
        const auto array = [](const std::vector<double>& values) {
            json a = json::array();
            for (const double v : values) a.push_back(std::isfinite(v) ? json(v) : json());
            return a;
        };
        j["column_rmse"] = array(r.column_rmse);
        j["row_rmse"] = array(r.row_rmse);
    }
    if (r.rings.empty()) return;
    json rings = json::array();
    for (const RingStats& s : r.rings) rings.push_back(ring_json(s));
    j["rings"] = rings;
    j["ring_layout"] = {{"gaze", {item.rings->gaze.x, item.rings->gaze.y}},
                        {"distance_px", item.rings->distance_px},
                        {"max_eccentricity_deg", item.rings->max_eccentricity_deg},
                        {"outer_deg", item.rings->outer_deg}};
}

// A value buffer's comparison: the errors, the failing and worst pixels, FLIP and rings.
void add_values_json(const DiffItem& item, json& j) {
    const BufferComparison& r = item.result;
    j["width"] = r.width;
    j["height"] = r.height;
    j["channels"] = r.channels;
    j["tolerance"] = tolerance_json(r.tolerance, false);
    if (!item.masked_by.empty()) {
        j["masked_by"] = item.masked_by;
        j["masked_pixels"] = r.masked_pixels - item.margin_pixels;
    }
    if (item.margin_pixels > 0) j["margin_pixels"] = item.margin_pixels;
    j["max_abs_error"] = number_json(r.max_abs);
    j["max_rel_error"] = number_json(r.max_rel);
    j["max_ulp"] = r.max_ulp;
    j["nan_mismatches"] = r.nan_mismatches;
    j["nonfinite_mismatches"] = r.nonfinite_mismatches;
    j["differing_elements"] = r.differing_elements;
    j["mean_abs_error"] = number_json(r.mean_abs);
    j["rmse"] = number_json(r.rmse);
    j["psnr"] = number_json(r.psnr);
    j["ssim"] = r.ssim ? number_json(*r.ssim) : json(nullptr);
    if (r.threshold >= 0.0) j["threshold"] = r.threshold;
    j["pixels_over_threshold"] = r.pixels_over_threshold;
    j["failing_pixels"] = r.failing_pixels;
    j["allowed_failing_pixels"] = r.allowed_failing_pixels;
    j["attributed_pixels"] = r.attributed_pixels;
    j["attributed_to"] = r.attributed_to;
    if (r.first_failing) j["first_failing_pixel"] = pixel_json(*r.first_failing);
    j["worst_pixels"] = json::array();
    for (const PixelDifference& d : r.worst) j["worst_pixels"].push_back(pixel_json(d));
    add_flip_and_rings_json(item, j);
}

json item_json(const DiffItem& item) {
    json j;
    j["frame"] = item.frame;
    j["name"] = item.name;
    j["stage"] = item.stage;
    j["kind"] = item.kind;
    j["golden_file"] = item.golden_file;
    j["candidate_file"] = item.candidate_file.empty() ? json(nullptr) : json(item.candidate_file);
    j["status"] = !item.compared ? (item.required ? "missing-required" : "missing")
                  : item.pass    ? "pass"
                                 : "fail";
    j["compared_as"] = item.is_id ? "ids" : "values";
    if (!item.note.empty()) j["note"] = item.note;
    if (!item.compared || item.hash_only) return j;
    if (item.is_id)
        add_ids_json(item.ids, j);
    else
        add_values_json(item, j);
    return j;
}

}  // namespace

json report_json(const DiffOptions& o, const DiffReport& report) {
    json j;
    j["golden"] = o.golden;
    j["candidate"] = o.candidate;
    if (!report.case_name.empty()) j["case"] = report.case_name;
    j["profile"] = report.profile;
    if (!report.port.empty()) j["port"] = report.port;
    j["pass"] = report.pass;
    j["compared"] = report.compared;
    j["failed"] = report.failed;  // out of tolerance + missing and required
    j["out_of_tolerance"] = report.out_of_tolerance();
    j["summary"] = result_counts(report);
    j["missing"] = report.missing;
    j["missing_required"] = report.missing_required;
    j["ignored_files"] = report.ignored;
    if (report.first_failing >= 0) {
        const DiffItem& f = report.items[static_cast<std::size_t>(report.first_failing)];
        j["first_failing"] = {{"frame", f.frame}, {"buffer", f.name}, {"stage", f.stage}};
        if (!report.probe_command.empty()) j["probe_command"] = report.probe_command;
    }
    j["buffers"] = json::array();
    for (const DiffItem& item : report.items) j["buffers"].push_back(item_json(item));
    return j;
}

}  // namespace fovref
