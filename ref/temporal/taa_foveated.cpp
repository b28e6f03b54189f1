#include "ref/temporal/taa_foveated.h"

#include <algorithm>

#include "ref/core/error.h"
#include "ref/foveation/foveated_trace.h"

namespace fovref {

TaaSource taa_source(const TaaBufferInputs& in, int x, int y) {
    TaaSource s;
    const LogPolarMap& map = in.map;
    const glm::vec2 centre{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
    if (in.gaze_valid && inside_gaze_circle(map, centre)) {
        const ScreenWindow window = gaze_window(map);
        s.kind = TaaSource::Kind::gaze;
        s.i = x - window.x0;
        s.j = y - window.y0;
        return s;
    }
    const glm::vec2 uv =
        in.forward.uv[static_cast<std::size_t>(y) * static_cast<std::size_t>(map.screen_width) +
                      static_cast<std::size_t>(x)];
    const BilinearLookup l = lp_bilinear_taps(in.lp_valid, uv);
    const float weights[4] = {(1.0f - l.fu) * (1.0f - l.fv), l.fu * (1.0f - l.fv),
                              (1.0f - l.fu) * l.fv, l.fu * l.fv};
    const int is[4] = {l.i0, l.i1, l.i0, l.i1}, js[4] = {l.j0, l.j0, l.j1, l.j1};
    float best = 0.0f;
    for (int k = 0; k < 4; ++k)
        if (l.traced[k] && weights[k] > best) {
            best = weights[k];
            s.kind = TaaSource::Kind::buffer;
            s.i = is[k];
            s.j = js[k];
        }
    return s;
}

namespace {

void check_inputs(const TaaBufferInputs& in) {
    FOVREF_CHECK(in.forward.map == in.map, "a forward table made for another map");
    FOVREF_CHECK(in.lp_valid.width == in.map.width && in.lp_valid.height == in.map.height,
                 "validity mask of another size than the buffer");
}

}  // namespace

Image taa_screen_depth(const TaaBufferInputs& in, const Image& lp_depth, const Image* gaze_depth) {
    check_inputs(in);
    FOVREF_CHECK(in.gaze_valid == nullptr || gaze_depth != nullptr, "gaze depth missing");
    Image out(in.map.screen_width, in.map.screen_height, 1, 0.0f);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const TaaSource s = taa_source(in, x, y);
            if (s.kind == TaaSource::Kind::gaze)
                out.at(x, y) = gaze_depth->at(s.i, s.j);
            else if (s.kind == TaaSource::Kind::buffer)
                out.at(x, y) = lp_depth.at(s.i, s.j);
        }
    return out;
}

Image taa_buffer_bounds(const TaaBufferInputs& in, const Image& lp_color, const Image* gaze_color,
                        const Image& screen_color) {
    check_inputs(in);
    FOVREF_CHECK(in.gaze_valid == nullptr || gaze_color != nullptr, "gaze colour missing");
    Image out(in.map.screen_width, in.map.screen_height, 6, 0.0f);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const TaaSource s = taa_source(in, x, y);
            float lo[3], hi[3];
            for (int c = 0; c < 3; ++c) lo[c] = hi[c] = screen_color.at(x, y, c);
            if (s.kind != TaaSource::Kind::none) {
                const bool gaze = s.kind == TaaSource::Kind::gaze;
                const Image& image = gaze ? *gaze_color : lp_color;
                const Image& valid = gaze ? *in.gaze_valid : in.lp_valid;
                for (int c = 0; c < 3; ++c) lo[c] = hi[c] = image.at(s.i, s.j, c);
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int i = std::clamp(s.i + di, 0, image.width - 1);
                        int j = s.j + dj;
                        if (gaze)
                            j = std::clamp(j, 0, image.height - 1);
                        else
                            j = (j + image.height) % image.height;  // the angle axis wraps
                        if (valid.at(i, j) == 0.0f) continue;
                        for (int c = 0; c < 3; ++c) {
                            lo[c] = std::min(lo[c], image.at(i, j, c));
                            hi[c] = std::max(hi[c], image.at(i, j, c));
                        }
                    }
            }
            for (int c = 0; c < 3; ++c) {
                out.at(x, y, c) = lo[c];
                out.at(x, y, 3 + c) = hi[c];
            }
        }
    return out;
}

}  // namespace fovref
