#include "tools/cli/commands/scene.h"

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/common/cli_common.h"

namespace fovref {

namespace {

std::string vec3_text(glm::vec3 v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", static_cast<double>(v.x),
                  static_cast<double>(v.y), static_cast<double>(v.z));
    return text;
}

// Lights by Light::Type: point, quad, emissive triangle.
struct LightCounts {
    int by_type[3] = {0, 0, 0};
};

LightCounts count_lights(const Scene& scene) {
    LightCounts counts;
    for (const Light& light : scene.lights) ++counts.by_type[static_cast<int>(light.type)];
    return counts;
}

nlohmann::json scene_info_json(const Scene& scene, const Bounds& bounds, const LightCounts& l) {
    nlohmann::json j;
    j["name"] = scene.name;
    j["source"] = scene.source;
    j["triangles"] = scene.triangle_count();
    j["bounds"] = {{"min", {bounds.min.x, bounds.min.y, bounds.min.z}},
                   {"max", {bounds.max.x, bounds.max.y, bounds.max.z}}};
    j["scene_scale"] = scene.scene_scale;
    j["materials"] = nlohmann::json::array();
    for (const Material& m : scene.materials)
        j["materials"].push_back({{"name", m.name},
                                  {"albedo", {m.albedo.x, m.albedo.y, m.albedo.z}},
                                  {"texture", m.texture},
                                  {"emission", {m.emission.x, m.emission.y, m.emission.z}},
                                  {"specular", {m.specular.x, m.specular.y, m.specular.z}},
                                  {"roughness", m.roughness}});
    j["textures"] = nlohmann::json::array();
    for (const Texture& t : scene.textures)
        j["textures"].push_back(
            {{"name", t.name}, {"width", t.image.width}, {"height", t.image.height}});
    j["lights"] = {{"point", l.by_type[0]}, {"quad", l.by_type[1]}, {"triangle", l.by_type[2]}};
    j["camera_path_keys"] = scene.camera_path.size();
    j["presets"] = nlohmann::json::array();
    for (const auto& [name, text] : scene.presets) j["presets"].push_back(name);
    j["dropped"] = {{"zero_area_triangles", scene.load_stats.zero_area_triangles_dropped}};
    j["ignored"] = {{"points", scene.load_stats.points_ignored},
                    {"lines", scene.load_stats.lines_ignored}};
    j["repaired"] = {{"polygons_triangulated", scene.load_stats.polygons_triangulated},
                     {"concave_polygons", scene.load_stats.concave_polygons},
                     {"normals_generated", scene.load_stats.normals_generated}};
    j["defaulted"] = scene.load_stats.defaulted;
    j["unsupported"] = scene.load_stats.unsupported;
    j["warnings"] = scene.load_stats.warnings;
    return j;
}

void print_materials(const Scene& scene) {
    std::printf("materials  %zu\n", scene.materials.size());
    for (std::size_t k = 0; k < scene.materials.size(); ++k) {
        const Material& m = scene.materials[k];
        std::printf(
            "  [%zu] %-20s albedo %s%s%s%s\n", k, m.name.c_str(), vec3_text(m.albedo).c_str(),
            m.texture >= 0 ? (" texture " + scene.textures[m.texture].name).c_str() : "",
            m.emission != glm::vec3(0.0f) ? (" emission " + vec3_text(m.emission)).c_str() : "",
            m.specular != glm::vec3(0.0f) ? (" specular " + vec3_text(m.specular) + " roughness " +
                                             std::to_string(m.roughness))
                                                .c_str()
                                          : "");
    }
    std::printf("textures   %zu\n", scene.textures.size());
    for (const Texture& t : scene.textures)
        std::printf("  %s %dx%d\n", t.name.c_str(), t.image.width, t.image.height);
}

void print_lights_and_camera(const Scene& scene, const LightCounts& l) {
    std::printf("lights     %zu (point %d, quad %d, emissive triangles %d)\n", scene.lights.size(),
                l.by_type[0], l.by_type[1], l.by_type[2]);
    for (const Light& light : scene.lights)
        if (light.type != Light::Type::triangle)
            std::printf("  %-5s at %s intensity %s\n", light_type_name(light.type),
                        vec3_text(light.position).c_str(), vec3_text(light.intensity).c_str());
    const Camera& c = scene.camera;
    std::printf("camera     at %s forward %s vfov %.6g deg\n", vec3_text(c.position).c_str(),
                vec3_text(c.forward).c_str(), static_cast<double>(c.vfov_deg));
    if (scene.camera_path.empty())
        std::printf("path       none (static camera)\n");
    else
        std::printf("path       %zu keys, t = %.6g .. %.6g\n", scene.camera_path.size(),
                    static_cast<double>(scene.camera_path.front().time),
                    static_cast<double>(scene.camera_path.back().time));
}

void print_scene_info(const Scene& scene, const Bounds& bounds, const LightCounts& l) {
    std::printf("scene      %s\n", scene.name.c_str());
    std::printf("source     %s\n", scene.source.c_str());
    std::printf("triangles  %zu\n", scene.triangle_count());
    std::printf("bounds     %s .. %s (scale %.6g)\n", vec3_text(bounds.min).c_str(),
                vec3_text(bounds.max).c_str(), static_cast<double>(scene.scene_scale));
    print_materials(scene);
    print_lights_and_camera(scene, l);
    const char* display = scene.display.kind == DisplayModel::Kind::field_of_view ? "field of view"
                          : scene.display.kind == DisplayModel::Kind::diagonal    ? "diagonal"
                                                                               : "fixed distance";
    std::printf("display    %s\n", display);
    std::string presets;
    for (const auto& [name, text] : scene.presets) presets += (presets.empty() ? "" : ", ") + name;
    std::printf("presets    %s\n", presets.empty() ? "none" : presets.c_str());
    std::printf("dropped    %lld zero-area triangles\n",
                static_cast<long long>(scene.load_stats.zero_area_triangles_dropped));
    const SceneLoadStats& stats = scene.load_stats;
    if (stats.points_ignored > 0 || stats.lines_ignored > 0)
        std::printf("ignored    %lld points, %lld lines (triangles only)\n",
                    static_cast<long long>(stats.points_ignored),
                    static_cast<long long>(stats.lines_ignored));
    std::printf(
        "repaired   %lld polygons triangulated (%lld concave, ear-clipped), %lld "
        "triangles without normals\n",
        static_cast<long long>(stats.polygons_triangulated),
        static_cast<long long>(stats.concave_polygons),
        static_cast<long long>(stats.normals_generated));
    for (const std::string& d : stats.defaulted) std::printf("defaulted  %s\n", d.c_str());
    for (const std::string& u : stats.unsupported) std::printf("unsupported %s\n", u.c_str());
    for (const std::string& w : stats.warnings) std::printf("warning    %s\n", w.c_str());
}

}  // namespace

int run_scene_info(const SceneInfoOptions& o) {
    const Scene scene = load_cli_scene(o.scene, /*report=*/false);
    const Bounds bounds = scene_bounds(scene);
    const LightCounts lights = count_lights(scene);
    if (o.json)
        std::cout << scene_info_json(scene, bounds, lights)
                         .dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
                  << "\n";
    else
        print_scene_info(scene, bounds, lights);
    return exit_ok;
}

int run_scene_export(const SceneExportOptions& o) {
    const Scene scene = load_cli_scene(o.scene);
    export_scene(scene, o.directory);
    say(o.quiet, "exported " + scene.name + " (" + std::to_string(scene.triangle_count()) +
                     " triangles) to " + o.directory + "/scene.json");
    return exit_ok;
}

int run_scene_list() {
    for (const ProceduralSceneInfo& info : procedural_scenes())
        std::printf("%-14s %s\n", info.name.c_str(), info.description.c_str());
    return exit_ok;
}

}  // namespace fovref
