// `probe --debugger`'s breakpoints (ref/stage/debugger.h): each function's condition names the
// coordinates it receives - the pixel, the texels pass 2 reads, the pixel within its eye, the
// BMFR block - and the frame and stage; functions that do not compute the target get no
// breakpoint and a reason. tests/cli/debugger.sh runs them under gdb.
#include <doctest/doctest.h>

#include <cmath>

#include "ref/stage/debugger.h"
#include "tests/stage/mode_test_util.h"

using namespace fovref;
using namespace fovref::test;

namespace {

Pipeline two_stages() {
    Pipeline p;
    p.add({"trace", {}, {}, nullptr, nullptr}).add({"resolve", {}, {}, nullptr, nullptr});
    return p;
}

RenderSettings screen(int width, int height) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    return s;
}

}  // namespace

TEST_CASE("debugger: a 2 x 2 block of texels is a range, other sets one test per texel") {
    const std::vector<PixelFunction> functions = {
        {"trace", "fovref::trace_texel", "", PixelArgs::texel, "lp_"},
        {"resolve", "fovref::resolve_pixel", ""}};
    DebugTarget target;
    target.frame = 3;
    target.pixel = glm::ivec2(10, 20);
    target.texels = {{"lp_", {4, 7}}, {"lp_", {5, 7}}, {"lp_", {4, 8}}, {"lp_", {5, 8}}};
    std::vector<Breakpoint> b =
        debugger_breakpoints(functions, two_stages(), screen(32, 32), target);
    REQUIRE(b.size() == 2);
    CHECK(b[0].condition ==
          "x >= 4 && x <= 5 && y >= 7 && y <= 8 && fovref::debugger_position.frame == 3 && "
          "fovref::debugger_position.stage == 0");
    CHECK(b[0].points.size() == 4);
    CHECK(b[1].condition ==
          "x == 10 && y == 20 && fovref::debugger_position.frame == 3 && "
          "fovref::debugger_position.stage == 1");
    // three texels of a wrapped column do not fill their rectangle
    target.texels = {{"lp_", {4, 0}}, {"lp_", {4, 9}}, {"lp_", {5, 0}}};
    b = debugger_breakpoints(functions, two_stages(), screen(32, 32), target);
    CHECK(b[0].condition.rfind("((x == 4 && y == 0) || (x == 4 && y == 9) || (x == 5 && y == 0))",
                               0) == 0);
}

TEST_CASE("debugger: functions that do not compute the target get no breakpoint, with a reason") {
    const std::vector<PixelFunction> functions = {
        {"trace", "fovref::gaze_pixel", "", PixelArgs::screen, "gaze_"},
        {"trace", "fovref::trace_texel", "", PixelArgs::texel, "lp_"},
        {"resolve", "fovref::resolve_pixel", ""}};
    DebugTarget pixel;
    pixel.pixel = glm::ivec2(1, 2);
    pixel.texels = {{"lp_", {4, 7}}};
    std::vector<Breakpoint> b = debugger_breakpoints(functions, two_stages(), screen(8, 8), pixel);
    CHECK(b[0].condition.empty());
    CHECK(b[0].skipped == "this pixel reads no gaze_ texel");
    CHECK(!b[1].condition.empty());
    DebugTarget texel;
    texel.texels = {{"lp_", {4, 7}}};
    b = debugger_breakpoints(functions, two_stages(), screen(8, 8), texel);
    CHECK(b[1].condition.rfind("x == 4 && y == 7 && ", 0) == 0);
    CHECK(b[2].condition.empty());
    CHECK(b[2].skipped.find("a texel probe") != std::string::npos);
    CHECK_THROWS_WITH_AS(
        debugger_breakpoints({{"shade", "fovref::f", ""}}, two_stages(), screen(8, 8), pixel),
        doctest::Contains("stage 'shade'"), Error);
    CHECK_THROWS_WITH_AS(debugger_command("gdb", "fovref", {}, {b[2]}),
                         doctest::Contains("no per-pixel function"), Error);
}

TEST_CASE("debugger: the rasterizer's functions get no breakpoint on a background pixel") {
    std::vector<PixelFunction> functions = {{"trace", "fovref::raster_fragment", ""},
                                            {"resolve", "fovref::shade_pixel", ""}};
    functions[0].needs_geometry = true;
    DebugTarget target;
    target.pixel = glm::ivec2(3, 4);
    target.background = {{3, 4}};
    std::vector<Breakpoint> b = debugger_breakpoints(functions, two_stages(), screen(8, 8), target);
    CHECK(b[0].condition.empty());
    CHECK(b[0].skipped.find("no triangle covers (3, 4)") != std::string::npos);
    CHECK_FALSE(b[1].condition.empty());  // a pass that does not need a triangle still stops
    target.background.clear();
    b = debugger_breakpoints(functions, two_stages(), screen(8, 8), target);
    CHECK_FALSE(b[0].condition.empty());
}

TEST_CASE("debugger: a stereo pixel stops in its eye's TAA at the pixel within the eye") {
    const std::vector<PixelFunction> functions = {
        {"resolve", "fovref::taa_pixel", "", PixelArgs::eye_pixel}};
    DebugTarget target;
    target.pixel = glm::ivec2(100, 30);
    target.eye_width = 64;
    const std::vector<Breakpoint> b =
        debugger_breakpoints(functions, two_stages(), screen(128, 48), target);
    CHECK(b[0].condition.rfind("x == 36 && y == 30 && fovref::debugger_position.eye == 1", 0) == 0);
    CHECK(b[0].eye == 1);
}

TEST_CASE("debugger: kfr's raster breakpoints are the G-buffer pixels lp_sample copied") {
    // Against the rendered frame: each lp_ texel the pixel reads was sampled at its
    // lp_screen_point, so the G-buffer pixel is that point floored (frame 1 with TAA's jitter).
    const ModeInfo& mode = find_mode("kfr");
    const std::vector<FrameResult> frames =
        render_all("cornell", "kfr", 96, 54, 2, {{"taa", "depth"}});
    RenderSettings s = screen(96, 54);
    s.params = Params(std::map<std::string, std::string>{{"taa", "depth"}});
    s.time_step = 1.0f / 30;
    const Image& points = buffer(frames[1], "lp_screen_point");
    int checked = 0;
    for (const glm::ivec2& pixel : {glm::ivec2(5, 5), glm::ivec2(30, 40), glm::ivec2(90, 10)}) {
        std::vector<glm::ivec2> expected, got;
        for (const TexelRead& read :
             mode.pixel_texels(scene_named("cornell"), s, 1, pixel.x, pixel.y)) {
            if (read.family == "gbuffer_") got.push_back(read.texel);
            if (read.family != "lp_") continue;
            const glm::ivec2 p{
                static_cast<int>(std::floor(points.at(read.texel.x, read.texel.y, 0))),
                static_cast<int>(std::floor(points.at(read.texel.x, read.texel.y, 1)))};
            if (std::find(expected.begin(), expected.end(), p) == expected.end())
                expected.push_back(p);
        }
        CHECK(got == expected);
        checked += static_cast<int>(got.size());
    }
    CHECK(checked >= 6);
}
