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

// The state the probed frame's TAA read: the previous frame's output, age, depth and camera.
TaaState previous_state(const ProbeContext& c, const TaaProbeInputs& in) {
    TaaState previous;
    if (!c.previous_frame) return previous;
    previous.valid = true;
    previous.history = image_of(*c.previous_frame, in.output);
    previous.age = image_of(*c.previous_frame, "taa_age");
    previous.depth = image_of(*c.previous_frame, in.depth);
    previous.camera = c.previous_frame->camera.value_or(c.camera);
    return previous;
}

// How the history was found: the camera, the reprojection and its depth test.
void add_reprojection(ProbeSection& s, const TaaProbeInputs& in, const TaaState& previous,
                      const TaaPixelRecord& r) {
    if (!previous.valid) {
        s.add("history", "none: the first frame");
        return;
    }
    if (r.decision == TaaDecision::stationary) {
        s.add("camera",
              "stationary (the pose equals the previous frame's bit for bit): the "
              "history at the pixel itself, never rejected, nothing reprojected");
        return;
    }
    s.add("camera", "moved: reprojection by the current depth and the previous camera");
    s.add("reprojected",
          "p' = (" + probe_float(r.previous_point.x) + ", " + probe_float(r.previous_point.y) +
              "), view depth z' = " + probe_float(r.previous_depth) + " in the previous camera");
    if (!(r.previous_depth > 0.0f)) return;
    const float tau = in.settings.params.tau;
    add_taps(s, previous.history, previous.depth, r.previous_point);
    s.add("history depth", "z_h = " + probe_float(r.history_depth) + " (bilinear, on-screen taps)");
    const float diff = std::fabs(r.previous_depth - r.history_depth);
    s.add("depth test",
          "|z' - z_h| = " + probe_float(diff) + (diff <= tau * r.previous_depth ? " <= " : " > ") +
              "tau z' = " + probe_float(tau * r.previous_depth) +
              (in.settings.mode == TaaMode::depth ? ""
                                                  : " (not used: clamping instead of rejection)"));
}

// The clamp box of pixel (x, y): from the buffer's bounds, or the colour's 3x3 on the screen.
std::string clamp_box_text(const Image& color, const Image* bounds, const std::string& name, int px,
                           int py) {
    glm::vec3 lo, hi;
    if (bounds) {
        lo = {bounds->at(px, py, 0), bounds->at(px, py, 1), bounds->at(px, py, 2)};
        hi = {bounds->at(px, py, 3), bounds->at(px, py, 4), bounds->at(px, py, 5)};
    } else {
        lo = hi = rgb(color, px, py);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int x = std::min(std::max(px + dx, 0), color.width - 1);
                const int y = std::min(std::max(py + dy, 0), color.height - 1);
                lo = glm::min(lo, rgb(color, x, y));
                hi = glm::max(hi, rgb(color, x, y));
            }
    }
    return probe_vec3(lo) + " .. " + probe_vec3(hi) +
           (bounds ? " (3x3 in the buffer, " + name + ")" : " (3x3 on the screen)");
}

// The recomputed pixel against the rendered output and age.
void add_check(ProbeSection& s, const FrameResult& f, const TaaProbeInputs& in, const Image& out,
               const Image& age, int x, int y, ProbeReport& report) {
    const glm::vec3 mine = rgb(out, x, y);
    s.add("value", probe_vec3(mine) + " = history (1 - 1/age) + current / age");
    const glm::vec3 rendered = rgb(image_of(f, in.output), x, y);
    const bool same = std::memcmp(&mine, &rendered, sizeof mine) == 0 &&
                      age.at(x, y) == image_of(f, "taa_age").at(x, y);
    s.add("check", in.output + " and taa_age: " +
                       (same ? "bit-identical to the rendered buffers"
                             : "DIFFER from the rendered buffers " + probe_vec3(rendered)));
    if (!same) report.consistent = false;
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
    const TaaState previous = previous_state(c, in);
    const TaaInputs inputs{color, depth, c.camera, in.gaze, bounds};
    Image out(color.width, color.height, 3, 0.0f), age(color.width, color.height, 1, 0.0f);
    const TaaPixelRecord r = taa_pixel(params, inputs, previous, c.x, c.y, out, age);
    s.add("current", in.color + " " + probe_vec3(rgb(color, c.x, c.y)) + ", view depth " +
                         probe_float(depth.at(c.x, c.y)) + " (" + in.depth + ")");
    add_reprojection(s, in, previous, r);
    const bool clamp_mode =
        in.settings.mode == TaaMode::clamp_screen || in.settings.mode == TaaMode::clamp_buffer;
    if (previous.valid && r.decision != TaaDecision::first) {
        s.add("history", probe_vec3(r.history) +
                             (r.decision == TaaDecision::clamped ? " (after clamping)" : ""));
        if (clamp_mode && (r.decision == TaaDecision::kept || r.decision == TaaDecision::clamped))
            s.add("clamp box", clamp_box_text(color, bounds, in.bounds, c.x, c.y));
        s.add("age", "previous " + probe_float(r.age_previous) + " -> " + probe_float(r.age) +
                         " (cap " + std::to_string(params.age_cap) + ")");
    }
    if (r.history_nonfinite) s.add("note", "the history was not finite: rejected");
    s.add("decision", clamp_mode && r.decision == TaaDecision::kept
                          ? "kept (inside the clamp box)"
                          : taa_decision_name(r.decision));
    add_check(s, f, in, out, age, c.x, c.y, report);
    report.sections.push_back(s);
}

}  // namespace fovref
