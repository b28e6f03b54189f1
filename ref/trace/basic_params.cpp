#include "ref/trace/basic_params.h"

#include <string>

#include "ref/core/error.h"

namespace fovref {

std::vector<ParamSpec> basic_param_specs() {
    return {
        {"primary", "ray", "primary visibility: 'ray' (ray casting) or 'raster' (the rasterizer)"},
        {"fill_rule", "d3d",
         "rasterizer fill rule for pixel centres exactly on an edge (primary=raster): 'd3d' "
         "(Direct3D/Vulkan top-left) or 'gl' (OpenGL; bottom-left in fovref's y-down frame)"}};
}

BasicParams parse_basic_params(const Params& params) {
    const std::vector<ParamSpec> specs = basic_param_specs();
    BasicParams parsed;
    const std::string primary = params.get_string(specs, "primary");
    if (primary == "ray")
        parsed.primary = PrimaryVisibility::ray;
    else if (primary == "raster")
        parsed.primary = PrimaryVisibility::raster;
    else
        throw Error("parameter 'primary': '" + primary + "' is neither 'ray' nor 'raster'");
    parsed.raster.fill_rule =
        parse_fill_rule(params.get_string(specs, "fill_rule"), "parameter 'fill_rule'");
    if (parsed.primary == PrimaryVisibility::ray && params.values().count("fill_rule") != 0)
        throw Error("parameter 'fill_rule' applies to the rasterizer only: add primary=raster");
    return parsed;
}

}  // namespace fovref
