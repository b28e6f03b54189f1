// Helpers shared by the tests that render whole modes (tests/visual_polar/modes_test.cpp,
// tests/temporal/taa_modes_test.cpp): procedural scenes built once, a render of every buffer of a
// sequence, a buffer looked up by name, bit-for-bit equality of images.
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"

namespace fovref::test {

/// The procedural scene `name`, built on first use.
inline const Scene& scene_named(const std::string& name) {
    static std::map<std::string, Scene> scenes;
    auto it = scenes.find(name);
    if (it == scenes.end()) it = scenes.emplace(name, make_procedural_scene(name)).first;
    return it->second;
}

/// Every buffer of frames first_frame .. first_frame + frames - 1 of `mode` on scene `scene`,
/// resumed from `state` (a dump of the frame before) when given.
inline std::vector<FrameResult> render_all(const std::string& scene, const std::string& mode,
                                           int width, int height, int frames,
                                           std::map<std::string, std::string> params,
                                           float time_step = 1.0f / 30, int first_frame = 0,
                                           std::vector<Buffer> state = {}) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.frame_count = frames;
    s.first_frame = first_frame;
    s.time_step = time_step;
    s.params = Params(std::move(params));
    s.requested = {"all"};
    s.state_buffers = std::move(state);
    return render(&scene_named(scene), mode, s);
}

/// The buffer `name` of a frame (the test fails when it is missing).
inline const Image& buffer(const FrameResult& f, const std::string& name) {
    const Buffer* b = f.find(name);
    REQUIRE_MESSAGE(b != nullptr, name);
    return b->image;
}

/// The counter `name` of a frame (the test fails when it is missing).
inline std::int64_t counter(const FrameResult& f, const std::string& name) {
    for (const auto& [key, value] : f.counters.values)
        if (key == name) return value;
    FAIL("no counter " << name);
    return 0;
}

/// The same shape and the same bits (memcmp: -0 differs from +0, NaNs by their payload).
inline bool same_bits(const Image& a, const Image& b) {
    return a.same_shape(b) &&
           std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

}  // namespace fovref::test
