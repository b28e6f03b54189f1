#include <algorithm>
#include <cstdio>
#include <string>

#include "tools/cli/commands/diff/internal.h"
#include "tools/cli/common/number_text.h"

namespace fovref {

namespace {

std::string values_text(const std::vector<float>& values) {
    std::string out = "(";
    for (std::size_t i = 0; i < values.size(); ++i) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(values[i]));
        out += (i ? ", " : "") + std::string(text);
    }
    return out + ")";
}

std::string percent(std::int64_t part, std::int64_t whole) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g%%",
                  whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0);
    return text;
}

// The widths of the table's stage and buffer columns: their longest entries.
struct Columns {
    int stage = 20, buffer = 26;
};

// The row's first columns: frame, stage, buffer, result.
void print_row_head(const DiffItem& item, const Columns& w) {
    std::printf("%-5d %-*s %-*s %-7s ", item.frame, w.stage, item.stage.c_str(), w.buffer,
                item.name.c_str(), item.status().c_str());
}

// One row of the table: a buffer's result (and its LDR-FLIP under it).
void print_row(const DiffItem& item, const Columns& w) {
    print_row_head(item, w);
    if (!item.compared || item.hash_only) {
        std::printf("%s\n", item.note.c_str());
        return;
    }
    if (item.is_id) {
        const IdComparison& r = item.ids;
        std::printf(
            "ids: %lld interior, %lld edge (%s of %lld edge "
            "px, %lld allowed)\n",
            static_cast<long long>(r.interior_mismatches),
            static_cast<long long>(r.edge_mismatches),
            percent(r.edge_mismatches, r.edge_pixels).c_str(),
            static_cast<long long>(r.edge_pixels),
            static_cast<long long>(r.allowed_edge_mismatches));
        if (!r.margin_source.empty())
            std::printf(
                "      decision (margin %s): %lld near-threshold flip(s), the oracle within "
                "%s of its threshold (not failures)%s\n",
                r.margin_source.c_str(), static_cast<long long>(r.near_threshold),
                r.near_max_margin >= 0.0 ? number_text(r.near_max_margin, "%.3g", "-").c_str()
                                         : "epsilon",
                r.far_min_margin >= 0.0 ? ("; far flips fail (the nearest " +
                                           number_text(r.far_min_margin, "%.3g", "-") + " from it)")
                                              .c_str()
                                        : "");
        if (!item.note.empty()) std::printf("      note: %s\n", item.note.c_str());
        return;
    }
    const BufferComparison& r = item.result;
    std::string masked;
    const std::int64_t by_ids = r.masked_pixels - item.margin_pixels;
    if (by_ids > 0 || item.margin_pixels > 0)
        masked = "  (" + (by_ids > 0 ? std::to_string(by_ids) + " px where ids differ" : "") +
                 (by_ids > 0 && item.margin_pixels > 0 ? ", " : "") +
                 (item.margin_pixels > 0
                      ? std::to_string(item.margin_pixels) + " px of the --margin band"
                      : "") +
                 " left out)";
    if (r.nonfinite_mismatches > 0) masked += "  convention mismatch: see note";
    std::printf("%10s %9lld %10lld %8s %8s%s\n", number_text(r.max_abs, "%.4g", "-").c_str(),
                static_cast<long long>(r.max_ulp), static_cast<long long>(r.failing_pixels),
                r.nonfinite_mismatches > 0 ? "-" : number_text(r.psnr, "%.4g", "-").c_str(),
                r.ssim ? number_text(*r.ssim, "%.4g", "-").c_str() : "-", masked.c_str());
    if (item.flip)
        std::printf(
            "      LDR-FLIP mean %.6f, weighted median %.6f, quartiles %.6f / %.6f, "
            "max %.6f; %.4g pixels per degree (%s)\n",
            item.flip->mean, item.flip->weighted_median, item.flip->first_quartile,
            item.flip->third_quartile, static_cast<double>(item.flip->max),
            static_cast<double>(item.flip_ppd), item.flip_observer.c_str());
    if (r.attributed_pixels > 0) {
        std::string by;
        for (const std::string& name : r.attributed_to) by += (by.empty() ? "" : ", ") + name;
        std::printf("      %lld failing pixel(s) attributed to near-threshold flips of %s\n",
                    static_cast<long long>(r.attributed_pixels), by.c_str());
    }
    if (!item.note.empty()) std::printf("      note: %s\n", item.note.c_str());
}

// Why an id buffer failed: its mismatch counts, its edge mismatches and the first interior one.
void print_id_failure(const IdComparison& r) {
    std::printf(
        ": %lld interior and %lld edge id mismatches (%lld and %lld allowed); "
        "later buffers are compared only where the ids agree\n",
        static_cast<long long>(r.interior_mismatches), static_cast<long long>(r.edge_mismatches),
        static_cast<long long>(r.tolerance.max_interior_mismatches),
        static_cast<long long>(r.allowed_edge_mismatches));
    // The pixel the failure points at: the first interior mismatch, else the first edge one
    if (!r.mismatches.empty()) {
        const IdMismatch& m = r.mismatches.front();
        std::printf("  first failing pixel (%d, %d): golden %s, candidate %s (%s mismatch)\n", m.x,
                    m.y, values_text(m.golden).c_str(), values_text(m.candidate).c_str(),
                    m.edge ? "edge" : "interior");
    }
    for (const IdMismatch& m : r.mismatches) {
        std::printf("  %s mismatch (%d, %d): golden %s, candidate %s\n",
                    m.edge ? "edge" : "interior", m.x, m.y, values_text(m.golden).c_str(),
                    values_text(m.candidate).c_str());
        if (!m.edge) break;  // the first interior one is what explains the failure
    }
}

// Why a value buffer failed: the pixels out of tolerance, the first failing and the worst pixel.
void print_value_failure(const DiffItem& item) {
    const BufferComparison& r = item.result;
    std::printf(
        ": %lld pixel(s) out of tolerance (abs %s, rel %s, ulp %lld, %lld allowed)\n",
        static_cast<long long>(r.failing_pixels), number_text(r.tolerance.abs, "%.4g", "-").c_str(),
        number_text(r.tolerance.rel, "%.4g", "-").c_str(), static_cast<long long>(r.tolerance.ulp),
        static_cast<long long>(r.allowed_failing_pixels));
    if (r.first_failing)
        std::printf("  first failing pixel (%d, %d): golden %s, candidate %s\n", r.first_failing->x,
                    r.first_failing->y, values_text(r.first_failing->golden).c_str(),
                    values_text(r.first_failing->candidate).c_str());
    if (!r.worst.empty())
        std::printf("  worst pixel (%d, %d): |error| %s, golden %s, candidate %s\n", r.worst[0].x,
                    r.worst[0].y, number_text(r.worst[0].abs_error, "%.4g", "-").c_str(),
                    values_text(r.worst[0].golden).c_str(),
                    values_text(r.worst[0].candidate).c_str());
}

// The first failing stage: its buffer, why it failed, and the probe command that explains it.
void print_first_failing(const DiffReport& report) {
    const DiffItem& item = report.items[static_cast<std::size_t>(report.first_failing)];
    std::printf("first failing stage: %s, buffer '%s', frame %d", item.stage.c_str(),
                item.name.c_str(), item.frame);
    if (!item.compared) {
        std::printf(": required, missing in the candidate\n");
    } else if (item.hash_only) {
        std::printf(": %s\n", item.note.c_str());
    } else if (item.is_id) {
        print_id_failure(item.ids);
    } else {
        print_value_failure(item);
    }
    if (!report.probe_command.empty())
        std::printf("  explain it: %s\n", report.probe_command.c_str());
}

}  // namespace

std::string result_counts(const DiffReport& report) {
    std::string text = std::to_string(report.compared) + " compared, " +
                       std::to_string(report.out_of_tolerance()) + " out of tolerance, " +
                       std::to_string(report.missing) + " missing in the candidate";
    if (report.missing_required > 0)
        text += ", " + std::to_string(report.missing_required) + " of them required";
    if (!report.ignored.empty())
        text += ", " + count_text(report.ignored.size(), "file") + " ignored";
    return text;
}

void print_summary(const DiffReport& report) {
    std::printf("fovref diff: golden %s%s, candidate %s, profile %s\n", report.golden.c_str(),
                report.case_name.empty() ? "" : (" (case " + report.case_name + ")").c_str(),
                report.candidate.c_str(), report.profile.c_str());
    for (const std::string& line : report.port) std::printf("port: %s\n", line.c_str());
    Columns w;
    for (const DiffItem& item : report.items) {
        w.stage = std::max(w.stage, static_cast<int>(item.stage.size()));
        w.buffer = std::max(w.buffer, static_cast<int>(item.name.size()));
    }
    std::printf("%-5s %-*s %-*s %-7s %10s %9s %10s %8s %8s\n", "frame", w.stage, "stage", w.buffer,
                "buffer", "result", "max abs", "max ulp", "fail px", "PSNR", "SSIM");
    for (const DiffItem& item : report.items) print_row(item, w);
    if (std::any_of(report.items.begin(), report.items.end(),
                    [](const DiffItem& item) { return item.flip.has_value(); }))
        std::printf("LDR-FLIP pooling: %s\n", flip_pooling_note);
    // Ignored files: one line per file whose name is close to a buffer's, the rest in one line
    std::vector<std::string> others;
    for (std::size_t k = 0; k < report.ignored.size(); ++k)
        if (report.ignored_hint[k].empty())
            others.push_back(report.ignored[k]);
        else
            std::printf("ignored: %s (matches no golden buffer; did you mean %s?)\n",
                        report.ignored[k].c_str(), report.ignored_hint[k].c_str());
    if (!others.empty()) {
        std::string list;
        for (std::size_t k = 0; k < others.size() && k < 4; ++k)
            list += (k ? ", " : "") + others[k];
        std::printf("ignored: %s named like no golden buffer (%s%s)\n",
                    count_text(static_cast<long long>(others.size()), "file").c_str(), list.c_str(),
                    others.size() > 4 ? ", ..." : "");
    }
    if (report.first_failing >= 0) print_first_failing(report);
    std::printf("RESULT: %s (%s)\n", report.pass ? "PASS" : "FAIL", result_counts(report).c_str());
}

}  // namespace fovref
