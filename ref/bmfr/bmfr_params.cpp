#include "ref/bmfr/bmfr_params.h"

#include "ref/core/error.h"

namespace fovref {

std::vector<ParamSpec> bmfr_param_specs(const char* denoise_default) {
    return {{"denoise", denoise_default,
             "'none' (the noisy 1-spp image is the final image) or 'bmfr' (blockwise multi-order "
             "feature regression, Koskela P2; SPEC §9)"},
            {"bmfr_storage", "half",
             "BMFR block matrix precision: 'half' (binary16, as the authors' code) or 'float'"},
            {"bmfr_position_limit_squared", "0.01",
             "BMFR reprojection: a history tap is kept when |P' - P|^2 is below this (scene "
             "units squared)"},
            {"bmfr_normal_limit_squared", "0.25",
             "BMFR reprojection: a history tap is kept when |n' - n|^2 is below this"},
            {"bmfr_noise_hash", "jenkins",
             "the stochastic regularisation's integer hash: 'jenkins' (Bob Jenkins' six-shift "
             "hash, the authors' bmfr.cl random()) or 'wang' (Thomas Wang's, fovref's before; "
             "docs/bmfr.md)"},
            {"bmfr_sums", "binary64",
             "the QR's column norms and dot products: 'binary64' (rows in order, rounded once) "
             "or 'workgroup' (in float, in the order of the authors' fitter on 256 work items; "
             "docs/bmfr.md)"},
            {"bmfr_remodulate", "floor",
             "remodulation: 'floor' multiplies by max(albedo, 0.01), the inverse of the "
             "demodulation (SPEC §9), or 'albedo' by the albedo itself, as the authors' "
             "accumulate_filtered_data (a pixel of albedo below 0.01 comes out darker)"},
            {"bmfr_gamma", "0.454545",
             "the remodulation's display exponent: '0.454545' (the authors' constant) or "
             "'1/2.2' (0.45454547, fovref's before); docs/bmfr.md"},
            {"bmfr_block", "32",
             "the block edge in pixels (texels): '32' (the authors') or '64' (Koskela P2 §6.1: "
             "the best quality; the grid's offsets scaled by 2)"},
            {"bmfr_behind_camera", "reject",
             "phase I's reprojection of a point behind the previous camera: 'reject' (no "
             "history) or 'project' (divided by the negative clip w, as the authors' code)"},
            {"bmfr_emission", "include",
             "'include': the whole radiance is demodulated (SPEC §9); 'separate': the emission "
             "seen directly is kept out of the fit and added back when remodulating (our "
             "extension: no smear around visible lights)"}};
}

BmfrSettings parse_bmfr_params(const Params& params, const char* denoise_default) {
    const std::vector<ParamSpec> specs = bmfr_param_specs(denoise_default);
    BmfrSettings s;
    const std::string denoise = params.get_string(specs, "denoise");
    if (denoise == "bmfr")
        s.enabled = true;
    else if (denoise != "none")
        throw Error("parameter 'denoise': expected 'none' or 'bmfr', got '" + denoise + "'");
    const std::string storage = params.get_string(specs, "bmfr_storage");
    if (storage == "half")
        s.params.storage = BmfrStorage::half;
    else if (storage == "float")
        s.params.storage = BmfrStorage::single;
    else
        throw Error("parameter 'bmfr_storage': expected 'half' or 'float', got '" + storage + "'");
    s.params.position_limit_squared =
        params.get_float(specs, "bmfr_position_limit_squared", 0.0f, 1e30f);
    s.params.normal_limit_squared =
        params.get_float(specs, "bmfr_normal_limit_squared", 0.0f, 4.0f);
    const std::string hash = params.get_string(specs, "bmfr_noise_hash");
    if (hash != "jenkins" && hash != "wang")
        throw Error("parameter 'bmfr_noise_hash': expected 'jenkins' or 'wang', got '" + hash +
                    "'");
    s.params.noise_hash = hash == "jenkins" ? BmfrNoiseHash::jenkins : BmfrNoiseHash::wang;
    s.params.sums = params.get_choice(specs, "bmfr_sums", {"binary64", "workgroup"}) == 0
                        ? BmfrSums::binary64
                        : BmfrSums::workgroup;
    if (params.get_choice(specs, "bmfr_remodulate", {"floor", "albedo"}) == 1)
        s.params.remodulation_floor = 0.0f;
    const std::string gamma = params.get_string(specs, "bmfr_gamma");
    if (gamma != "0.454545" && gamma != "1/2.2")
        throw Error("parameter 'bmfr_gamma': expected '0.454545' or '1/2.2', got '" + gamma + "'");
    s.params.display_exponent = gamma == "0.454545" ? 0.454545f : 1.0f / 2.2f;
    const std::string block = params.get_string(specs, "bmfr_block");
    if (block != "32" && block != "64")
        throw Error("parameter 'bmfr_block': expected '32' or '64', got '" + block + "'");
    s.params.block_size = block == "64" ? 64 : 32;
    const std::string behind = params.get_string(specs, "bmfr_behind_camera");
    if (behind != "reject" && behind != "project")
        throw Error("parameter 'bmfr_behind_camera': expected 'reject' or 'project', got '" +
                    behind + "'");
    s.params.project_behind_camera = behind == "project";
    const std::string emission = params.get_string(specs, "bmfr_emission");
    if (emission != "separate" && emission != "include")
        throw Error("parameter 'bmfr_emission': expected 'separate' or 'include', got '" +
                    emission + "'");
    s.params.separate_emission = emission == "separate";
    if (!s.enabled)
        for (const ParamSpec& spec : specs)
            if (spec.name != "denoise" && params.given(spec.name))
                throw Error("parameter '" + spec.name + "' applies to denoise=bmfr only");
    return s;
}

}  // namespace fovref
