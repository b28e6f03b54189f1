// fovref probe on the foveated modes (ref/log_polar/probe.h): its recomputations with
// the passes' own per-pixel functions agree with the rendered buffers bit for bit at pixels in
// and out of the gaze circle, on the screen's corners and edges, and at texels traced or not.
#include <doctest/doctest.h>

#include "ref/core/error.h"
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

TEST_CASE("foveation probe: stereo pixels of both eyes and texels of each eye agree") {
    const Scene scene = make_procedural_scene("cornell");
    for (const std::string barrel : {"off", "on"}) {
        RenderSettings s;
        s.width = 96;
        s.height = 40;
        s.params = Params({{"barrel", barrel}});
        // Both eyes, their centres, the seam between them and the screen's corners.
        for (const auto& p : {std::pair{10, 20}, std::pair{60, 13}, std::pair{47, 39},
                              std::pair{48, 0}, std::pair{24, 20}, std::pair{95, 39}}) {
            const ProbeReport r = probe_pixel(&scene, "stereo-lp", s, 0, p.first, p.second);
            INFO("barrel ", barrel, " pixel ", p.first, ",", p.second);
            CHECK(r.consistent);
            int traced = 0;
            for (const ProbeSection& section : r.sections)
                traced += section.stage == "stereo_trace";
            // Away from the corners (whose taps lie beyond them, untraced) and the lens's edge, a
            // pixel looks up traced texels of its eye.
            if (p.first % 48 > 8 && p.first % 48 < 40 && p.second > 5 && p.second < 35)
                CHECK(traced > 0);
        }
        for (const int eye : {0, 1})
            for (const auto& t : {std::pair{0, 0}, std::pair{10, 7}, std::pair{20, 27}}) {
                const ProbeReport r = probe_pixel(&scene, "stereo-lp", s, 0, 0, 0,
                                                  glm::ivec2(t.first, t.second), eye);
                INFO("eye ", eye, " texel ", t.first, ",", t.second);
                CHECK(r.consistent);
                REQUIRE(r.buffer_texel.has_value());
                CHECK(r.buffer_texel->y == t.second);
                CHECK(r.buffer_texel->x == eye * 34 + t.first);  // w = 34 at 96x40
            }
        // The eye is required for a stereo texel and refused for a mono one.
        CHECK_THROWS_AS(probe_pixel(&scene, "stereo-lp", s, 0, 0, 0, glm::ivec2(1, 1)), Error);
    }
    RenderSettings mono;
    mono.width = 64;
    mono.height = 36;
    CHECK_THROWS_AS(probe_pixel(&scene, "cfov", mono, 0, 0, 0, glm::ivec2(1, 1), 0), Error);
}
