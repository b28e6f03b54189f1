#include "ref/modes/modes.h"

#include "ref/core/error.h"
#include "ref/image/image.h"
#include "ref/modes/building_blocks.h"
#include "ref/modes/log_polar.h"
#include "ref/modes/ray_tracing.h"
#include "ref/modes/sparse_sampling.h"
#include "ref/modes/visual_polar.h"

namespace fovref {

namespace {

std::vector<ModeInfo> make_modes() {
    std::vector<ModeInfo> modes = {
        basic_mode(),
        ground_truth_mode(),
        foveated_mode("fov", "log-polar foveated ray tracing, shaded as basic"),
        foveated_mode("kfov", "kernel log-polar foveated ray tracing, K(x) = x^alpha"),
        foveated_mode("cfov", "log-polar foveation with a ray-traced gaze buffer (composite)"),
        foveated_mode("ckfov", "kernel log-polar foveation with a gaze buffer"),
        foveated_mode("kfr",
                      "kernel foveated rendering: deferred shading in the log-polar buffer, "
                      "internal AA, mip resolve, post-AA; TAA with jitter after the inverse "
                      "transform"),
        stereo_mode(),
        pathtrace_mode(),
        pathtrace_reference_mode(),
        visual_polar_mode(),
        visual_polar_basic_mode(),
        log_polar_pathtrace_mode(),
        linear_falloff_mode(),
        acuity_mode(),
    };
    for (ModeInfo& mode : building_block_modes()) modes.push_back(std::move(mode));
    return modes;
}

}  // namespace

const std::vector<ModeInfo>& render_modes() {
    static const std::vector<ModeInfo> modes = make_modes();
    return modes;
}

bool carries_state(const ModeInfo& mode, const Params& params) {
    const auto on = [&](const char* key, const char* off) {
        const auto it = params.values().find(key);
        return it != params.values().end() && it->second != off;
    };
    if (mode.parameters_carry_state && mode.parameters_carry_state(params)) return true;
    return !mode.stateless || on("taa", "off") || on("denoise", "none");
}

const ModeInfo& find_mode(const std::string& name) {
    for (const ModeInfo& mode : render_modes())
        if (mode.name == name) return mode;
    std::vector<std::string> names;
    for (const ModeInfo& mode : render_modes()) names.push_back(mode.name);
    throw Error("unknown mode '" + name + "' (modes: " + join_names(names) + ")");
}

std::vector<std::string> render_each(const Scene* scene, const std::string& mode,
                                     const RenderSettings& settings,
                                     const std::function<void(FrameResult&)>& on_frame) {
    return render_each(scene, find_mode(mode), settings, on_frame);
}

std::vector<FrameResult> render(const Scene* scene, const std::string& mode,
                                const RenderSettings& settings) {
    return render(scene, find_mode(mode), settings);
}

ProbeReport probe_pixel(const Scene* scene, const std::string& mode, const RenderSettings& settings,
                        int frame, int x, int y, std::optional<glm::ivec2> texel, int eye) {
    return probe_pixel(scene, find_mode(mode), settings, frame, x, y, texel, eye);
}

std::vector<FrameResult> render_golden_case(const GoldenCase& golden_case, const Scene* scene,
                                            const std::vector<std::string>& requested,
                                            const std::function<void(double)>& progress) {
    return render(scene, golden_case.mode, case_settings(golden_case, requested, progress));
}

}  // namespace fovref
