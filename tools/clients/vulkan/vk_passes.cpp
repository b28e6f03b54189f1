// vk_passes: fovref's passes as a Vulkan compute port (issue 30's client, its first passes): each
// pass reads a golden bundle's own input buffers, runs one compute shader and writes its output
// under the bundle's name, so that `fovref diff` checks that pass alone (an error cannot cascade):
//
//   fovref golden export textured-room-ckfov-gaze-lerp gold
//   vk_passes lerp gold out            # out/f000_final.pfm ..., out/vk_passes.json
//   fovref diff gold out --profile gpu-rt --require final
//
// Passes:
//   lerp         Lund's Gaussian lerp: input the buffer before it (taa_color with TAA, else
//                resolved), output the gaussian_lerp stage's buffer; the gaze from the case's
//                `gaze` parameter (default the screen centre); `gaze_track` is not read yet.
//   internal_aa  Meng's internal AA in the log-polar buffer: lp_color and lp_valid in,
//                lp_color_aa out.
// Options: --device lavapipe (the CPU device even when a GPU is there; default: a GPU first),
//          --bug (the shader variant with an injected porting bug, for the diff to catch).
// It depends on nothing of fovref's; the dump's vk_passes.json records the device and its float
// controls. Exit 0 on success, 2 on any error.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/clients/common/files.h"
#include "tools/clients/vulkan/vulkan_compute.h"

#ifndef FOVREF_VK_SHADER_DIR
#define FOVREF_VK_SHADER_DIR "."
#endif

using json = nlohmann::json;
using namespace fovref_client;

namespace {

// A buffer in fovref's rows (top row first) from a PFM file (bottom row first), and back.
std::vector<float> flip_rows(const std::vector<float>& rows, int width, int height, int channels) {
    std::vector<float> out(rows.size());
    const std::size_t row = static_cast<std::size_t>(width) * channels;
    for (int y = 0; y < height; ++y)
        std::memcpy(&out[static_cast<std::size_t>(height - 1 - y) * row],
                    &rows[static_cast<std::size_t>(y) * row], row * sizeof(float));
    return out;
}

// The buffer of `frame` named `name` in the manifest (null when absent).
const json* find_buffer(const json& frame, const std::string& name) {
    for (const json& b : frame.at("buffers"))
        if (b.at("name") == name) return &b;
    return nullptr;
}

struct LerpParameters {
    std::int32_t width, height, channels;
    float gaze_x, gaze_y, ramp_start, ramp_span;
};

// The buffer in fovref's rows (top row first) of the manifest's entry `b`.
PfmImage read_buffer(const std::string& bundle, const json& b) {
    PfmImage image = read_pfm(bundle + "/" + b.at("file").get<std::string>());
    image.bottom_up = flip_rows(image.bottom_up, image.width, image.height, image.channels);
    return image;  // now top row first
}

// Writes `rows` (top row first) as frame `frame`'s buffer `name`.
void write_buffer(const std::string& out, int frame, const std::string& name, int width, int height,
                  int channels, const std::vector<float>& rows) {
    char file[96];
    std::snprintf(file, sizeof file, "/f%03d_%s.pfm", frame, name.c_str());
    write_pfm(out + file, width, height, channels, flip_rows(rows, width, height, channels));
}

std::string shader(const std::string& name, bool bug) {
    return std::string(FOVREF_VK_SHADER_DIR) + "/" + name + (bug ? "_bug.spv" : ".spv");
}

// The internal AA pass on every frame that has lp_color_aa.
int run_internal_aa(VulkanCompute& vk, const json& manifest, const std::string& bundle,
                    const std::string& out, bool bug) {
    int frames = 0;
    for (const json& frame : manifest.at("frames")) {
        const json* colour = find_buffer(frame, "lp_color");
        const json* valid = find_buffer(frame, "lp_valid");
        if (!find_buffer(frame, "lp_color_aa") || !colour || !valid) continue;
        PfmImage c = read_buffer(bundle, *colour);
        PfmImage v = read_buffer(bundle, *valid);
        std::vector<float> result(c.bottom_up.size(), 0.0f);
        const std::int32_t push[3] = {c.width, c.height, c.channels};
        vk.dispatch(shader("internal_aa", bug), {&c.bottom_up, &v.bottom_up, &result}, push,
                    sizeof push, static_cast<std::uint32_t>(c.width + 7) / 8,
                    static_cast<std::uint32_t>(c.height + 7) / 8);
        write_buffer(out, frame.at("frame").get<int>(), "lp_color_aa", c.width, c.height,
                     c.channels, result);
        ++frames;
    }
    if (frames == 0)
        throw std::runtime_error("internal_aa: the bundle has no lp_color_aa (internal AA)");
    return frames;
}

// The lerp pass on every frame that has a gaussian_lerp stage.
int run_lerp(VulkanCompute& vk, const json& manifest, const std::string& bundle,
             const std::string& out, bool bug) {
    const json& c = manifest.at("case");
    const int width = c.at("width").get<int>(), height = c.at("height").get<int>();
    const json params = c.value("params", json::object());
    if (params.contains("gaze_track"))
        throw std::runtime_error("lerp: gaze_track is not read yet (give a case with `gaze`)");
    float gaze_x = 0.5f * static_cast<float>(width), gaze_y = 0.5f * static_cast<float>(height);
    if (params.contains("gaze") && !params["gaze"].get<std::string>().empty())
        std::sscanf(params["gaze"].get<std::string>().c_str(), "%f,%f", &gaze_x, &gaze_y);
    // The ramp: D / 6 to the farthest corner (computed once on the host, as a renderer would)
    const float diagonal = std::sqrt(static_cast<float>(width * width + height * height));
    float farthest = 0.0f;
    for (const float cx : {0.0f, static_cast<float>(width)})
        for (const float cy : {0.0f, static_cast<float>(height)})
            farthest = std::max(farthest, std::hypot(cx - gaze_x, cy - gaze_y));
    int frames = 0;
    for (const json& frame : manifest.at("frames")) {
        std::string output;
        for (const json& b : frame.at("buffers"))
            if (b.value("stage", "") == "gaussian_lerp") output = b.at("name");
        if (output.empty()) continue;
        const json* input = find_buffer(frame, "taa_color");
        if (!input) input = find_buffer(frame, "resolved");
        if (!input)
            throw std::runtime_error("lerp: the bundle has no resolved or taa_color buffer");
        PfmImage in = read_buffer(bundle, *input);
        std::vector<float> result(in.bottom_up.size(), 0.0f);
        const LerpParameters push{width,
                                  height,
                                  in.channels,
                                  gaze_x,
                                  gaze_y,
                                  diagonal / 6.0f,
                                  farthest - diagonal / 6.0f};
        vk.dispatch(shader("gaussian_lerp", bug), {&in.bottom_up, &result}, &push, sizeof push,
                    static_cast<std::uint32_t>(width + 7) / 8,
                    static_cast<std::uint32_t>(height + 7) / 8);
        write_buffer(out, frame.at("frame").get<int>(), output, width, height, in.channels, result);
        ++frames;
    }
    if (frames == 0) throw std::runtime_error("lerp: the bundle has no gaussian_lerp stage");
    return frames;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    DevicePreference preference = DevicePreference::any;
    bool bug = false;
    std::vector<std::string> positional;
    for (const std::string& a : args) {
        if (a == "--device=lavapipe" || a == "--lavapipe")
            preference = DevicePreference::lavapipe;
        else if (a == "--bug")
            bug = true;
        else
            positional.push_back(a);
    }
    if (positional.size() != 3 || (positional[0] != "lerp" && positional[0] != "internal_aa")) {
        std::fprintf(stderr,
                     "usage: vk_passes [--lavapipe] [--bug] lerp|internal_aa BUNDLE OUT_DIR\n"
                     "  runs one of fovref's passes as a Vulkan compute shader on a golden\n"
                     "  bundle's own inputs and writes its output for `fovref diff`\n");
        return 2;
    }
    const std::string pass = positional[0], bundle = positional[1], out = positional[2];
    try {
        const json manifest = json::parse(read_text(bundle + "/manifest.json"));
        VulkanCompute vk(preference);
        std::error_code ec;
        std::filesystem::create_directories(out, ec);
        if (ec) throw std::runtime_error(out + ": cannot create directory: " + ec.message());
        const bool lerp = pass == "lerp";
        const int frames = lerp ? run_lerp(vk, manifest, bundle, out, bug)
                                : run_internal_aa(vk, manifest, bundle, out, bug);
        const char* injected = lerp ? "pixel centre without +1/2" : "v clamped, not wrapped";
        const json record{{"pass", pass},
                          {"device", vk.device_description()},
                          {"float_controls", vk.float_controls()},
                          {"injected_bug", bug ? injected : ""},
                          {"frames", frames}};
        std::ofstream(out + "/vk_passes.json") << record.dump(1) << "\n";
        std::fprintf(stderr, "vk_passes: %s, %d frame(s) on %s\n", pass.c_str(), frames,
                     vk.device_description().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vk_passes: %s\n", e.what());
        return 2;
    }
    return 0;
}
