// fovref probe on the foveated modes (ref/foveation/foveation_probe.h): its recomputations with
// the passes' own per-pixel functions agree with the rendered buffers bit for bit at pixels in
// and out of the gaze circle, on the screen's corners and edges, and at texels traced or not.
#include <doctest/doctest.h>

#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"

using namespace fovref;

TEST_CASE("foveation probe: every pixel and texel explanation agrees with the frame") {
    const Scene scene = make_procedural_scene("checker-room");
    const int pixels[][2] = {{40, 22}, {0, 0}, {79, 44}, {0, 30}, {45, 24}, {70, 5}};
    for (const std::string mode : {"fov", "kfov", "cfov", "ckfov", "kfr"})
        for (const std::string filters : {"", "lerp", "internal_aa,lerp,post_aa"}) {
            RenderSettings s;
            s.width = 80;
            s.height = 45;
            s.params = Params({{"filters", filters}, {"gaze", "45.5,20"}});
            if (mode == "kfr") s.params.set("resolve", filters.empty() ? "bilinear" : "mip");
            for (const auto& p : pixels) {
                const ProbeReport r = probe_pixel(&scene, mode, s, 0, p[0], p[1]);
                INFO(mode, " ", filters, " pixel ", p[0], ",", p[1]);
                CHECK(r.consistent);
                bool resolved = false;
                for (const ProbeSection& section : r.sections)
                    resolved |= section.stage == "resolve";
                CHECK(resolved);
            }
            for (const auto& t : {std::pair{0, 0}, std::pair{5, 17}, std::pair{20, 24}}) {
                const ProbeReport r =
                    probe_pixel(&scene, mode, s, 0, 0, 0, glm::ivec2(t.first, t.second));
                INFO(mode, " texel ", t.first, ",", t.second);
                CHECK(r.consistent);
                REQUIRE(r.texel.has_value());
            }
        }
}
