// Gaze tracks (ref/gaze/gaze_track.h): the CSV format, its errors with file and line, the
// frame -> gaze rule, and a foveated sequence driven by a track equal frame by frame to renders
// with the fixed gaze of each frame.
#include <doctest/doctest.h>

#include <cstring>

#include "ref/gaze/gaze_track.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

TEST_CASE("gaze track: format, errors with the line, the sample a frame uses") {
    const std::vector<GazeSample> t = parse_gaze_track(
        "frame,x,y\n# recorded at 120 Hz\n0, 10.5, 20\n\n3,-5,1e3\r\n7,640,360", "t.csv");
    REQUIRE(t.size() == 3);
    CHECK(t[1] == GazeSample{3, {-5.0f, 1000.0f}});
    CHECK(gaze_at_frame(t, 0) == glm::vec2(10.5f, 20.0f));
    CHECK(gaze_at_frame(t, 2) == glm::vec2(10.5f, 20.0f));  // held until the next sample
    CHECK(gaze_at_frame(t, 3) == glm::vec2(-5.0f, 1000.0f));
    CHECK(gaze_at_frame(t, 100) == glm::vec2(640.0f, 360.0f));
    const std::vector<GazeSample> late = parse_gaze_track("5,1,2\n", "late.csv");
    CHECK(gaze_at_frame(late, 0) == glm::vec2(1.0f, 2.0f));  // before the first: the first
    const auto message = [](const std::string& text) {
        return test::error_message([&] { parse_gaze_track(text, "g.csv"); });
    };
    CHECK(message("0,1,2\n0,3,4\n") ==
          "g.csv:2: frame 0 does not follow frame 0 (frames must "
          "strictly increase)");
    CHECK(message("0,1\n") == "g.csv:1: expected 'frame,x,y', got '0,1'");
    CHECK(message("0,1,2,3\n") == "g.csv:1: expected 'frame,x,y', got '0,1,2,3'");
    CHECK(test::contains(message("#\n-1,1,2\n"), "g.csv:2: frame '-1' is not an integer >= 0"));
    CHECK(test::contains(message("1,nan,2\n"), "g.csv:1: gaze 'nan,2' is not two finite"));
    CHECK(test::contains(message("1,1e9,2\n"), "within 1e7 pixels"));
    CHECK(test::contains(message("1,x,2\n"), "g.csv:1: gaze"));
    CHECK(message("# nothing\n\n") == "g.csv: no gaze sample (expected lines 'frame,x,y')");
    CHECK(test::contains(test::error_message([] { read_gaze_track("/nonexistent/g.csv"); }),
                         "/nonexistent/g.csv"));
}

TEST_CASE("gaze track: a sequence follows the track frame by frame") {
    const Scene scene = make_procedural_scene("cornell");
    test::TempDir dir("gaze-track");
    test::write_bytes(dir.file("g.csv"), "0,20,15\n1,60.5,30\n");
    RenderSettings s;
    s.width = 80;
    s.height = 45;
    s.frame_count = 3;
    s.params = Params(std::map<std::string, std::string>{{"gaze_track", dir.file("g.csv")}});
    const std::vector<FrameResult> tracked = render(&scene, "cfov", s);
    REQUIRE(tracked.size() == 3);
    const char* gazes[3] = {"20,15", "60.5,30", "60.5,30"};
    for (int f = 0; f < 3; ++f) {
        RenderSettings one = s;
        one.first_frame = f;
        one.frame_count = 1;
        one.params = Params(std::map<std::string, std::string>{{"gaze", gazes[f]}});
        const FrameResult fixed = render(&scene, "cfov", one).at(0);
        const Image& a = tracked[static_cast<std::size_t>(f)].find("final")->image;
        const Image& b = fixed.find("final")->image;
        INFO("frame ", f);
        CHECK(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0);
    }
    // A track and a fixed gaze together are refused.
    s.params.set("gaze", "1,1");
    CHECK(test::contains(test::error_message([&] { render(&scene, "cfov", s); }),
                         "'gaze' and 'gaze_track' both given"));
}
