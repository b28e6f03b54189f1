#include "ref/trace/trace_probe.h"

#include <cmath>
#include <cstring>

#include "ref/bvh/bvh.h"
#include "ref/core/rng.h"
#include "ref/raster/rasterizer.h"
#include "ref/stage/probe.h"
#include "ref/trace/basic_params.h"
#include "ref/trace/direct_light.h"
#include "ref/trace/ground_truth.h"
#include "ref/trace/raycast_gbuffer.h"
#include "ref/trace/shade_basic.h"
#include "ref/trace/trace_probe.h"

namespace fovref {

glm::vec3 probe_rgb(const FrameResult& frame, const std::string& name, int x, int y) {
    const Buffer* b = frame.find(name);
    if (!b || b->image.channels < 3) return glm::vec3(NAN);
    return {b->image.at(x, y, 0), b->image.at(x, y, 1), b->image.at(x, y, 2)};
}

void explain_surface(const Scene& scene, const SurfacePoint& surface, ProbeSection& section) {
    section.add("position", probe_vec3(surface.position));
    section.add("geometric normal", probe_vec3(surface.geometric_normal));
    section.add("shading normal", probe_vec3(surface.shading_normal));
    section.add("uv", "(" + probe_float(surface.uv.x) + ", " + probe_float(surface.uv.y) + ")");
    if (surface.material < 0) return;
    const Material& m = scene.materials[static_cast<std::size_t>(surface.material)];
    section.add("material", std::to_string(surface.material) + " '" + m.name + "', albedo " +
                                probe_vec3(m.albedo) + ", emission " + probe_vec3(m.emission));
    if (m.texture >= 0) {
        const Texture& t = scene.textures[static_cast<std::size_t>(m.texture)];
        // The sampler's own computation, recorded (surface_at calls the same function).
        BilinearTrace trace;
        const glm::vec3 value = sample_texture_bilinear(t, surface.uv, &trace);
        const BilinearTaps& taps = trace.taps;
        if (taps.valid) {
            const int xs[4] = {taps.x0, taps.x1, taps.x0, taps.x1};
            const int ys[4] = {taps.y0, taps.y0, taps.y1, taps.y1};
            section.add("texture", "'" + t.name + "' " + std::to_string(t.image.width) + "x" +
                                       std::to_string(t.image.height) +
                                       ", bilinear, repeat; lerp fractions tx " +
                                       probe_float(taps.tx) + " ty " + probe_float(taps.ty));
            for (int k = 0; k < 4; ++k)
                section.add("  texel " + std::to_string(k), "(" + std::to_string(xs[k]) + ", " +
                                                                std::to_string(ys[k]) + ") value " +
                                                                probe_vec3(trace.texels[k]));
            section.add(
                "  lerp in x",
                "top = texel 0 (1 - tx) + texel 1 tx = " + probe_vec3(trace.top) +
                    ", bottom = texel 2 (1 - tx) + texel 3 tx = " + probe_vec3(trace.bottom));
            section.add("  lerp in y", "top (1 - ty) + bottom ty = " + probe_vec3(value));
        } else {
            section.add("texture", "uv not finite: black");
        }
    }
    section.add("albedo", probe_vec3(surface.albedo));
}

void probe_check(ProbeReport& report, ProbeSection& section, const std::string& what,
                 glm::vec3 mine, glm::vec3 rendered) {
    const bool same = std::memcmp(&mine, &rendered, sizeof mine) == 0;
    section.add("check", what + ": " +
                             (same ? "bit-identical to the rendered buffer"
                                   : "DIFFERS from the rendered buffer " + probe_vec3(rendered)));
    if (!same) report.consistent = false;
}

namespace {

// The ray, the closest hit and the surface there.
void explain_ray(const Scene& scene, const Bvh& bvh, const Ray& ray, const std::string& label,
                 ProbeSection& section, Hit& hit, SurfacePoint& surface) {
    section.add(label + " ray", "origin " + probe_vec3(ray.origin) + ", direction " +
                                    probe_vec3(ray.direction) + ", t in (" +
                                    probe_float(ray.t_min) + ", " + probe_float(ray.t_max) + ")");
    TraceStats stats;
    hit = trace_closest(bvh, ray, stats);
    section.add("traversal", std::to_string(stats.nodes_visited) + " nodes visited, " +
                                 std::to_string(stats.triangles_tested) + " triangles tested");
    if (!hit.hit()) {
        section.add("hit", "miss (background: black)");
        return;
    }
    section.add("hit", "t " + probe_float(hit.t) + ", primitive " + std::to_string(hit.primitive) +
                           ", barycentrics u " + probe_float(hit.u) + " v " + probe_float(hit.v) +
                           " (closest; ties: lowest primitive id)");
    surface = surface_at(scene, hit.primitive, hit.u, hit.v);
}

// The light samples shade_direct recorded, and the radiance.
void explain_shading(const Scene& scene, const SurfacePoint& surface, glm::vec3 radiance,
                     const std::vector<LightSampleRecord>& lights, std::uint32_t frame,
                     std::uint32_t pixel, std::uint32_t base, ProbeSection& section) {
    const Material& m = scene.materials[static_cast<std::size_t>(surface.material)];
    section.add("rand", "rand(frame " + std::to_string(frame) + ", pixel " + std::to_string(pixel) +
                            ", dimension " + std::to_string(base) + " + 2 l (+1)) (SPEC §0)");
    if (m.emission != glm::vec3(0.0f))
        section.add("emission", probe_vec3(m.emission) + " (front side only)");
    if (lights.empty()) section.add("lights", "none: no shadow rays");
    for (const LightSampleRecord& r : lights) {
        const Light& light = scene.lights[static_cast<std::size_t>(r.light)];
        std::string text = std::string(light_type_name(light.type)) + ": ";
        if (light.type != Light::Type::point)
            text += "r1 " + probe_float(r.r1) + " r2 " + probe_float(r.r2) + ", ";
        text += "sample " + probe_vec3(r.sample) + ", d " + probe_float(r.distance) + ", cos " +
                probe_float(r.cos_surface) + ", G " + probe_float(r.geometry) + " -> " + r.outcome;
        if (std::string(r.outcome) == "lit" || std::string(r.outcome) == "occluded")
            text += " (shadow ray from " + probe_vec3(r.shadow_origin) + ")";
        if (std::string(r.outcome) == "lit") text += ", adds " + probe_vec3(r.contribution);
        section.add("light " + std::to_string(r.light), text);
    }
    section.add("radiance", probe_vec3(radiance));
}

std::string fixed_text(FixedPoint p) {
    auto one = [](std::int64_t v) {
        return std::to_string(v) + "/256 (" +
               probe_float(static_cast<float>(v) / static_cast<float>(raster_subpixel_scale)) + ")";
    };
    return "(" + one(p.x) + ", " + one(p.y) + ")";
}

// Which side of the (clockwise-on-screen, y-down) triangle an edge a -> b is.
const char* edge_side(FixedPoint a, FixedPoint b) {
    const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
    if (dy == 0) return dx > 0 ? "top" : "bottom";
    return dy < 0 ? "left" : "right";
}

// The rasterizer's decision at one pixel, from the pass's own functions (explain_raster_pixel).
void explain_raster(const ProbeContext& c, const RasterSettings& raster, ProbeReport& report,
                    ProbeSection& vis, std::int32_t& winner, RasterFragment& winning) {
    const RasterPixelExplanation e = explain_raster_pixel(*c.scene, c.camera, c.settings->width,
                                                          c.settings->height, raster, c.x, c.y);
    vis.add("fill rule", std::string(fill_rule_name(e.fill_rule)) +
                             (e.fill_rule == FillRule::d3d
                                  ? ": a centre on an edge is covered by top and left edges"
                                  : ": a centre on an edge is covered by bottom and left edges "
                                    "(OpenGL's top-left in its y-up window)"));
    vis.add("sample", "pixel centre " + fixed_text(e.centre) + " in 1/256 px");
    if (e.candidates.empty())
        vis.add("coverage", "no triangle's snapped coverage contains the centre: background");
    for (const RasterCandidate& k : e.candidates) {
        const std::string name = "triangle " + std::to_string(k.primitive);
        std::string setup = "snapped corners a " + fixed_text(k.a) + ", b " + fixed_text(k.b) +
                            ", c " + fixed_text(k.c) + " (clockwise on screen";
        if (k.near_clipped || k.guard_clipped)
            setup += std::string(", fan triangle ") + std::to_string(k.fan_triangle) +
                     " of the polygon clipped by the " +
                     (k.near_clipped && k.guard_clipped ? "near plane and the guard band"
                      : k.near_clipped                  ? "near plane"
                                                        : "guard band");
        vis.add(name, setup + ")");
        const FixedPoint corners[3] = {k.a, k.b, k.c};
        const char* edge_names[3] = {"E_bc", "E_ca", "E_ab"};
        const std::int64_t values[3] = {k.edges.wa, k.edges.wb, k.edges.wc};
        std::string edges = "doubled area " + std::to_string(k.area) + ";";
        for (int i = 0; i < 3; ++i) {
            edges += std::string(" ") + edge_names[i] + " " + std::to_string(values[i]);
            if (values[i] == 0)
                edges += std::string(" (on the ") +
                         edge_side(corners[(i + 1) % 3], corners[(i + 2) % 3]) + " edge, " +
                         (k.owns[i] ? "which owns it" : "which does not own it") + ")";
        }
        vis.add("  edges", edges + " -> covered");
        if (!k.fragment) {
            vis.add("  fragment",
                    "the pixel's ray does not meet the plane in front of the "
                    "camera: dropped");
            continue;
        }
        vis.add("  fragment", "plane hit t " + probe_float(k.value.t) + ", barycentrics u " +
                                  probe_float(k.value.u) + " v " + probe_float(k.value.v) +
                                  ", view depth " + probe_float(k.value.depth));
        std::string test;
        if (k.stored_primitive < 0)
            test = "passes: the first fragment here";
        else if (k.value.depth != k.stored_depth)
            test = std::string(k.won_depth_test ? "passes: " : "fails: ") +
                   probe_float(k.value.depth) + (k.won_depth_test ? " < " : " > ") +
                   probe_float(k.stored_depth) + " of triangle " +
                   std::to_string(k.stored_primitive) + " (\"less\")";
        else
            test = std::string(k.won_depth_test ? "passes" : "fails") +
                   ": equal depth to triangle " + std::to_string(k.stored_primitive) +
                   ", the lower primitive id wins (SPEC §3, §4)";
        vis.add("  depth test", test);
    }
    winner = e.winner;
    for (const RasterCandidate& k : e.candidates)
        if (k.fragment && k.primitive == e.winner && k.won_depth_test) winning = k.value;
    if (e.candidates.size() > 1 && winner >= 0)
        vis.add("winner", "triangle " + std::to_string(winner) +
                              ": smallest view depth; an equal depth goes to the lower id "
                              "(SPEC §3, §4)");
    else if (winner >= 0)
        vis.add("winner", "triangle " + std::to_string(winner) + " (the only one covering it)");
    const float gbuffer_id = c.frame->find("gbuffer_primitive_id")->image.at(c.x, c.y);
    const bool same = static_cast<float>(winner) == gbuffer_id;
    vis.add("check", std::string("winner: ") + (same ? "the G-buffer's primitive id"
                                                     : "DIFFERS from the G-buffer's primitive id " +
                                                           probe_float(gbuffer_id)));
    if (!same) report.consistent = false;
}

// [primary_visibility] of a rasterized G-buffer: the rasterizer's decision, the surface at the
// winner's plane point, and the ray caster's answer for comparison.
void explain_raster_visibility(const ProbeContext& c, const RasterSettings& raster, const Bvh& bvh,
                               const Ray& ray, ProbeReport& report) {
    const Scene& scene = *c.scene;
    const FrameResult& f = *c.frame;
    ProbeSection vis{"primary_visibility",
                     "rasterized G-buffer: coverage in 1/256-px fixed point, attributes where "
                     "the pixel's ray meets the winning triangle's plane (docs/raster.md)",
                     {}};
    std::int32_t winner = -1;
    RasterFragment winning;
    explain_raster(c, raster, report, vis, winner, winning);
    if (winner >= 0) {
        const SurfacePoint surface = surface_at(scene, winner, winning.u, winning.v);
        explain_surface(scene, surface, vis);
        probe_check(report, vis, "position", surface.position,
                    probe_rgb(f, "gbuffer_world_position", c.x, c.y));
    }
    report.sections.push_back(vis);
    // The ray caster's answer, for comparison only: it is not what this G-buffer used.
    ProbeSection caster{"ray caster (comparison)",
                        "what ray-cast primary visibility (--param primary=ray) would give "
                        "here; not used by this G-buffer",
                        {}};
    Hit hit;
    SurfacePoint traced;
    explain_ray(scene, bvh, ray, "primary", caster, hit, traced);
    caster.add("compared", hit.primitive == winner
                               ? "the same primitive: the same t, u, v bits (docs/raster.md)"
                               : "another primitive than the rasterizer's: the ray passes "
                                 "within the snapping distance (~1/256 px) of an edge, where "
                                 "the two decide coverage differently");
    report.sections.push_back(caster);
}

// [primary_visibility] of a ray-cast G-buffer: the pass's own per-pixel function into a scratch
// G-buffer, checked against the rendered one.
void explain_ray_visibility(const ProbeContext& c, const Bvh& bvh, const Ray& ray,
                            ProbeReport& report) {
    const Scene& scene = *c.scene;
    const FrameResult& f = *c.frame;
    const int width = c.settings->width, height = c.settings->height;
    ProbeSection vis{"primary_visibility",
                     c.jitter == Offset2{} ? "one ray through the pixel centre (Lund §3.1)"
                                           : "one ray through the pixel at the TAA jitter (" +
                                                 probe_float(c.jitter.x) + ", " +
                                                 probe_float(c.jitter.y) + ") (SPEC §7)",
                     {}};
    vis.add("primary ray", "origin " + probe_vec3(ray.origin) + ", direction " +
                               probe_vec3(ray.direction) + ", t in (" + probe_float(ray.t_min) +
                               ", " + probe_float(ray.t_max) + ")");
    // The pass's own per-pixel function, into a scratch G-buffer.
    GBuffer scratch(width, height);
    RaycastStats stats;
    const Hit hit = raycast_gbuffer_pixel(scratch, PrimaryView(scene, bvh, c.camera, c.camera), c.x,
                                          c.y, stats, c.jitter);
    vis.add("traversal", std::to_string(stats.primary.nodes_visited) + " nodes visited, " +
                             std::to_string(stats.primary.triangles_tested) + " triangles tested");
    if (!hit.hit()) {
        vis.add("hit", "miss (background: ids -1, every other channel 0)");
    } else {
        vis.add("hit", "t " + probe_float(hit.t) + ", primitive " + std::to_string(hit.primitive) +
                           ", barycentrics u " + probe_float(hit.u) + " v " + probe_float(hit.v) +
                           " (closest; ties: lowest primitive id)");
        explain_surface(scene, surface_at(scene, hit.primitive, hit.u, hit.v), vis);
    }
    // Every channel but motion (the scratch pass used this camera as the previous one).
    const bool same = probe_same_gbuffer(scratch, f, "gbuffer_", c.x, c.y);
    vis.add("check",
            std::string("G-buffer pixel: ") + (same ? "bit-identical to the rendered buffers"
                                                    : "DIFFERS from the rendered buffers"));
    if (!same) report.consistent = false;
    report.sections.push_back(vis);
}

// [shade_direct]: the shading pass's own per-pixel function on the rendered G-buffer.
void explain_shade_direct(const ProbeContext& c, const Bvh& bvh, ProbeReport& report) {
    ProbeSection shade{"shade_direct", "Lambert + one shadow ray per light sample (Gupta §2)", {}};
    // With TAA the shading pass writes "shaded" (TAA then writes "final").
    explain_shade_at(c, bvh, "gbuffer_", c.frame->find("shaded") ? "shaded" : "final", c.x, c.y,
                     shade, report);
    report.sections.push_back(shade);
}

}  // namespace

bool probe_same_gbuffer(const GBuffer& mine, const FrameResult& f, const std::string& prefix, int x,
                        int y) {
    return probe_same_gbuffer(mine, x, y, f, prefix, x, y);
}

bool probe_same_gbuffer(const GBuffer& mine, int x, int y, const FrameResult& f,
                        const std::string& prefix, int rx, int ry) {
    bool same = true;
    for (const auto& [name, image] :
         {std::pair<const char*, const Image*>{"view_depth", &mine.view_depth},
          {"hit_distance", &mine.hit_distance},
          {"world_position", &mine.world_position},
          {"shading_normal", &mine.shading_normal},
          {"geometric_normal", &mine.geometric_normal},
          {"albedo", &mine.albedo},
          {"material_id", &mine.material_id},
          {"primitive_id", &mine.primitive_id}}) {
        const Image& rendered = f.find(prefix + name)->image;
        for (int k = 0; k < image->channels; ++k) {
            const float a = image->at(x, y, k), b = rendered.at(rx, ry, k);
            same = same && std::memcmp(&a, &b, sizeof a) == 0;
        }
    }
    return same;
}

void explain_shade_at(const ProbeContext& c, const Bvh& bvh, const std::string& prefix,
                      const std::string& color, int x, int y, ProbeSection& shade,
                      ProbeReport& report, const ScreenWindow* window) {
    const Scene& scene = *c.scene;
    const FrameResult& f = *c.frame;
    const ShadeInputs inputs{f.find(prefix + "world_position")->image,
                             f.find(prefix + "shading_normal")->image,
                             f.find(prefix + "geometric_normal")->image,
                             f.find(prefix + "albedo")->image,
                             f.find(prefix + "material_id")->image,
                             f.find(prefix + "primitive_id")->image,
                             window};
    SurfacePoint surface;
    ShadingStats unused;
    if (!gbuffer_surface(scene, inputs, x, y, surface, unused)) {
        shade.add("shading", "background (or no valid material): black, nothing shaded");
        return;
    }
    shade.add("inputs", "from " + prefix + "*: position " + probe_vec3(surface.position) +
                            ", shading normal " + probe_vec3(surface.shading_normal) + ", albedo " +
                            probe_vec3(surface.albedo));
    ShadingStats stats;
    std::vector<LightSampleRecord> lights;
    const glm::vec3 l = shade_basic_pixel(scene, scene.lights.empty() ? nullptr : &bvh, inputs,
                                          c.camera, f.frame, x, y, stats, &lights);
    explain_shading(scene, surface, l, lights, static_cast<std::uint32_t>(f.frame),
                    shade_pixel_index(inputs, x, y), 0, shade);
    probe_check(report, shade, "radiance", l, probe_rgb(f, color, x, y));
}

void explain_basic(const ProbeContext& c, ProbeReport& report) {
    const BasicParams params = parse_basic_params(c.settings->params);
    const Bvh bvh = build_bvh(c.scene->positions);

    ProbeSection map{"forward map", "screen pixel -> buffer texel", {}};
    map.add("mapping", "none (no foveation): buffer texel (" + std::to_string(c.x) + ", " +
                           std::to_string(c.y) + "), weight 1");
    report.sections.push_back(map);

    // The pixel centre, or the TAA jitter's launch point.
    const Ray ray =
        primary_ray(c.camera, tan_half_vfov(c.camera), c.settings->width, c.settings->height,
                    static_cast<float>(c.x) + c.jitter.x, static_cast<float>(c.y) + c.jitter.y);
    if (params.primary == PrimaryVisibility::raster)
        explain_raster_visibility(c, params.raster, bvh, ray, report);
    else
        explain_ray_visibility(c, bvh, ray, report);
    explain_shade_direct(c, bvh, report);
}

void explain_ground_truth(const ProbeContext& c, ProbeReport& report) {
    const Scene& scene = *c.scene;
    const Bvh bvh = build_bvh(scene.positions);
    ProbeSection ss{"supersample",
                    "16 rays at Halton(2,3) points 1..16, each shaded like basic, box filter "
                    "(Lund §3.2)",
                    {}};
    TraceStats primary;
    ShadingStats shading;
    std::vector<GroundTruthSample> samples;
    const glm::vec3 mean = ground_truth_pixel(
        scene, bvh, c.camera, tan_half_vfov(c.camera), static_cast<std::uint32_t>(c.frame->frame),
        c.settings->width, c.settings->height, c.x, c.y, primary, shading, &samples);
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const GroundTruthSample& g = samples[s];
        std::string text = "offset (" + probe_float(g.offset.x) + ", " + probe_float(g.offset.y) +
                           "), direction " + probe_vec3(g.direction);
        if (!g.hit.hit()) {
            ss.add("sample " + std::to_string(s), text + " -> miss");
            continue;
        }
        ss.add("sample " + std::to_string(s),
               text + " -> primitive " + std::to_string(g.hit.primitive) + " t " +
                   probe_float(g.hit.t) + ", radiance " + probe_vec3(g.radiance));
    }
    const glm::vec3 sum = samples.empty() ? glm::vec3(0.0f) : samples.back().sum;
    ss.add("box filter", "sum " + probe_vec3(sum) + " x 1/16 = " + probe_vec3(mean));
    probe_check(report, ss, "mean", mean, probe_rgb(*c.frame, "final", c.x, c.y));
    report.sections.push_back(ss);
}

}  // namespace fovref
