// vk_passes: fovref's passes as a Vulkan compute port (issue 30's client, first pass): each pass
// reads a golden bundle's own input buffers, runs one compute shader and writes its output under
// the bundle's name, so that `fovref diff` checks that pass alone (an error cannot cascade):
//
//   fovref golden export textured-room-ckfov-gaze-lerp gold
//   vk_passes lerp gold out            # out/f000_final.pfm ..., out/vk_passes.json
//   fovref diff gold out --profile gpu-rt --require final
//
// Passes:
//   lerp   Lund's Gaussian lerp: input the buffer before it (taa_color with TAA, else resolved),
//          output the gaussian_lerp stage's buffer; the gaze from the case's `gaze` parameter
//          (default the screen centre); `gaze_track` is not read yet.
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
        const PfmImage in = read_pfm(bundle + "/" + input->at("file").get<std::string>());
        std::vector<float> source = flip_rows(in.bottom_up, in.width, in.height, in.channels);
        std::vector<float> result(source.size(), 0.0f);
        const LerpParameters push{width,
                                  height,
                                  in.channels,
                                  gaze_x,
                                  gaze_y,
                                  diagonal / 6.0f,
                                  farthest - diagonal / 6.0f};
        vk.dispatch(std::string(FOVREF_VK_SHADER_DIR) +
                        (bug ? "/gaussian_lerp_bug.spv" : "/gaussian_lerp.spv"),
                    {&source, &result}, &push, sizeof push, (width + 7) / 8, (height + 7) / 8);
        char name[64];
        std::snprintf(name, sizeof name, "/f%03d_%s.pfm", frame.at("frame").get<int>(),
                      output.c_str());
        write_pfm(out + name, width, height, in.channels,
                  flip_rows(result, width, height, in.channels));
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
    if (positional.size() != 3 || positional[0] != "lerp") {
        std::fprintf(stderr,
                     "usage: vk_passes [--lavapipe] [--bug] lerp BUNDLE OUT_DIR\n"
                     "  runs one of fovref's passes as a Vulkan compute shader on a golden\n"
                     "  bundle's own inputs and writes its output for `fovref diff`\n");
        return 2;
    }
    const std::string bundle = positional[1], out = positional[2];
    try {
        const json manifest = json::parse(read_text(bundle + "/manifest.json"));
        VulkanCompute vk(preference);
        std::error_code ec;
        std::filesystem::create_directories(out, ec);
        if (ec) throw std::runtime_error(out + ": cannot create directory: " + ec.message());
        const int frames = run_lerp(vk, manifest, bundle, out, bug);
        const json record{{"pass", "lerp"},
                          {"device", vk.device_description()},
                          {"float_controls", vk.float_controls()},
                          {"injected_bug", bug ? "pixel centre without +1/2" : ""},
                          {"frames", frames}};
        std::ofstream(out + "/vk_passes.json") << record.dump(1) << "\n";
        std::fprintf(stderr, "vk_passes: lerp, %d frame(s) on %s\n", frames,
                     vk.device_description().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vk_passes: %s\n", e.what());
        return 2;
    }
    return 0;
}
