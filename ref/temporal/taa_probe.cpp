#include "ref/temporal/taa_probe.h"

#include <cmath>
#include <cstring>

#include "ref/core/error.h"

namespace fovref {

TaaProbeInputs taa_probe_inputs(const FrameResult& frame, const TaaSettings& settings,
                                glm::vec2 gaze) {
    TaaProbeInputs in;
    in.settings = settings;
    in.color = frame.find("shaded") ? "shaded" : "resolved";
    in.depth = frame.find("taa_view_depth") ? "taa_view_depth" : "gbuffer_view_depth";
    in.bounds = frame.find("taa_bounds") ? "taa_bounds" : "";
    in.output = frame.find("taa_color") ? "taa_color" : "final";
    in.gaze = gaze;
    return in;
}

namespace {

const Image& image_of(const FrameResult& frame, const std::string& name) {
    const Buffer* b = frame.find(name);
    FOVREF_CHECK(b != nullptr, "probe: the frame has no TAA buffer " + name);
    return b->image;
}

glm::vec3 rgb(const Image& image, int x, int y) {
    return {image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)};
}

// The taps taa_sample reads at q, listed with their weights.
void add_taps(ProbeSection& s, const Image& history, const Image& depth, glm::vec2 q) {
    TaaTaps t;
    if (!taa_taps(history.width, history.height, q, t)) {
        s.add("  taps", "none: p' lies off the screen");
        return;
    }
    for (int k = 0; k < 4; ++k) {
        std::string text = "(" + std::to_string(t.x[k]) + ", " + std::to_string(t.y[k]) +
                           "), weight " + probe_float(t.w[k]);
        if (t.on_screen(k, history.width, history.height))
            text += ": history " + probe_vec3(rgb(history, t.x[k], t.y[k])) + ", depth " +
                    probe_float(depth.at(t.x[k], t.y[k]));
        else
            text += ": off screen, dropped";
        s.add("  tap " + std::to_string(k), text);
    }
}

}  // namespace

void explain_taa(const ProbeContext& c, const TaaProbeInputs& in, ProbeReport& report) {
    const FrameResult& f = *c.frame;
    const TaaParams& params = in.settings.params;
    ProbeSection s{"taa",
                   std::string("temporal anti-aliasing, ") + taa_mode_name(in.settings.mode) +
                       " (Lund §3.4, docs/temporal.md)",
                   {}};
    const Image& color = image_of(f, in.color);
    const Image& depth = image_of(f, in.depth);
    const Image* bounds = in.bounds.empty() ? nullptr : &image_of(f, in.bounds);
    TaaState previous;
    if (c.previous_frame) {
        previous.valid = true;
        previous.history = image_of(*c.previous_frame, in.output);
        previous.age = image_of(*c.previous_frame, "taa_age");
        previous.depth = image_of(*c.previous_frame, in.depth);
        previous.camera = c.previous_frame->camera.value_or(c.camera);
    }
    const TaaInputs inputs{color, depth, c.camera, in.gaze, bounds};
    Image out(color.width, color.height, 3, 0.0f), age(color.width, color.height, 1, 0.0f);
    const TaaPixelRecord r = taa_pixel(params, inputs, previous, c.x, c.y, out, age);
    const glm::vec3 current = rgb(color, c.x, c.y);
    s.add("current", in.color + " " + probe_vec3(current) + ", view depth " +
                         probe_float(depth.at(c.x, c.y)) + " (" + in.depth + ")");
    if (!previous.valid) {
        s.add("history", "none: the first frame");
    } else if (r.decision == TaaDecision::stationary) {
        s.add("camera",
              "stationary (the pose equals the previous frame's bit for bit): the "
              "history at the pixel itself, never rejected, nothing reprojected");
    } else {
        s.add("camera", "moved: reprojection by the current depth and the previous camera");
        s.add("reprojected", "p' = (" + probe_float(r.previous_point.x) + ", " +
                                 probe_float(r.previous_point.y) + "), view depth z' = " +
                                 probe_float(r.previous_depth) + " in the previous camera");
        if (r.previous_depth > 0.0f) {
            add_taps(s, previous.history, previous.depth, r.previous_point);
            s.add("history depth",
                  "z_h = " + probe_float(r.history_depth) + " (bilinear, on-screen taps)");
            const float diff = std::fabs(r.previous_depth - r.history_depth);
            s.add("depth test", "|z' - z_h| = " + probe_float(diff) +
                                    (diff <= params.tau * r.previous_depth ? " <= " : " > ") +
                                    "tau z' = " + probe_float(params.tau * r.previous_depth) +
                                    (in.settings.mode == TaaMode::depth
                                         ? ""
                                         : " (not used: clamping instead of rejection)"));
        }
    }
    const bool clamp_mode =
        in.settings.mode == TaaMode::clamp_screen || in.settings.mode == TaaMode::clamp_buffer;
    if (previous.valid && r.decision != TaaDecision::first) {
        s.add("history", probe_vec3(r.history) +
                             (r.decision == TaaDecision::clamped ? " (after clamping)" : ""));
        if (clamp_mode && (r.decision == TaaDecision::kept || r.decision == TaaDecision::clamped)) {
            glm::vec3 lo, hi;
            if (bounds) {
                lo = {bounds->at(c.x, c.y, 0), bounds->at(c.x, c.y, 1), bounds->at(c.x, c.y, 2)};
                hi = {bounds->at(c.x, c.y, 3), bounds->at(c.x, c.y, 4), bounds->at(c.x, c.y, 5)};
            } else {
                lo = hi = current;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int x = std::min(std::max(c.x + dx, 0), color.width - 1);
                        const int y = std::min(std::max(c.y + dy, 0), color.height - 1);
                        lo = glm::min(lo, rgb(color, x, y));
                        hi = glm::max(hi, rgb(color, x, y));
                    }
            }
            s.add("clamp box", probe_vec3(lo) + " .. " + probe_vec3(hi) +
                                   (bounds ? " (3x3 in the buffer, " + in.bounds + ")"
                                           : " (3x3 on the screen)"));
        }
        s.add("age", "previous " + probe_float(r.age_previous) + " -> " + probe_float(r.age) +
                         " (cap " + std::to_string(params.age_cap) + ")");
    }
    if (r.history_nonfinite) s.add("note", "the history was not finite: rejected");
    s.add("decision", clamp_mode && r.decision == TaaDecision::kept
                          ? "kept (inside the clamp box)"
                          : taa_decision_name(r.decision));
    const glm::vec3 mine = rgb(out, c.x, c.y);
    s.add("value", probe_vec3(mine) + " = history (1 - 1/age) + current / age");
    const glm::vec3 rendered = rgb(image_of(f, in.output), c.x, c.y);
    const bool same = std::memcmp(&mine, &rendered, sizeof mine) == 0 &&
                      age.at(c.x, c.y) == image_of(f, "taa_age").at(c.x, c.y);
    s.add("check", in.output + " and taa_age: " +
                       (same ? "bit-identical to the rendered buffers"
                             : "DIFFER from the rendered buffers " + probe_vec3(rendered)));
    if (!same) report.consistent = false;
    report.sections.push_back(s);
}

}  // namespace fovref
