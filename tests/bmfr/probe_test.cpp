// fovref probe on a BMFR-denoised frame (ref/bmfr/probe.h): phase I, the fit, the weighted sum,
// phase III, the remodulation and the TAA recomputed by the phases' own per-pixel functions agree
// with the rendered buffers bit for bit - on the first frame (no history), later frames (whose
// offset grids differ), at the screen's corners (mirrored blocks, taps outside the image), and
// with the emission kept out of the fit.
#include <doctest/doctest.h>

#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "ref/stage/probe.h"

using namespace fovref;

TEST_CASE("BMFR probe: every phase at a pixel agrees with the frame, bit for bit") {
    const Scene scene = make_procedural_scene("cornell");
    for (const std::string emission : {"include", "separate"}) {
        RenderSettings s;
        s.width = 72;
        s.height = 40;
        s.time_step = 1.0f / 30;
        s.params = Params({{"denoise", "bmfr"}, {"bmfr_emission", emission}});
        for (const int frame : {0, 1, 3})
            for (const auto& p :
                 {std::pair{36, 20}, std::pair{0, 0}, std::pair{71, 39}, std::pair{33, 2}}) {
                const ProbeReport r =
                    probe_pixel(&scene, find_mode("pathtrace"), s, frame, p.first, p.second);
                INFO("emission ", emission, " frame ", frame, " pixel ", p.first, ",", p.second);
                CHECK(r.consistent);
                int phases = 0, checks = 0;
                for (const ProbeSection& section : r.sections) {
                    phases += section.stage.rfind("bmfr_", 0) == 0;
                    for (const ProbeLine& line : section.lines) checks += line.key == "check";
                }
                CHECK(phases == 6);  // phase I, fit, weighted sum, phase III, remodulate, TAA
                CHECK(checks ==
                      8);  // accumulated, spp, accept, fitted, filtered, display, taa, final
            }
    }
}

TEST_CASE("BMFR probe: a pathtrace frame without BMFR gets no BMFR sections") {
    const Scene scene = make_procedural_scene("cornell");
    RenderSettings s;
    s.width = 40;
    s.height = 24;
    const ProbeReport r = probe_pixel(&scene, find_mode("pathtrace"), s, 0, 10, 10);
    CHECK(r.consistent);
    for (const ProbeSection& section : r.sections) CHECK(section.stage.rfind("bmfr_", 0) != 0);
}
