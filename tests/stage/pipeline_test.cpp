#include <doctest/doctest.h>

#include <cmath>

#include "ref/building_blocks/building_blocks.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/image/image.h"
#include "ref/modes/modes.h"
#include "ref/scene/scene_file.h"

using namespace fovref;

namespace {

// A three-stage toy pipeline: a -> b, and an independent c. The stages share a state that counts
// their runs.
struct ToyState : StageState {
    int* runs = nullptr;
};

void make_a(FrameContext& ctx) {
    ++ctx.state<ToyState>().runs[0];
    ctx.result->add("a", BufferKind::scalar, {"v"}, Image(2, 2, 1, 1.0f));
}

void a_to_b(FrameContext& ctx) {
    ++ctx.state<ToyState>().runs[1];
    Image b = ctx.input("a");
    for (float& v : b.data) v *= 2.0f;
    ctx.result->add("b", BufferKind::scalar, {"v"}, b);
}

void make_c(FrameContext& ctx) {
    ++ctx.state<ToyState>().runs[2];
    ctx.note = "made c";
    ctx.result->add("c", BufferKind::scalar, {"v"}, Image(1, 1, 1, 3.0f));
}

Pipeline toy_pipeline(int* runs) {
    auto state = std::make_shared<ToyState>();
    state->runs = runs;
    Pipeline p;
    p.stages.push_back({"make_a", {}, {"a"}, make_a, state});
    p.stages.push_back({"a_to_b", {"a"}, {"b"}, a_to_b, state});
    p.stages.push_back({"make_c", {}, {"c"}, make_c, state});
    p.final_outputs = {"b"};
    return p;
}

}  // namespace

TEST_CASE("pipeline: only stages whose outputs are consumed run, the others are recorded") {
    int runs[3] = {0, 0, 0};
    Pipeline p = toy_pipeline(runs);
    FrameContext ctx;
    FrameResult r = p.run_frame(ctx, {});
    CHECK(runs[0] == 1);
    CHECK(runs[1] == 1);
    CHECK(runs[2] == 0);  // nobody asked for c
    REQUIRE(r.stages.size() == 3);
    CHECK(r.stages[2].name == "make_c");
    CHECK_FALSE(r.stages[2].ran);
    CHECK(r.stages[2].note.find("skipped") != std::string::npos);
    REQUIRE(r.find("b") != nullptr);
    CHECK(r.find("b")->image.data[0] == 2.0f);
    CHECK(r.find("c") == nullptr);

    FrameResult only_c = p.run_frame(ctx, {"c"});
    CHECK(runs[0] == 1);
    CHECK(runs[2] == 1);
    CHECK(only_c.stages[2].note == "made c");

    FrameResult all = p.run_frame(ctx, {"all"});
    CHECK(all.buffers.size() == 3);
    CHECK_THROWS_WITH_AS(p.run_frame(ctx, {"nope"}), doctest::Contains("'nope'"), Error);
}

// SPEC §0: a stage that receives NaN/Inf replaces it by 0, counts it and never propagates it.
// The pipeline does it where every stage reads its inputs (FrameContext::input): here make_a's
// output is corrupted after it ran (the after_stage hook), a_to_b reads zeros, and the frame
// counts the replaced values once however often the buffer is read.
TEST_CASE("pipeline: non-finite stage inputs are replaced by 0 and counted, once per frame") {
    int runs[3] = {0, 0, 0};
    Pipeline p = toy_pipeline(runs);
    RenderSettings settings;
    settings.after_stage = [](const std::string& stage, FrameResult& result) {
        if (stage != "make_a") return;
        for (Buffer& b : result.buffers)
            if (b.name == "a") {
                b.image.data[0] = std::nanf("");
                b.image.data[3] = -INFINITY;
            }
    };
    FrameContext ctx;
    ctx.settings = &settings;
    const FrameResult r = p.run_frame(ctx, {"all"});
    REQUIRE(r.find("b") != nullptr);
    const std::vector<float> b = r.find("b")->image.data;
    CHECK(b == std::vector<float>{0.0f, 2.0f, 2.0f, 0.0f});
    CHECK(r.counters.get("nonfinite_stage_inputs") == 2);
    // a clean frame has no such counter
    settings.after_stage = nullptr;
    CHECK(p.run_frame(ctx, {"all"}).counters.get("nonfinite_stage_inputs") == 0);
    bool listed = false;
    for (const auto& [name, value] : p.run_frame(ctx, {"all"}).counters.values)
        listed = listed || name == "nonfinite_stage_inputs";
    CHECK_FALSE(listed);
}

TEST_CASE("render: settings and parameters are validated with the setting's name") {
    RenderSettings s;
    s.width = 0;
    CHECK_THROWS_WITH_AS(render(nullptr, "rng", s), doctest::Contains("--width"), Error);
    s.width = 8;
    s.height = 100000;
    CHECK_THROWS_WITH_AS(render(nullptr, "rng", s), doctest::Contains("--height"), Error);
    s.height = 4;
    s.frame_count = 0;
    CHECK_THROWS_WITH_AS(render(nullptr, "rng", s), doctest::Contains("--frames"), Error);
    s.frame_count = 1;
    CHECK_THROWS_WITH_AS(render(nullptr, "no-such-mode", s), doctest::Contains("modes:"), Error);
    s.params.set("alpha", "2");
    CHECK_THROWS_WITH_AS(render(nullptr, "rng", s), doctest::Contains("'alpha'"), Error);
    s.params = Params();
    CHECK_THROWS_WITH_AS(render(nullptr, "splat", s), doctest::Contains("needs a scene"), Error);
    s.time_step = std::nanf("");
    CHECK_THROWS_AS(render(nullptr, "rng", s), Error);
}

TEST_CASE("params: typed getters reject malformed and out-of-range values by name") {
    const std::vector<ParamSpec> specs = {{"alpha", "1", "kernel exponent"},
                                          {"rings", "20", "ring count"},
                                          {"taa", "off", "temporal accumulation"}};
    Params p;
    CHECK(p.get_float(specs, "alpha", 1.0f, 8.0f) == 1.0f);
    p.set_from_assignment("alpha=3.5");
    CHECK(p.get_float(specs, "alpha", 1.0f, 8.0f) == 3.5f);
    p.set_from_assignment("alpha=3.5x");
    CHECK_THROWS_WITH_AS(p.get_float(specs, "alpha", 1, 8), doctest::Contains("'alpha'"), Error);
    p.set_from_assignment("alpha=nan");
    CHECK_THROWS_AS(p.get_float(specs, "alpha", 1, 8), Error);
    p.set_from_assignment("alpha=9");
    CHECK_THROWS_WITH_AS(p.get_float(specs, "alpha", 1, 8), doctest::Contains("outside"), Error);
    p.set_from_assignment("rings=7");
    CHECK(p.get_int(specs, "rings", 1, 100) == 7);
    p.set_from_assignment("rings=7.5");
    CHECK_THROWS_AS(p.get_int(specs, "rings", 1, 100), Error);
    CHECK_FALSE(p.get_bool(specs, "taa"));
    p.set_from_assignment("taa=maybe");
    CHECK_THROWS_AS(p.get_bool(specs, "taa"), Error);
    // a choice: the index of the value, any other value named with the choices
    CHECK(p.get_choice(specs, "rings", {"3", "7.5", "9"}) == 1);
    CHECK(p.get_choice(specs, "alpha", {"9"}) == 0);
    CHECK_THROWS_WITH_AS(p.get_choice(specs, "taa", {"off", "depth", "clamp"}),
                         "parameter 'taa': expected 'off', 'depth' or 'clamp', got 'maybe'", Error);
    CHECK_THROWS_WITH_AS(p.get_choice(specs, "taa", {"off", "on"}),
                         "parameter 'taa': expected 'off' or 'on', got 'maybe'", Error);
    CHECK_THROWS_AS(p.set_from_assignment("novalue"), Error);
    CHECK_THROWS_AS(p.set_from_assignment("=3"), Error);
    Params unknown;
    unknown.set("beta", "1");
    CHECK_THROWS_WITH_AS(unknown.check_known(specs, "kfov"), doctest::Contains("alpha, rings, taa"),
                         Error);
}

TEST_CASE("counters keep insertion order and accumulate") {
    Counters c;
    c.add("rays", 3);
    c.add("shadow", 1);
    c.add("rays", 4);
    CHECK(c.get("rays") == 7);
    CHECK(c.get("absent") == 0);
    REQUIRE(c.values.size() == 2);
    CHECK(c.values[0].first == "rays");
}

TEST_CASE("camera rays: the centre ray is F, rays are unit, and the screen is symmetric") {
    Camera camera = look_at({1, 2, 3}, {1, 2, -7}, {0, 1, 0}, 60.0f);
    // 3x3: pixel (1,1) has centre (1.5, 1.5), the screen centre.
    Image rays = camera_rays(camera, 3, 3);
    CHECK(rays.at(1, 1, 0) == 0.0f);
    CHECK(rays.at(1, 1, 1) == 0.0f);
    CHECK(rays.at(1, 1, 2) == -1.0f);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) {
            float len2 = rays.at(x, y, 0) * rays.at(x, y, 0) + rays.at(x, y, 1) * rays.at(x, y, 1) +
                         rays.at(x, y, 2) * rays.at(x, y, 2);
            CHECK(len2 == doctest::Approx(1.0f).epsilon(1e-6));  // normalised in float
        }
    // Left/right and top/bottom mirror exactly; screen y grows downwards (top row looks up).
    CHECK(rays.at(0, 1, 0) == -rays.at(2, 1, 0));
    CHECK(rays.at(1, 0, 1) == -rays.at(1, 2, 1));
    CHECK(rays.at(1, 0, 1) > 0.0f);
    // Top edge midpoint of a 2x2 screen: the ray tilts up by exactly vfov/2 = 30 degrees.
    glm::vec3 edge = primary_ray_direction(camera, tan_half_vfov(camera), 2, 2, 1.0f, 0.0f);
    CHECK(edge.y == doctest::Approx(0.5f).epsilon(1e-6));  // sin(30 deg)
}

TEST_CASE("rng image holds rand_unit(frame, y*W+x, d)") {
    Image image = rng_image(7, 5, 3);
    CHECK(image.at(4, 2, 1) == rand_unit(7, 14, 1));
    CHECK(image.at(0, 0, 0) == rand_unit(7, 0, 0));
    CHECK(image.at(3, 1, 2) != rng_image(8, 5, 3).at(3, 1, 2));
}

TEST_CASE("centroid splat: nearest wins, equal depth goes to the lowest primitive id") {
    Scene scene;
    scene.source = "test";
    scene.materials.push_back(Material{"red", {1, 0, 0}});
    scene.materials.push_back(Material{"blue", {0, 0, 1}});
    auto add_triangle = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, int material) {
        scene.positions.insert(scene.positions.end(), {a, b, c});
        glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
        scene.normals.insert(scene.normals.end(), {n, n, n});
        scene.uvs.insert(scene.uvs.end(), {glm::vec2(0), glm::vec2(0), glm::vec2(0)});
        scene.material_ids.push_back(material);
    };
    // Triangles 0 and 1 have the same centroid (0,0,-5) and depth; 2 is nearer at depth 3;
    // 3 is behind the camera; 4 is off screen to the right.
    // (Depth 3 < 5, but at another pixel.)
    add_triangle({-1, -1, -5}, {1, -1, -5}, {0, 2, -5}, 1);
    add_triangle({1, -1, -5}, {-1, -1, -5}, {0, 2, -5}, 0);
    add_triangle({2.6f, -1, -3}, {2.8f, -1, -3}, {2.7f, 2, -3}, 0);
    add_triangle({-1, -1, 5}, {1, -1, 5}, {0, 2, 5}, 0);
    add_triangle({99, -1, -5}, {101, -1, -5}, {100, 2, -5}, 0);
    finalize_scene(scene);
    Camera camera = look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90.0f);
    SplatBuffers s = centroid_splat(scene, camera, 4, 4);
    CHECK(s.splatted == 3);
    CHECK(s.behind == 1);
    CHECK(s.off_screen == 1);
    // Centroid (0,0,-5) projects to the screen centre (2, 2): pixel (2, 2).
    CHECK(s.primitive.at(2, 2) == 0.0f);
    CHECK(s.depth.at(2, 2) == 5.0f);
    CHECK(s.albedo.at(2, 2, 2) == 1.0f);  // material 1 (blue) of triangle 0
    CHECK(s.primitive.at(0, 0) == -1.0f);
    // Centroid (2.7, 0, -3): ndc x = 0.9 -> screen x 3.8, y 2 -> pixel (3, 2).
    CHECK(s.primitive.at(3, 2) == 2.0f);
    CHECK(s.depth.at(3, 2) == 3.0f);
    Image shaded = headlight_shade(s.albedo, s.normal, s.primitive, camera);
    CHECK(shaded.at(2, 2, 2) == 1.0f);  // facing the camera: 0.2 + 0.8 * 1
    CHECK(shaded.at(0, 0, 0) == 0.0f);

    // A later, nearer triangle on the same pixel wins over the earlier ones.
    add_triangle({-0.5f, -0.5f, -2.5f}, {0.5f, -0.5f, -2.5f}, {0, 1, -2.5f}, 0);
    SplatBuffers nearer = centroid_splat(scene, camera, 4, 4);
    CHECK(nearer.primitive.at(2, 2) == 5.0f);
    CHECK(nearer.depth.at(2, 2) == 2.5f);
}

TEST_CASE("pipeline validation: inputs must come from earlier stages, outputs are unique") {
    auto noop = [](FrameContext&) {};
    Pipeline reads_later;
    reads_later.stages.push_back({"b", {"a"}, {"b"}, noop});
    reads_later.stages.push_back({"a", {}, {"a"}, noop});
    CHECK_THROWS_WITH_AS(reads_later.validate("m"), doctest::Contains("reads 'a'"), Error);
    Pipeline twice;
    twice.stages.push_back({"a1", {}, {"a"}, noop});
    twice.stages.push_back({"a2", {}, {"a"}, noop});
    CHECK_THROWS_WITH_AS(twice.validate("m"), doctest::Contains("produced twice"), Error);
    Pipeline missing_final;
    missing_final.stages.push_back({"a", {}, {"a"}, noop});
    missing_final.final_outputs = {"z"};
    CHECK_THROWS_AS(missing_final.validate("m"), Error);
    // Every registered mode is well formed.
    for (const ModeInfo& mode : render_modes()) {
        Scene empty;
        CHECK_NOTHROW(mode.build(&empty, RenderSettings{}).validate(mode.name));
    }
}

TEST_CASE("render reports progress through stages and frames, ending at 1") {
    RenderSettings s;
    s.width = 4;
    s.height = 2;
    s.frame_count = 3;
    std::vector<double> reports;
    s.progress = [&reports](double f) { reports.push_back(f); };
    render(nullptr, "halton", s);
    REQUIRE(reports.size() >= 3);
    for (std::size_t k = 1; k < reports.size(); ++k) CHECK(reports[k] >= reports[k - 1]);
    CHECK(reports.back() == 1.0);
}

// Skipping stages nobody consumed (SPEC: no stage whose output nobody asked for) changes no bit:
// every mode, rendered for its final outputs only and with every buffer requested, gives the
// same final buffers over three frames (modes with state carry it through the skipped stages'
// absence), and the final-only render does skip stages where the mode has any to skip.
TEST_CASE("pipeline: skipping unconsumed stages leaves the final buffers bit-identical") {
    const Scene scene = load_scene("cornell");
    int modes_with_skips = 0;
    for (const ModeInfo& mode : render_modes()) {
        RenderSettings s;
        s.width = 24;
        s.height = 14;
        s.frame_count = 3;
        const Scene* scene_or_null = mode.needs_scene ? &scene : nullptr;
        const std::vector<FrameResult> final_only = render(scene_or_null, mode.name, s);
        s.requested = {"all"};
        const std::vector<FrameResult> everything = render(scene_or_null, mode.name, s);
        REQUIRE(final_only.size() == everything.size());
        bool skipped = false;
        for (std::size_t f = 0; f < final_only.size(); ++f) {
            for (const StageRun& run : final_only[f].stages) skipped = skipped || !run.ran;
            for (const Buffer& b : final_only[f].buffers) {
                const Buffer* same = everything[f].find(b.name);
                INFO("mode " << mode.name << ", frame " << f << ", buffer " << b.name);
                REQUIRE(same != nullptr);
                CHECK(canonical_sha256(same->image) == canonical_sha256(b.image));
            }
        }
        modes_with_skips += skipped ? 1 : 0;
    }
    CHECK(modes_with_skips >= 5);
}

namespace {

// A stage that reads its port "in" and writes its port "out": the wiring decides which buffers.
void double_in_to_out(FrameContext& ctx) {
    Image out = ctx.input("in");
    for (float& v : out.data) v *= 2.0f;
    ctx.output("out", BufferKind::scalar, {"v"}, std::move(out));
}

void read_undeclared(FrameContext& ctx) { (void)ctx.input("a"); }

void write_undeclared(FrameContext& ctx) {
    ctx.output("elsewhere", BufferKind::scalar, {"v"}, Image(1, 1, 1, 0.0f));
}

}  // namespace

// Stages declare their ports (slot -> buffer) and the framework hands over the buffers the wiring
// binds: the same stage function serves two wirings, and a stage that reads or writes a slot it
// did not declare fails with its name.
TEST_CASE("pipeline: ports bind a stage's slots to the buffers the wiring names") {
    int runs[3] = {0, 0, 0};
    Pipeline p = toy_pipeline(runs);
    p.stages.push_back({"a_twice", {{"in", "a"}}, {{"out", "a4"}}, double_in_to_out});
    p.stages.push_back({"b_twice", {{"in", "b"}}, {{"out", "b4"}}, double_in_to_out});
    p.validate("toy");
    FrameContext ctx;
    const FrameResult r = p.run_frame(ctx, {"a4", "b4"});
    REQUIRE(r.find("a4") != nullptr);
    REQUIRE(r.find("b4") != nullptr);
    CHECK(r.find("a4")->image.data[0] == 2.0f);  // a = 1
    CHECK(r.find("b4")->image.data[0] == 4.0f);  // b = 2 a
    CHECK(r.find("a4")->stage == "a_twice");

    Pipeline reads;
    reads.stages.push_back({"make_a", {}, {"a"}, make_a, std::make_shared<ToyState>()});
    reads.stages.push_back({"sneaky", {}, {"x"}, read_undeclared});
    int more[3] = {0, 0, 0};
    static_cast<ToyState&>(*reads.stages.front().state).runs = more;
    CHECK_THROWS_WITH_AS(reads.run_frame(ctx, {"all"}),
                         doctest::Contains("stage 'sneaky' reads 'a', which it does not declare"),
                         Error);
    Pipeline writes;
    writes.stages.push_back({"stray", {}, {"x"}, write_undeclared});
    CHECK_THROWS_WITH_AS(writes.run_frame(ctx, {"all"}),
                         doctest::Contains("writes 'elsewhere', which it does not declare"), Error);
}

namespace {

// A stage with a cheap output and a costly one it computes only when wanted.
void cheap_and_costly(FrameContext& ctx) {
    ctx.output("cheap", BufferKind::scalar, {"v"}, Image(1, 1, 1, 1.0f));
    if (ctx.wants("costly")) ctx.output("costly", BufferKind::scalar, {"v"}, Image(1, 1, 1, 2.0f));
}

void forgets_out(FrameContext& ctx) { (void)ctx; }

}  // namespace

// A stage may leave out an output nobody wants (FrameContext::wants); one that is wanted must
// still be produced.
TEST_CASE("pipeline: a stage leaves out the outputs nobody wants, and only those") {
    Pipeline p;
    p.stages.push_back({"both", {}, {"cheap", "costly"}, cheap_and_costly});
    p.stages.push_back({"reader", {{"in", "cheap"}}, {"out"}, double_in_to_out});
    p.final_outputs = {"out"};
    FrameContext ctx;
    CHECK(ctx.all_wanted);
    const FrameResult plain = p.run_frame(ctx, {});
    CHECK(plain.find("out") != nullptr);
    CHECK(plain.find("costly") == nullptr);
    CHECK(p.wanted_buffers({}) == std::vector<std::string>{"out", "cheap"});
    CHECK(p.run_frame(ctx, {"costly"}).find("costly") != nullptr);
    CHECK(p.run_frame(ctx, {"all"}).find("costly") != nullptr);
    CHECK(p.wanted_buffers({"all", "out"}) == std::vector<std::string>{"all"});
    CHECK(ctx.all_wanted);  // reset after the frame

    Pipeline forgetful;
    forgetful.stages.push_back({"forgets", {}, {"out"}, forgets_out});
    forgetful.final_outputs = {"out"};
    CHECK_THROWS_WITH_AS(forgetful.run_frame(ctx, {}),
                         doctest::Contains("'forgets' did not produce 'out'"), Error);

    // In the modes: pass 2's decision buffers are left out of a plain render and there when asked
    const Scene scene = load_scene("cornell");
    RenderSettings s;
    s.width = 32;
    s.height = 18;
    for (const char* mode : {"kfr", "stereo-lp", "visual-polar-basic"}) {
        INFO(mode);
        s.requested = {};
        const FrameResult final_only = render(&scene, mode, s).at(0);
        CHECK(final_only.find("resolve_tap") == nullptr);
        s.requested = {"final", "resolve_tap_margin"};
        const FrameResult asked = render(&scene, mode, s).at(0);
        CHECK(asked.find("resolve_tap") != nullptr);
        CHECK(asked.find("resolve_tap_margin") != nullptr);
    }
    // TAA's age (a copy of the state's) likewise, the output the same bits either way
    s.frame_count = 2;
    s.params.set("taa", "depth");
    for (const char* mode : {"cfov", "stereo-lp"}) {
        CAPTURE(mode);
        s.requested = {};
        const std::vector<FrameResult> plain_taa = render(&scene, mode, s);
        s.requested = {"final", "taa_age"};
        const std::vector<FrameResult> with_age = render(&scene, mode, s);
        for (int k = 0; k < 2; ++k) {
            CAPTURE(k);
            CHECK(plain_taa.at(k).find("taa_age") == nullptr);
            REQUIRE(with_age.at(k).find("taa_age") != nullptr);
            if (k == 0) CHECK(with_age.at(k).find("taa_age")->image == Image(32, 18, 1, 1.0f));
            CHECK(bit_equal(plain_taa.at(k).find("final")->image,
                            with_age.at(k).find("final")->image));
        }
    }
}

namespace {

// A 1000-value buffer (the scan's AVX2 steps of 32 values in four chains, then its SSE2 and
// scalar tail) and a stage that reads it.
void make_long(FrameContext& ctx) {
    ctx.result->add("long", BufferKind::scalar, {"v"}, Image(250, 4, 1, 1.5f));
}
void read_long(FrameContext& ctx) {
    ctx.result->add("read", BufferKind::scalar, {"v"}, ctx.input("long"));
}

}  // namespace

// The scan for non-finite inputs finds one wherever it lies: in each of the AVX2 path's four
// chains, at the end of its last step, in the tail after it, and not in a clean buffer.
TEST_CASE("pipeline: a non-finite input is found at every position of a long buffer") {
    Pipeline p;
    p.stages.push_back({"make_long", {}, {"long"}, make_long});
    p.stages.push_back({"read_long", {"long"}, {"read"}, read_long});
    RenderSettings settings;
    FrameContext ctx;
    ctx.settings = &settings;
    for (const std::size_t at : {0, 7, 8, 15, 16, 24, 31, 32, 500, 991, 992, 995, 996, 999}) {
        for (const float bad : {std::nanf(""), INFINITY, -INFINITY}) {
            CAPTURE(at);
            CAPTURE(bad);
            settings.after_stage = [at, bad](const std::string& stage, FrameResult& result) {
                if (stage == "make_long") result.buffers.at(0).image.data.at(at) = bad;
            };
            const FrameResult r = p.run_frame(ctx, {"read"});
            CHECK(r.counters.get("nonfinite_stage_inputs") == 1);
            CHECK(r.find("read")->image.data.at(at) == 0.0f);
        }
    }
    settings.after_stage = nullptr;
    CHECK(p.run_frame(ctx, {"read"}).counters.get("nonfinite_stage_inputs") == 0);
}

namespace {

// A stage that writes every value of its output into recycled storage: it records what the
// storage held and where it lies, then writes frame + 1 everywhere.
struct RecycleState : StageState {
    int width = 3;
    std::vector<float> seen;       ///< the storage's values before the stage wrote
    const float* where = nullptr;  ///< the storage's address
};

void fill_recycled(FrameContext& ctx) {
    RecycleState& state = ctx.state<RecycleState>();
    Image image = ctx.recycled("out", state.width, 2, 1);
    state.seen = image.data;
    state.where = image.data.data();
    for (float& v : image.data) v = static_cast<float>(ctx.frame + 1);
    ctx.output("out", BufferKind::scalar, {"v"}, std::move(image));
}

void recycles_undeclared(FrameContext& ctx) { (void)ctx.recycled("elsewhere", 1, 1, 1); }

}  // namespace

// FrameContext::recycled hands a stage the storage of its output's buffer from an earlier frame,
// only when the frame's caller left it (hand_back), of the same shape; else zeros.
TEST_CASE("pipeline: an output's storage is recycled from what the caller handed back") {
    auto state = std::make_shared<RecycleState>();
    Pipeline p;
    p.stages.push_back({"fill", {}, {{"out", "filled"}}, fill_recycled, state});
    p.final_outputs = {"filled"};
    FrameContext ctx;
    const auto run = [&](int frame) {
        ctx.frame = frame;
        return p.run_frame(ctx, {});
    };
    FrameResult r0 = run(0);
    CHECK(state->seen == std::vector<float>(6, 0.0f));  // nothing handed back yet: zeros
    CHECK(ctx.recyclable == std::vector<std::string>{"filled"});
    const float* first = state->where;
    ctx.hand_back(r0);
    FrameResult r1 = run(1);
    CHECK(state->seen == std::vector<float>(6, 1.0f));  // frame 0's storage and values
    CHECK(state->where == first);
    CHECK(r1.find("filled")->image.data == std::vector<float>(6, 2.0f));
    // what the caller moved away is not handed back
    const Image kept = std::move(r1.buffers.at(0).image);
    ctx.hand_back(r1);
    CHECK(ctx.spare.empty());
    FrameResult r2 = run(2);
    CHECK(state->seen == std::vector<float>(6, 0.0f));
    // storage of another shape is not used
    ctx.hand_back(r2);
    state->width = 4;
    run(3);
    CHECK(state->seen == std::vector<float>(8, 0.0f));
    // a buffer recycled() never asked for is not kept
    ctx.recyclable.clear();
    FrameResult r4 = run(4);
    ctx.recyclable.clear();
    ctx.hand_back(r4);
    CHECK(ctx.spare.empty());

    Pipeline stray;
    stray.stages.push_back({"stray", {}, {"x"}, recycles_undeclared});
    CHECK_THROWS_WITH_AS(stray.run_frame(ctx, {"all"}),
                         doctest::Contains("storage asked for 'elsewhere'"), Error);
}

// render_each hands each frame back once its callback returned, and the stages write into what
// came back; a callback that takes every buffer away but the one TAA carries (`final`) leaves
// nothing to recycle, so that render runs on fresh storage. Both give the same bits: TAA with
// clamp-buffer, whose taa_source recycles its depth and its bounds, pass 2 its output (every
// value written).
TEST_CASE("render_each recycles the outputs its callback leaves, the frames' bits are unchanged") {
    const Scene scene = load_scene("checker-room");
    RenderSettings s;
    s.width = 96;
    s.height = 54;
    s.frame_count = 4;
    s.requested = {"all"};
    s.params.set("taa", "clamp-buffer");
    std::vector<FrameResult> kept;  // on fresh storage
    render_each(&scene, find_mode("cfov"), s, [&](FrameResult& f) {
        kept.push_back(f);
        std::erase_if(f.buffers, [](const Buffer& b) { return b.name != "final"; });
    });
    int frames = 0;
    const float* bounds = nullptr;  // where frame f - 1's taa_bounds lay
    render_each(&scene, find_mode("cfov"), s, [&](FrameResult& f) {
        REQUIRE(f.find("taa_bounds") != nullptr);
        const float* here = f.find("taa_bounds")->image.data.data();
        if (f.frame > 0) CHECK(here == bounds);  // frame f - 1's storage, handed back
        bounds = here;
        INFO("frame " << f.frame);
        REQUIRE(f.buffers.size() == kept.at(static_cast<std::size_t>(f.frame)).buffers.size());
        for (const Buffer& b : f.buffers) {
            INFO(b.name);
            CHECK(
                bit_equal(b.image, kept.at(static_cast<std::size_t>(f.frame)).find(b.name)->image));
        }
        ++frames;
    });
    CHECK(frames == 4);
}

// BMFR's stages take their history (phase I's accumulation and counts, phase III's output, its
// TAA's output) back from the previous frame's buffers (FrameContext::carried) instead of
// keeping copies, and write their other outputs into recycled storage: a render whose callback
// leaves every buffer gives the bits of one whose callback takes all but the carried ones away
// (fresh storage for the others), on the screen and in Visual-Polar space; a callback that moves
// a carried buffer away stops the next frame with a clear error. (That the carried history gives
// the bits of the copies kept before is the goldens' check: they were made with the copies.)
TEST_CASE("BMFR's history comes back from the frame's own buffers, the bits unchanged") {
    const Scene scene = load_scene("cornell");
    for (const char* mode : {"pathtrace", "visual-polar"}) {
        CAPTURE(mode);
        RenderSettings s;
        s.width = 64;
        s.height = 36;
        s.frame_count = 3;
        s.params.set("denoise", "bmfr");
        s.requested = {"final"};
        const std::vector<std::string> carried = {"bmfr_accumulated_noisy", "bmfr_spp",
                                                  "bmfr_accumulated_filtered", "bmfr_taa"};
        std::vector<FrameResult> kept;  // the others on fresh storage
        render_each(&scene, find_mode(mode), s, [&](FrameResult& f) {
            kept.push_back(f);
            std::erase_if(f.buffers, [&](const Buffer& b) {
                return std::find(carried.begin(), carried.end(), b.name) == carried.end();
            });
        });
        int frames = 0;
        render_each(&scene, find_mode(mode), s, [&](FrameResult& f) {
            INFO("frame " << f.frame);
            CHECK(bit_equal(f.find("final")->image,
                            kept.at(static_cast<std::size_t>(f.frame)).find("final")->image));
            ++frames;
        });
        CHECK(frames == 3);
        for (const char* taken : {"bmfr_spp", "bmfr_accumulated_filtered", "bmfr_taa"}) {
            CAPTURE(taken);
            const std::string message = "BMFR's history, the previous frame's buffer '" +
                                        std::string(taken) + "', was not handed back";
            CHECK_THROWS_WITH_AS(render_each(&scene, find_mode(mode), s,
                                             [&](FrameResult& f) {
                                                 for (Buffer& b : f.buffers)
                                                     if (b.name == taken)
                                                         Image gone = std::move(b.image);
                                             }),
                                 doctest::Contains(message.c_str()), Error);
        }
    }
}
