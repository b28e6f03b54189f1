#include "tools/cli/commands/stress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ref/bmfr/bmfr.h"
#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/image/image.h"
#include "ref/image/image_io.h"
#include "ref/log_polar/map.h"
#include "ref/metrics/flip.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/ssim.h"
#include "ref/modes/modes.h"
#include "ref/scene/camera.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/common/number_text.h"

namespace fovref {

namespace {

using json = nlohmann::json;
constexpr double none = std::numeric_limits<double>::quiet_NaN();

/// One row of the report.
struct Row {
    std::string group, name;
    bool finite = true, deterministic = true;
    double error = none;  ///< the measured error (NaN: not measured)
    double bound = none;  ///< the stated bound (NaN: none, the row reports the degradation)
    std::string unit{}, note{};
    bool expect_refused = false, refused = false;
    bool may_refuse = false;          ///< a clear refusal is as good as a finite result
    bool determinism_checked = true;  ///< false: the case computes once ("-" in the report)
    std::int64_t violations = 0;      ///< decisions unlike binary64, misses on a shared edge

    bool pass() const {
        if (expect_refused) return refused;
        if (refused) return may_refuse;
        if (!finite || !deterministic || violations > 0) return false;
        return std::isnan(bound) || (std::isfinite(error) && error <= bound);
    }
    std::string status() const {
        if (pass()) return std::isnan(bound) || expect_refused ? "ok" : "ok (within bound)";
        if (expect_refused) return "FAIL: not refused";
        if (refused) return "FAIL: refused";
        if (!finite) return "FAIL: not finite";
        if (!deterministic) return "FAIL: not deterministic";
        if (violations > 0) return "FAIL: unlike binary64";
        return "FAIL: beyond bound";
    }
};

bool all_finite(const Image& image) {
    return std::all_of(image.data.begin(), image.data.end(),
                       [](float v) { return std::isfinite(v); });
}

/// Renders frame 0 of `mode` twice; the buffers of the first, and whether both gave the same bits.
FrameResult render_twice(const Scene& scene, const std::string& mode, int w, int h,
                         const std::vector<std::pair<std::string, std::string>>& params,
                         const std::vector<std::string>& requested, bool& deterministic) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.requested = requested;
    for (const auto& [k, v] : params) s.params.set(k, v);
    FrameResult a = render(&scene, mode, s).front();
    const FrameResult b = render(&scene, mode, s).front();
    deterministic = a.buffers.size() == b.buffers.size();
    for (std::size_t i = 0; deterministic && i < a.buffers.size(); ++i)
        deterministic =
            canonical_sha256(a.buffers[i].image) == canonical_sha256(b.buffers[i].image);
    return a;
}

bool frame_finite(const FrameResult& f) {
    return std::all_of(f.buffers.begin(), f.buffers.end(),
                       [](const Buffer& b) { return all_finite(b.image); });
}

const Image& buffer(const FrameResult& f, const std::string& name) {
    const Buffer* b = f.find(name);
    if (!b) throw Error("stress: the render has no buffer '" + name + "'");
    return b->image;
}

std::string number(double v) { return number_text(v, "%g"); }

// ---- Cases --------------------------------------------------------------------------------

/// Camera rays for a vertical field of view from 0.5 to 170 degrees: the largest angle between
/// primary_ray_direction and the same formula in binary64 (double vectors, the same tan(vfov/2):
/// the check is of the formula's binary32 evaluation; dm::tan itself is measured in
/// tests/core/dmath_test.cpp). No libm here: the fovref binary imports none (core.no_libm_in_cli).
void camera_rays(std::vector<Row>& rows, bool) {
    for (const double vfov : {0.5, 1.0, 10.0, 60.0, 120.0, 170.0}) {
        const Camera camera = look_at({0.3f, 0.2f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f},
                                      static_cast<float>(vfov));
        const int w = 160, h = 90;
        const float t = tan_half_vfov(camera);
        const double td = t;
        Row r{"camera rays", "vfov " + number(vfov) + " deg, 160x90"};
        r.unit = "rad";
        r.bound = 1e-6;
        r.error = 0.0;
        for (int y = 0; y <= h; y += 9)
            for (int x = 0; x <= w; x += 16) {
                const glm::vec3 d = primary_ray_direction(camera, t, w, h, static_cast<float>(x),
                                                          static_cast<float>(y));
                const double a = (2.0 * x / w - 1.0) * td * w / h, b = (2.0 * y / h - 1.0) * td;
                double e[3];
                for (int k = 0; k < 3; ++k)
                    e[k] = camera.forward[k] + a * camera.right[k] - b * camera.up[k];
                const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                // the angle between d and e from |d x e| / (|d| |e|) (no cancellation)
                const double dd[3] = {d.x, d.y, d.z};
                const double c[3] = {dd[1] * e[2] - dd[2] * e[1], dd[2] * e[0] - dd[0] * e[2],
                                     dd[0] * e[1] - dd[1] * e[0]};
                const double dn = std::sqrt(dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2]);
                const double angle = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / (dn * n);
                r.finite =
                    r.finite && std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
                r.error = std::max(r.error, angle);
            }
        rows.push_back(r);
    }
}

/// The log-polar map on screens from 11x11 to 16384x16384 and for gazes on the edges, at the
/// corners and 10 000 px off screen: the largest distance between p and
/// lp_inverse(lp_forward(p)) over a grid of screen points within R of the gaze (binary64
/// distance; the exact round trip is p itself).
void log_polar_round_trip(std::vector<Row>& rows, bool fast) {
    struct Setting {
        int w, h;
        float gx, gy;
        std::string what;
    };
    std::vector<Setting> settings = {{1, 1, 0.5f, 0.5f, "1x1, centre"},
                                     {11, 11, 5.5f, 5.5f, "11x11, centre"},
                                     {1280, 720, 640, 360, "1280x720, centre"},
                                     {1280, 720, 0, 0, "1280x720, gaze at a corner"},
                                     {1280, 720, 1280, 360, "1280x720, gaze on the right edge"},
                                     {1280, 720, 640, 720, "1280x720, gaze on the bottom edge"},
                                     {1280, 720, -10000, 360, "1280x720, gaze 10 000 px off"},
                                     {3840, 2160, 1920, 1080, "3840x2160, centre"}};
    if (!fast) settings.push_back({16384, 16384, 8192, 8192, "16384x16384, centre (map only)"});
    for (const Setting& s : settings) {
        for (const float alpha : {1.0f, 4.0f}) {
            LogPolarParams p;
            p.sigma = 1.0f;
            p.lp_aspect = 0.0f;
            p.kernel = power_kernel(alpha);
            Row r{"log-polar round trip", s.what + ", alpha " + number(alpha)};
            r.unit = "px";
            r.error = 0.0;
            try {
                const LogPolarMap map = make_log_polar_map(p, s.w, s.h, {s.gx, s.gy}, 1000.0f);
                // Bound: a few binary32 ulps of the radius, log and exp (which amplify the ulp of
                // ln(1 + r) by about R): 4e-6 of R plus 1e-3 px.
                r.bound = 4e-6 * map.radius_max + 1e-3;
                const int steps = 64;
                for (int iy = 0; iy <= steps; ++iy)
                    for (int ix = 0; ix <= steps; ++ix) {
                        const glm::vec2 q{static_cast<float>(s.w * ix) / steps,
                                          static_cast<float>(s.h * iy) / steps};
                        if (gaze_distance(map.gaze, q) > map.radius_max) continue;
                        const glm::vec2 back = lp_inverse(map, lp_forward(map, q));
                        if (!std::isfinite(back.x) || !std::isfinite(back.y)) r.finite = false;
                        const double dx = static_cast<double>(back.x) - q.x,
                                     dy = static_cast<double>(back.y) - q.y;
                        r.error = std::max(r.error, std::sqrt(dx * dx + dy * dy));
                    }
                r.note = "R = " + number(map.radius_max) + " px";
            } catch (const Error& e) {
                r.refused = true;
                r.note = e.what();
            }
            rows.push_back(r);
        }
    }
}

/// The foveated parameters at the ends of their ranges render finite, deterministic images;
/// beyond them they are refused with a message naming the parameter.
void parameter_limits(std::vector<Row>& rows, bool fast) {
    const Scene scene = load_scene("cornell");
    struct Setting {
        std::string mode, key, value;
        bool refused;
    };
    std::vector<Setting> settings = {
        {"fov", "sigma", "0.01", false},      {"fov", "sigma", "1024", false},
        {"fov", "sigma", "0", true},          {"fov", "sigma", "2000", true},
        {"fov", "alpha", "1", false},         {"fov", "alpha", "64", false},
        {"fov", "alpha", "0.5", true},        {"fov", "alpha", "65", true},
        {"fov", "lp_aspect", "0", false},     {"fov", "lp_aspect", "1000", false},
        {"fov", "lp_aspect", "-1", true},     {"fov", "lp_aspect", "nan", true},
        {"cfov", "gaze_angle", "1.5", false}, {"cfov", "gaze_angle", "0.0001", false},
        {"cfov", "gaze_angle", "1.6", true},  {"fov", "gaze", "-10000,18", false},
        {"fov", "gaze", "64,36", false},      {"fov", "gaze", "0,0", false}};
    if (fast)  // sigma = 0.01 makes a 6400 x 3600 buffer: full suite only
        settings = {settings[1], settings[2],  settings[3],  settings[5],
                    settings[6], settings[11], settings[14], settings[15]};
    for (const Setting& s : settings) {
        Row r{"parameter limits", s.mode + " " + s.key + "=" + s.value};
        r.expect_refused = s.refused;
        try {
            bool same = true;
            // every buffer, pass 2's decisions too (a plain render leaves them out)
            const FrameResult f =
                render_twice(scene, s.mode, 64, 36, {{s.key, s.value}}, {"all"}, same);
            r.deterministic = same;
            r.finite = frame_finite(f);
        } catch (const Error& e) {
            r.refused = true;
            r.note = e.what();
            if (r.note.size() > 90) r.note = r.note.substr(0, 87) + "...";
        }
        rows.push_back(r);
    }
}

/// The cornell box scaled by s and moved by d: the G-buffer's primitive ids against the unscaled
/// scene's (share of pixels that differ) and the view depth / s against the unscaled depth
/// (largest relative difference). No bound: the report shows where precision degrades.
Scene transformed(const Scene& base, float s, float d) {
    Scene scene = base;
    const glm::vec3 shift{d, d * 0.5f, -d * 0.25f};
    for (glm::vec3& p : scene.positions) p = p * s + shift;
    for (Light& l : scene.lights) {
        l.position = l.position * s + shift;
        l.edge_u *= s;
        l.edge_v *= s;
    }
    scene.camera.position = scene.camera.position * s + shift;
    for (CameraKey& k : scene.camera_path) k.position = k.position * s + shift;
    scene.scene_scale *= s;
    return scene;
}

void scene_scale(std::vector<Row>& rows, bool fast) {
    const Scene base = load_scene("cornell");
    const int w = 96, h = 54;
    bool same = true;
    const std::vector<std::string> wanted = {"gbuffer_primitive_id", "gbuffer_view_depth"};
    const FrameResult ref = render_twice(base, "basic", w, h, {}, wanted, same);
    const Image& ids0 = buffer(ref, "gbuffer_primitive_id");
    const Image& depth0 = buffer(ref, "gbuffer_view_depth");
    struct Setting {
        float s, d;
        std::string what;
    };
    std::vector<Setting> settings = {{1e-4f, 0, "scale 1e-4"}, {1e-2f, 0, "scale 1e-2"},
                                     {1e3f, 0, "scale 1e3"},   {1e6f, 0, "scale 1e6"},
                                     {1, 1e2f, "moved 1e2"},   {1, 1e3f, "moved 1e3"},
                                     {1, 1e4f, "moved 1e4"},   {1, 1e5f, "moved 1e5"}};
    if (fast) settings = {settings[0], settings[3], settings[7]};
    for (const Setting& st : settings) {
        const Scene scene = transformed(base, st.s, st.d);
        Row r{"scene scale and position",
              st.what + " (cornell, " + std::to_string(w) + "x" + std::to_string(h) + ")"};
        r.unit = "share of ids";
        const FrameResult f = render_twice(scene, "basic", w, h, {}, wanted, same);
        r.deterministic = same;
        r.finite = frame_finite(f);
        const Image& ids = buffer(f, "gbuffer_primitive_id");
        const Image& depth = buffer(f, "gbuffer_view_depth");
        std::size_t differ = 0;
        double depth_error = 0.0;
        for (std::size_t i = 0; i < ids.data.size(); ++i) {
            if (ids.data[i] != ids0.data[i]) {
                ++differ;
                continue;
            }
            if (depth0.data[i] > 0.0f)
                depth_error =
                    std::max(depth_error,
                             std::fabs(static_cast<double>(depth.data[i]) / st.s - depth0.data[i]) /
                                 depth0.data[i]);
        }
        r.error = static_cast<double>(differ) / static_cast<double>(ids.data.size());
        r.note = "depth/scale vs unscaled: max rel. " + number(depth_error);
        rows.push_back(r);
    }
}

/// NaN and +-Inf in every input of the metrics and of FLIP: the results are finite and the
/// non-finite inputs are counted (SPEC §0).
void nonfinite_inputs(std::vector<Row>& rows, bool) {
    Image a(32, 24, 3), b(32, 24, 3);
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        a.data[i] = 0.25f + 0.5f * static_cast<float>(i % 7) / 7.0f;
        b.data[i] = a.data[i] + 0.01f * static_cast<float>(i % 3);
    }
    const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                              std::numeric_limits<float>::infinity(),
                              -std::numeric_limits<float>::infinity()};
    for (const float v : specials)
        for (int which = 0; which < 2; ++which) {
            Image x = a, y = b;
            Image& target = which == 0 ? x : y;
            for (std::size_t i = 5; i < target.data.size(); i += 97) target.data[i] = v;
            const std::string what =
                std::string(std::isnan(v) ? "NaN" : (v > 0 ? "+Inf" : "-Inf")) + " in the " +
                (which == 0 ? "reference" : "test");
            {
                Row r{"non-finite inputs", "display transform, " + what};
                r.finite = all_finite(to_display(target));
                rows.push_back(r);
            }
            {
                Row r{"non-finite inputs", "LDR-FLIP, " + what};
                const FlipResult f = ldr_flip(to_display(x), to_display(y), FlipParams{});
                const FlipResult g = ldr_flip(x, y, FlipParams{});
                r.finite = all_finite(f.error_map) && std::isfinite(f.mean) &&
                           all_finite(g.error_map) && std::isfinite(g.mean);
                r.note = std::to_string(g.nonfinite_inputs) + " non-finite inputs counted";
                r.deterministic = canonical_sha256(g.error_map) ==
                                  canonical_sha256(ldr_flip(x, y, FlipParams{}).error_map);
                rows.push_back(r);
            }
        }
}

/// Every render mode on screens of 1x1, 2x1, 1x2 and 3x2 pixels: finite and deterministic.
void tiny_screens(std::vector<Row>& rows, bool fast) {
    const Scene scene = load_scene("cornell");
    std::vector<std::string> modes = {
        "basic", "ground-truth",       "fov",       "kfov",         "cfov",           "ckfov",
        "kfr",   "visual-polar-basic", "pathtrace", "visual-polar", "linear-falloff", "acuity"};
    if (fast) modes.resize(5);
    for (const std::string& mode : modes)
        for (const auto& [w, h] :
             std::vector<std::pair<int, int>>{{1, 1}, {2, 1}, {1, 2}, {3, 2}}) {
            Row r{"tiny screens", mode + " " + std::to_string(w) + "x" + std::to_string(h)};
            r.may_refuse = true;  // with a message naming the limit (Visual-Polar: buffer 2x1)
            try {
                bool same = true;
                const FrameResult f = render_twice(scene, mode, w, h, {}, {"all"}, same);
                r.deterministic = same;
                r.finite = frame_finite(f);
            } catch (const Error& e) {
                r.refused = true;
                r.note = e.what();
            }
            rows.push_back(r);
        }
}

/// Ray-triangle decisions against binary64 (Moller-Trumbore on the same binary32 inputs):
/// rays at grazing angles to a unit triangle pair (a quad split on its diagonal), aimed at a
/// grid of points across it, and rays at a triangle of 1e-6 pixel area. Counted: rays the
/// binary64 test says hit (farther than 1e-5 of the triangle's size from every edge) but the
/// BVH misses, or the reverse; and rays along the shared diagonal that miss both triangles
/// (watertightness: must be none). The error is the relative t difference of the hits.
bool hit_binary64(const glm::vec3& o, const glm::vec3& d, const glm::vec3& a, const glm::vec3& b,
                  const glm::vec3& c, double& t, double& edge) {
    double e1[3], e2[3], p[3], q[3], s[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = static_cast<double>(b[k]) - a[k];
        e2[k] = static_cast<double>(c[k]) - a[k];
        s[k] = static_cast<double>(o[k]) - a[k];
    }
    const auto cross = [](const double* x, const double* y, double* z) {
        z[0] = x[1] * y[2] - x[2] * y[1];
        z[1] = x[2] * y[0] - x[0] * y[2];
        z[2] = x[0] * y[1] - x[1] * y[0];
    };
    const double dd[3] = {d.x, d.y, d.z};
    cross(dd, e2, p);
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0) return false;
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    cross(s, e1, q);
    const double v = (dd[0] * q[0] + dd[1] * q[1] + dd[2] * q[2]) / det;
    t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    edge = std::min(std::min(u, v), 1.0 - u - v);
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0;
}

void grazing_rays(std::vector<Row>& rows, bool fast) {
    // A unit quad in the z = 0 plane as two triangles sharing the diagonal (0,0)-(1,1).
    const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                         {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const Bvh bvh = build_bvh(quad);
    for (const double angle : {0.5, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
        Row r{"grazing rays", "slope " + number(angle) + " to a unit quad"};
        r.unit = "rel. t";
        r.error = 0.0;
        std::int64_t wrong = 0, diagonal_misses = 0, rays = 0;
        const int n = fast ? 24 : 96;
        const float nf = static_cast<float>(n);
        for (int iy = 1; iy < n; ++iy)
            for (int ix = 1; ix < n; ++ix) {
                const glm::vec3 target{static_cast<float>(ix) / nf, static_cast<float>(iy) / nf, 0};
                // slope `angle` (tan of the angle; equal to it to 1e-5 relative below 0.01)
                const glm::vec3 dir{0.6f, 0.8f, -static_cast<float>(angle)};
                Ray ray;
                ray.direction = dir;
                ray.origin = target - 2.0f * dir;
                TraceStats stats;
                const Hit hit = trace_closest(bvh, ray, stats);
                ++rays;
                const bool on_diagonal = ix == iy;
                double t0 = 0, edge0 = 0, t1 = 0, edge1 = 0;
                const bool h0 = hit_binary64(ray.origin, dir, quad[0], quad[1], quad[2], t0, edge0);
                const bool h1 = hit_binary64(ray.origin, dir, quad[3], quad[4], quad[5], t1, edge1);
                if (on_diagonal) {
                    if (!hit.hit()) ++diagonal_misses;
                    continue;
                }
                const bool clear = std::max(edge0, edge1) > 1e-5 || (!h0 && !h1);
                if (clear && hit.hit() != (h0 || h1)) ++wrong;
                if (hit.hit() && (h0 || h1)) {
                    const double t = h0 ? t0 : t1;
                    r.error = std::max(r.error, std::fabs(hit.t - t) / t);
                }
                r.finite = r.finite && (!hit.hit() || std::isfinite(hit.t));
            }
        r.bound = 1e-6;  // t relative: a few binary32 roundings (the origin is 2 units away)
        r.determinism_checked = false;
        r.violations = wrong + diagonal_misses;
        r.note = std::to_string(rays) + " rays, " + std::to_string(wrong) +
                 " decisions unlike binary64 away from edges, " + std::to_string(diagonal_misses) +
                 " misses on the shared edge";
        rows.push_back(r);
    }
    // A triangle of about 1e-6 px^2 seen from 1 unit with a 1000 px focal length.
    {
        Row r{"grazing rays", "triangle of 1e-6 px^2 at 1 unit (f = 1000 px)"};
        const float side = 1.414e-6f;  // (side^2 / 2) * 1000^2 px^2 per unit^2 = 1e-6 px^2
        const std::vector<glm::vec3> tiny = {{0, 0, 0}, {side, 0, 0}, {0, side, 0}};
        const Bvh small = build_bvh(tiny);
        std::int64_t wrong = 0, hits = 0;
        const int n = fast ? 16 : 64;
        const float nf = static_cast<float>(n);
        for (int iy = 0; iy <= n; ++iy)
            for (int ix = 0; ix <= n; ++ix) {
                const glm::vec3 target{side * static_cast<float>(ix) / nf,
                                       side * static_cast<float>(iy) / nf, 0.0f};
                Ray ray;
                ray.direction = glm::vec3(0.0f, 0.0f, -1.0f);
                ray.origin = target + glm::vec3(0.0f, 0.0f, 1.0f);
                TraceStats stats;
                const Hit hit = trace_closest(small, ray, stats);
                double t = 0, edge = 0;
                const bool h =
                    hit_binary64(ray.origin, ray.direction, tiny[0], tiny[1], tiny[2], t, edge);
                hits += hit.hit() ? 1 : 0;
                if (std::fabs(edge) > 1e-5 && hit.hit() != h) ++wrong;
            }
        r.determinism_checked = false;
        r.violations = wrong;
        r.note = std::to_string(hits) + " hits, " + std::to_string(wrong) +
                 " decisions unlike binary64 away from edges";
        rows.push_back(r);
    }
}

/// BMFR on blocks that are empty (sky), constant on a flat wall (rank-deficient features), and
/// with NaN or Inf in each input buffer: finite output; a constant colour is reproduced within
/// the storage's precision (binary16: 2e-3, binary32: 1e-4).
void bmfr_blocks(std::vector<Row>& rows, bool) {
    const int w = 70, h = 40;
    Image radiance(w, h, 3, 0.25f), albedo(w, h, 3, 0.5f), normal(w, h, 3), world(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            world.at(x, y, 0) = 0.05f * static_cast<float>(x);
            world.at(x, y, 1) = 0.05f * static_cast<float>(y);
            world.at(x, y, 2) = 1.0f;
            normal.at(x, y, 1) = 1.0f;
        }
    for (const BmfrStorage storage : {BmfrStorage::half, BmfrStorage::single}) {
        BmfrParams params;
        params.storage = storage;
        const std::string st = storage == BmfrStorage::half ? "binary16" : "binary32";
        const auto denoise = [&](const Image& rad, const Image& alb, const Image& nor,
                                 const Image& wor) {
            BmfrHistory history;
            BmfrStats stats;
            return bmfr_denoise_frame(params, rad, alb, Image{}, nor, wor, ViewProjection{}, 0,
                                      history, stats);
        };
        {
            Row r{"bmfr blocks", "constant colour, flat wall (rank-deficient), " + st};
            const BmfrFrame a = denoise(radiance, albedo, normal, world);
            r.finite = all_finite(a.output);
            r.deterministic = canonical_sha256(a.output) ==
                              canonical_sha256(denoise(radiance, albedo, normal, world).output);
            r.error = 0.0;
            for (float v : a.fitted.data) r.error = std::max(r.error, std::fabs(v - 0.5));
            r.bound = storage == BmfrStorage::half ? 2e-3 : 1e-4;
            r.unit = "abs";
            rows.push_back(r);
        }
        {
            Row r{"bmfr blocks", "empty blocks (sky: all zero), " + st};
            const Image zero(w, h, 3, 0.0f);
            const BmfrFrame a = denoise(zero, zero, zero, zero);
            r.finite = all_finite(a.output);
            r.error = 0.0;
            for (float v : a.output.data)
                r.error = std::max(r.error, std::fabs(static_cast<double>(v)));
            r.bound = 0.0;
            r.unit = "abs";
            rows.push_back(r);
        }
        const char* names[] = {"radiance", "albedo", "normal", "world position"};
        for (int which = 0; which < 4; ++which)
            for (const float v : {std::numeric_limits<float>::quiet_NaN(),
                                  std::numeric_limits<float>::infinity()}) {
                Image in[4] = {radiance, albedo, normal, world};
                for (std::size_t i = 7; i < in[which].data.size(); i += 131) in[which].data[i] = v;
                Row r{"bmfr blocks", std::string(std::isnan(v) ? "NaN" : "Inf") + " in the " +
                                         names[which] + ", " + st};
                const BmfrFrame a = denoise(in[0], in[1], in[2], in[3]);
                r.finite = all_finite(a.output);
                r.deterministic = canonical_sha256(a.output) ==
                                  canonical_sha256(denoise(in[0], in[1], in[2], in[3]).output);
                rows.push_back(r);
            }
    }
}

/// NaN and +Inf written into every 37th value of each buffer a stage hands on (through the
/// render's after_stage hook), for every mode, over two frames (modes with state carry the
/// second frame's history through it): the final image must stay finite (SPEC §0: non-finite
/// values are replaced, never propagated). The final image itself is not corrupted (that would
/// only test the corruption).
void injected_buffers(std::vector<Row>& rows, bool fast) {
    const Scene scene = load_scene("cornell");
    std::vector<std::string> modes = {"basic",          "fov",
                                      "kfov",           "cfov",
                                      "ckfov",          "kfr",
                                      "stereo-lp",      "pathtrace",
                                      "visual-polar",   "visual-polar-basic",
                                      "linear-falloff", "acuity"};
    if (fast) modes = {"basic", "fov", "kfr", "visual-polar"};
    for (const std::string& mode : modes) {
        RenderSettings s;
        s.width = 32;
        s.height = 18;
        s.frame_count = 2;
        std::vector<std::pair<std::string, std::string>> params;
        if (mode == "basic" || mode == "fov" || mode == "kfr") params = {{"taa", "depth"}};
        for (const auto& [k, v] : params) s.params.set(k, v);
        // What the stages hand on: every buffer of a full render but the final image.
        const std::vector<std::string> finals = {"final"};
        RenderSettings all = s;
        all.requested = {"all"};
        std::vector<std::pair<std::string, std::string>> targets;  // (stage, buffer)
        const std::vector<FrameResult> full = render(&scene, mode, all);
        for (const Buffer& b : full.front().buffers)
            if (std::find(finals.begin(), finals.end(), b.name) == finals.end())
                targets.emplace_back(b.stage, b.name);
        for (const float bad :
             {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
            Row r{"injected NaN/Inf", mode + ": " + (std::isnan(bad) ? "NaN" : "+Inf") +
                                          " in each of " + std::to_string(targets.size()) +
                                          " handed-on buffers"};
            r.determinism_checked = false;
            std::string broken;
            for (const auto& [stage, name] : targets) {
                RenderSettings corrupt = s;
                corrupt.requested = {"all"};
                corrupt.after_stage = [&, target_stage = stage, target = name](
                                          const std::string& ran, FrameResult& result) {
                    if (ran != target_stage) return;
                    for (Buffer& b : result.buffers)
                        if (b.name == target)
                            for (std::size_t i = 0; i < b.image.data.size(); i += 37)
                                b.image.data[i] = bad;
                };
                try {
                    for (const FrameResult& f : render(&scene, mode, corrupt))
                        for (const std::string& final_name : finals) {
                            const Buffer* b = f.find(final_name);
                            if (b && !all_finite(b->image)) {
                                ++r.violations;
                                if (broken.size() < 200)
                                    broken += (broken.empty() ? "" : ", ") + name + " -> " +
                                              final_name + " (frame " + std::to_string(f.frame) +
                                              ")";
                            }
                        }
                } catch (const std::exception& e) {  // Error, or worse (bad_alloc)
                    ++r.violations;
                    if (broken.size() < 300)
                        broken += (broken.empty() ? "" : ", ") + name + ": " + e.what();
                }
            }
            r.note = broken.empty() ? "finals finite" : "not finite: " + broken;
            rows.push_back(r);
        }
    }
}

struct Group {
    const char* name;
    void (*run)(std::vector<Row>&, bool fast);
};

const Group groups[] = {{"camera rays", camera_rays},
                        {"tiny screens", tiny_screens},
                        {"grazing rays", grazing_rays},
                        {"bmfr blocks", bmfr_blocks},
                        {"log-polar round trip", log_polar_round_trip},
                        {"parameter limits", parameter_limits},
                        {"scene scale and position", scene_scale},
                        {"non-finite inputs", nonfinite_inputs},
                        {"injected NaN/Inf", injected_buffers}};

}  // namespace

int run_stress(const StressOptions& o) {
    std::vector<Row> rows;
    int groups_run = 0;
    for (const Group& g : groups) {
        if (!o.filter.empty() && std::string(g.name).find(o.filter) == std::string::npos) continue;
        ++groups_run;
        const auto start = std::chrono::steady_clock::now();
        g.run(rows, o.fast);
        if (!o.quiet)
            std::fprintf(
                stderr, "stress: %s done (%.1f s)\n", g.name,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    if (groups_run == 0) throw Error("stress: no case group matches --case '" + o.filter + "'");
    int failed = 0;
    std::printf("%-26s %-46s %-6s %-6s %-12s %-12s %s\n", "group", "case", "finite", "determ",
                "error", "bound", "status / note");
    json out = json::array();
    for (const Row& r : rows) {
        failed += r.pass() ? 0 : 1;
        const std::string error = std::isnan(r.error) ? "-" : number(r.error);
        const std::string bound = std::isnan(r.bound) ? "-" : number(r.bound);
        std::printf(
            "%-26s %-46s %-6s %-6s %-12s %-12s %s%s%s\n", r.group.c_str(), r.name.c_str(),
            r.expect_refused ? "-" : (r.finite ? "yes" : "NO"),
            r.expect_refused || !r.determinism_checked ? "-" : (r.deterministic ? "yes" : "NO"),
            error.c_str(), bound.c_str(),
            r.refused && r.pass() ? "refused (clear message)" : r.status().c_str(),
            r.note.empty() ? "" : ": ", r.note.c_str());
        json j = {{"group", r.group},
                  {"case", r.name},
                  {"finite", r.finite},
                  {"deterministic", r.deterministic},
                  {"determinism_checked", r.determinism_checked},
                  {"unit", r.unit},
                  {"status", r.status()},
                  {"pass", r.pass()},
                  {"note", r.note},
                  {"expect_refused", r.expect_refused},
                  {"refused", r.refused}};
        if (!std::isnan(r.error)) j["error"] = r.error;
        if (!std::isnan(r.bound)) j["bound"] = r.bound;
        out.push_back(j);
    }
    if (!o.json.empty()) write_file_atomic(o.json, json{{"rows", out}}.dump(1) + "\n");
    std::printf("stress: %zu case(s), %d failed\n", rows.size(), failed);
    return failed == 0 ? 0 : 1;
}

}  // namespace fovref
