#include "tools/cli/commands/gain.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "ref/analysis/gain.h"
#include "ref/core/error.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/number_text.h"

namespace fovref {

namespace {

std::string fov_text(const GainParams& p) {
    if (p.shape == FovShape::disc)
        return "disc " + number_text(p.width_deg, "%.6g") + " deg diameter (radius " +
               number_text(p.width_deg / 2.0, "%.6g") + ")";
    return "ellipse " + number_text(p.width_deg, "%.6g") + " x " +
           number_text(p.height_deg, "%.6g") + " deg";
}

// The case's parameters and result for --json.
nlohmann::json gain_json(const GainParams& p, const GainResult& r) {
    nlohmann::json j;
    j["shape"] = fov_shape_name(p.shape);
    j["width_deg"] = p.width_deg;
    if (p.shape == FovShape::ellipse) j["height_deg"] = p.height_deg;
    j["display_cpd"] = p.display_cpd;
    j["model"] = {{"peak_cpd", p.peak_cpd},
                  {"fovea_deg", p.fovea_deg},
                  {"falloff_cpd", p.falloff_cpd},
                  {"falloff_slope", p.falloff_slope}};
    if (p.shape == FovShape::ellipse) j["angle_steps"] = p.angle_steps;  // a disc is closed-form
    j["area_deg2"] = r.area_deg2;
    j["acuity_integral"] = r.acuity_integral;
    j["uniform_integral"] = r.uniform_integral;
    j["v_max_cpd"] = r.v_max_cpd;
    j["full_rate_radius_deg"] = r.full_rate_radius_deg;
    j["gain"] = r.gain;
    j["gain_percent"] = 100.0 * r.gain;
    return j;
}

// The one case of --fov-deg, its options checked by name.
GainParams params_from_options(const GainOptions& o) {
    if (o.fov_deg.empty()) {
        if (!o.shape.empty()) throw Error("gain: --shape needs --fov-deg");
        throw Error("gain: --max-cpd needs --fov-deg");
    }
    if (o.fov_deg.size() > 2)
        throw Error("gain: --fov-deg takes W (a disc's diameter) or W,H (an ellipse), got " +
                    std::to_string(o.fov_deg.size()) + " values");
    for (double v : o.fov_deg)
        if (!(std::isfinite(v) && v > 0.0 && v <= gain_max_fov_deg))
            throw Error("gain: --fov-deg: each value must be finite and in (0, 360] degrees, got " +
                        check_value_text(v));
    const std::string shape = !o.shape.empty()        ? o.shape
                              : o.fov_deg.size() == 1 ? "disc"
                                                      : "ellipse";
    if (shape == "disc" && o.fov_deg.size() != 1)
        throw Error("gain: --shape disc takes one --fov-deg value (the diameter), got 2");
    if (shape == "ellipse" && o.fov_deg.size() != 2)
        throw Error("gain: --shape ellipse takes --fov-deg W,H (full axes), got one value");
    if (!(std::isfinite(o.max_cpd) && o.max_cpd > 0.0 && o.max_cpd <= gain_max_cpd))
        throw Error("gain: --max-cpd must be finite and in (0, 10000] c/deg, got " +
                    check_value_text(o.max_cpd));
    GainParams p;
    p.shape = shape == "disc" ? FovShape::disc : FovShape::ellipse;
    p.width_deg = o.fov_deg[0];
    p.height_deg = p.shape == FovShape::ellipse ? o.fov_deg[1] : o.fov_deg[0];
    p.display_cpd = o.max_cpd;
    p.angle_steps = o.angle_steps;
    return p;
}

void print_one(const GainParams& p, const GainResult& r) {
    std::printf("theoretical gain (Koskela P1 §4): 1 - integral(V dA) / (V_max * area)\n");
    std::printf("FOV        %s, area %s deg^2\n", fov_text(p).c_str(),
                number_text(r.area_deg2, "%.6g").c_str());
    std::printf("V_max      %s c/deg (full rate up to e = %s deg)\n",
                number_text(r.v_max_cpd, "%.6g").c_str(),
                number_text(r.full_rate_radius_deg, "%.6g").c_str());
    std::printf("integral   %s of %s c/deg deg^2 (V_max * area)\n",
                number_text(r.acuity_integral, "%.6g").c_str(),
                number_text(r.uniform_integral, "%.6g").c_str());
    std::printf("gain       %.2f%%\n", 100.0 * r.gain);
    std::printf("model      %s\n", gain_model_line);
    std::printf("note       %s\n", gain_density_note);
}

int run_table(const GainOptions& o) {
    std::vector<GainCase> cases = p1_gain_cases();
    std::vector<GainResult> results;
    for (GainCase& c : cases) {
        c.params.angle_steps = o.angle_steps;
        results.push_back(theoretical_gain(c.params));
    }
    if (o.json) {
        nlohmann::json j;
        j["cases"] = nlohmann::json::array();
        for (std::size_t k = 0; k < cases.size(); ++k) {
            nlohmann::json c = gain_json(cases[k].params, results[k]);
            c["name"] = cases[k].name;
            c["description"] = cases[k].description;
            c["quoted_percent"] = cases[k].quoted_percent;
            c["quoted"] = cases[k].quoted;
            j["cases"].push_back(c);
        }
        j["model"] = gain_model_line;
        j["note"] = gain_density_note;
        std::cout << j.dump(2) << "\n";
        return exit_ok;
    }
    std::printf(
        "Koskela P1 §4: theoretical gain = 1 - integral(V dA) / (V_max * area), gaze at the FOV "
        "centre\n");
    std::printf("%-18s %-38s %-11s %-7s %s\n", "case", "FOV", "V_max", "gain", "sources quote");
    for (std::size_t k = 0; k < cases.size(); ++k) {
        char gain[16];
        std::snprintf(gain, sizeof gain, "%.2f%%", 100.0 * results[k].gain);
        std::printf("%-18s %-38s %-11s %-7s %s\n", cases[k].name.c_str(),
                    fov_text(cases[k].params).c_str(),
                    (number_text(results[k].v_max_cpd, "%.6g") + " c/deg").c_str(), gain,
                    cases[k].quoted.c_str());
    }
    std::printf("model: %s\n", gain_model_line);
    std::printf("note: %s\n", gain_density_note);
    return exit_ok;
}

}  // namespace

int run_gain(const GainOptions& o) {
    if (o.fov_deg.empty() && o.shape.empty() && !o.max_cpd_given) return run_table(o);
    const GainParams p = params_from_options(o);
    const GainResult r = theoretical_gain(p);
    if (o.json) {
        nlohmann::json j = gain_json(p, r);
        j["model"] = gain_model_line;
        j["note"] = gain_density_note;
        std::cout << j.dump(2) << "\n";
    } else {
        print_one(p, r);
    }
    return exit_ok;
}

}  // namespace fovref
