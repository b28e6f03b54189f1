#include "tools/cli/commands/diff/diff.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "ref/metrics/flip.h"
#include "tools/cli/commands/diff/internal.h"

namespace fs = std::filesystem;

namespace fovref {

std::string DiffItem::status() const {
    if (!compared) return required ? "MISSING" : "missing";
    return pass ? "pass" : "FAIL";
}

bool DiffItem::focus_pixel(int& x, int& y) const {
    if (!compared || hash_only) return false;
    if (is_id) {
        if (ids.mismatches.empty()) return false;
        x = ids.mismatches[0].x;  // interior mismatches are listed first
        y = ids.mismatches[0].y;
        return true;
    }
    if (result.worst.empty()) return false;
    x = result.worst[0].x;
    y = result.worst[0].y;
    return true;
}

int run_diff(const DiffOptions& o) {
    if (o.flip && o.distance_px > 0.0f) {
        char text[48];
        std::snprintf(text, sizeof text, "--distance-px %g", static_cast<double>(o.distance_px));
        check_flip_viewing_distance(o.distance_px, text);
    }
    tolerance_profile(o.profile);  // an unknown profile is an error before any file is read
    if (!fs::exists(o.golden)) throw Error(o.golden + ": no such file or directory");
    if (!fs::exists(o.candidate)) throw Error(o.candidate + ": no such file or directory");

    DiffReport report;
    report.golden = o.golden;
    report.candidate = o.candidate;
    report.profile = o.profile;
    const bool golden_bundle = fs::is_directory(o.golden);
    const bool candidate_dir = fs::is_directory(o.candidate);
    Manifest manifest;
    ItemInputs inputs;
    if (golden_bundle) {
        manifest = read_manifest(o.golden);
        collect_bundle_items(o, manifest, candidate_dir, report, inputs);
    } else {
        collect_image_item(o, candidate_dir, report, inputs);
    }

    // The buffer names the tolerances must name; buffers compared as integers
    std::vector<std::string> names;
    const auto add_name = [&names](const std::string& name) {
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    };
    for (const ManifestBuffer& b : manifest.buffers) add_name(b.name);
    for (const DiffItem& item : report.items) add_name(item.name);
    const ToleranceTable tolerances = diff_tolerances(o, names);
    for (DiffItem& item : report.items)
        item.is_id = item.is_id || tolerances.for_buffer(item.name).integer;
    // --require all leaves out the oracle's decision margins: a port does not write them
    if (o.require == "all")
        for (const std::string& name : names)
            for (DiffItem& item : report.items)
                if (item.name == tolerances.for_buffer(name).margin) item.required = false;
    compare_items(o, tolerances, inputs, report);
    for (std::size_t k = 0; k < report.items.size(); ++k)
        if (!report.items[k].pass) {
            ++report.failed;
            if (report.first_failing < 0) report.first_failing = static_cast<int>(k);
        }
    if (report.compared == 0)
        throw Error("nothing to compare: no file in " + o.candidate +
                    " is named like a buffer of " + o.golden +
                    " (expected e.g. f000_final.pfm or final.pfm; see `fovref diff --help`)");
    report.pass = report.failed == 0;
    if (report.first_failing >= 0 && golden_bundle) {
        const DiffItem& item = report.items[static_cast<std::size_t>(report.first_failing)];
        int x = 0, y = 0;
        if (item.focus_pixel(x, y)) report.probe_command = probe_command(manifest, item, x, y);
    }

    // Reports.
    if (!o.json_path.empty()) {
        const std::string text = report_json(o, report).dump(1) + "\n";
        if (o.json_path == "-")
            std::cout << text;
        else
            write_file_atomic(o.json_path, text);
    }
    if (!o.html_dir.empty()) write_diff_html(report, o.html_dir);
    if (!o.quiet && o.json_path != "-") print_summary(report);
    return report.pass ? 0 : 1;
}

}  // namespace fovref
