#include "tools/clients/vulkan/pass.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#ifndef FOVREF_VK_SHADER_DIR
#define FOVREF_VK_SHADER_DIR "."
#endif

namespace fovref_client {

namespace {

// A PFM's rows (bottom row first) in fovref's order (top row first), and back: the same swap.
std::vector<float> flip_rows(const std::vector<float>& rows, int width, int height, int channels) {
    std::vector<float> out(rows.size());
    const std::size_t row = static_cast<std::size_t>(width) * channels;
    for (int y = 0; y < height; ++y)
        std::memcpy(&out[static_cast<std::size_t>(height - 1 - y) * row],
                    &rows[static_cast<std::size_t>(y) * row], row * sizeof(float));
    return out;
}

const json* find_buffer(const json& frame, const std::string& name) {
    for (const json& b : frame.at("buffers"))
        if (b.at("name") == name) return &b;
    return nullptr;
}

std::vector<Pass>& registry() {
    static std::vector<Pass> passes;
    return passes;
}

}  // namespace

std::string PassContext::shader(const std::string& name) const {
    return std::string(FOVREF_VK_SHADER_DIR) + "/" + name + (bug ? "_bug.spv" : ".spv");
}

void PassContext::dispatch(const std::string& shader_name, const std::vector<HostBuffer>& buffers,
                           const void* push, std::uint32_t push_size, std::uint32_t groups_x,
                           std::uint32_t groups_y, std::uint32_t groups_z) {
    vk.dispatch(shader(shader_name), buffers, push, push_size, groups_x, groups_y, groups_z);
    device_ms += vk.last_run_ms();
    ++dispatches;
}

std::string PassContext::param(const std::string& key, const std::string& fallback) const {
    const json& c = manifest.at("case");
    if (!c.contains("params") || !c.at("params").contains(key)) return fallback;
    const json& v = c.at("params").at(key);
    return v.is_string() ? v.get<std::string>() : v.dump();
}

float PassContext::float_param(const std::string& key, const std::string& fallback) const {
    const std::string text = param(key, fallback);
    char* end = nullptr;
    const float value = std::strtof(text.c_str(), &end);
    if (text.empty() || *end != '\0')
        throw std::runtime_error("parameter " + key + " '" + text + "' is not a number");
    return value;
}

int PassContext::each_frame(
    const std::string& stage,
    const std::function<void(const json& frame, const std::string& output)>& run,
    const std::string& none) {
    int frames = 0;
    for (const json& frame : manifest.at("frames")) {
        const std::string output = output_of(frame, stage);
        if (output.empty()) continue;
        const double before = device_ms;
        run(frame, output);
        notes["frame_ms"][std::to_string(frame.at("frame").get<int>())] = device_ms - before;
        ++frames;
    }
    if (frames == 0) throw std::runtime_error(none);
    return frames;
}

const json* PassContext::previous_frame(const json& frame) const {
    const int index = frame.at("frame").get<int>();
    if (index == 0) return nullptr;
    for (const json& f : manifest.at("frames"))
        if (f.at("frame").get<int>() == index - 1) return &f;
    throw std::runtime_error("frame " + std::to_string(index) + " needs frame " +
                             std::to_string(index - 1) +
                             " (its history), which the bundle does not hold");
}

int PassContext::width() const { return manifest.at("case").at("width").get<int>(); }
int PassContext::height() const { return manifest.at("case").at("height").get<int>(); }

bool PassContext::has(const json& frame, const std::string& name) {
    return find_buffer(frame, name) != nullptr;
}

std::string PassContext::output_of(const json& frame, const std::string& stage) {
    for (const json& b : frame.at("buffers"))
        if (b.value("stage", "") == stage) return b.at("name").get<std::string>();
    return "";
}

Image PassContext::read(const json& frame, const std::string& name) const {
    const json* b = find_buffer(frame, name);
    if (!b)
        throw std::runtime_error("frame " + std::to_string(frame.at("frame").get<int>()) + " of " +
                                 bundle + " has no buffer " + name);
    if (b->contains("raw_file")) {  // 2 or more than 3 channels (golden export --raw-copies)
        Image image{b->at("width").get<int>(),
                    b->at("height").get<int>(),
                    b->at("channels").get<int>(),
                    {}};
        image.data =
            read_binary32(bundle + "/" + b->at("raw_file").get<std::string>(),
                          static_cast<std::size_t>(image.width) * image.height * image.channels);
        return image;
    }
    const int channels = b->at("channels").get<int>();
    if (channels != 1 && channels != 3)
        throw std::runtime_error(bundle + ": buffer " + name + " has " + std::to_string(channels) +
                                 " channels, stored as EXR: export the bundle with "
                                 "`fovref golden export --raw-copies`");
    PfmImage pfm = read_pfm(bundle + "/" + b->at("file").get<std::string>());
    return {pfm.width, pfm.height, pfm.channels,
            flip_rows(pfm.bottom_up, pfm.width, pfm.height, pfm.channels)};
}

void PassContext::write(int frame, const std::string& name, const Image& image) const {
    char file[128];
    const bool pfm = image.channels == 1 || image.channels == 3;
    std::snprintf(file, sizeof file, "/f%03d_%s.%s", frame, name.c_str(), pfm ? "pfm" : "f32");
    if (pfm)
        write_pfm(out + file, image.width, image.height, image.channels,
                  flip_rows(image.data, image.width, image.height, image.channels));
    else  // raw binary32, top row first: `fovref diff` takes the size from the golden
        write_binary32(out + file, image.data);
}

void PassContext::require_bmfr_block_32(const std::string& pass) const {
    const std::string block = param("bmfr_block", "32");
    if (block != "32")
        throw std::runtime_error(pass + ": bmfr_block=" + block +
                                 " is not ported (the shaders fit 32 x 32 blocks)");
}

void PassContext::write_resolve_decisions(int frame, const std::vector<float>& decisions,
                                          int levels) const {
    const std::size_t pixels = decisions.size() / 4;
    Image tap{width(), height(), 2, std::vector<float>(pixels * 2)};
    Image level{width(), height(), levels, std::vector<float>(pixels * levels)};
    for (std::size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 2; ++c) tap.data[p * 2 + c] = decisions[p * 4 + c];
        for (int c = 0; c < levels; ++c) level.data[p * levels + c] = decisions[p * 4 + 2 + c];
    }
    write(frame, "resolve_tap", tap);
    if (levels > 0) write(frame, "resolve_mip_level", level);
}

bool register_pass(const Pass& pass) {
    registry().push_back(pass);
    return true;
}

std::vector<Pass> registered_passes() {
    std::vector<Pass> passes = registry();
    std::sort(passes.begin(), passes.end(),
              [](const Pass& a, const Pass& b) { return a.name < b.name; });
    return passes;
}

}  // namespace fovref_client
