// What every pass of the Vulkan compute client (tools/clients/vulkan/) shares: the bundle it
// reads (a golden bundle's manifest and PFM buffers, in fovref's rows, top row first), the dump
// it writes (PFM files under the bundle's names, for `fovref diff`), and the registry the passes
// join. A pass lives in passes/<name>.cpp with its shaders in shaders/<name>*.comp, and joins
// the registry with
//
//   const bool registered = register_pass({"name", "what it computes", "its injected bug", run});
//
// Depends on nothing of fovref's.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tools/clients/common/files.h"
#include "tools/clients/vulkan/vulkan_compute.h"

namespace fovref_client {

using json = nlohmann::json;

/// One buffer in fovref's rows: element (x, y, c) at data[(y * width + x) * channels + c].
struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> data;
};

/// The state a pass runs with.
struct PassContext {
    VulkanCompute& vk;
    const json& manifest;    ///< the bundle's manifest.json
    std::string bundle;      ///< the bundle's directory
    std::string out;         ///< the dump's directory
    bool bug = false;        ///< run the shaders built with -DINJECT_BUG
    double device_ms = 0.0;  ///< the sum of the pass's dispatches' run times (VulkanCompute)
    int dispatches = 0;
    json notes = json::object();  ///< what the pass adds to port.json ("precise" use...)

    /// The SPIR-V file of shader `name` (shaders/<name>.comp), the bug variant under --bug.
    std::string shader(const std::string& name) const;
    /// vk.dispatch, adding its run time to device_ms.
    void dispatch(const std::string& shader_name, const std::vector<HostBuffer>& buffers,
                  const void* push, std::uint32_t push_size, std::uint32_t groups_x,
                  std::uint32_t groups_y, std::uint32_t groups_z = 1);

    /// The case's parameter `key` as the manifest states it, else `fallback` (the documented
    /// default: the manifest lists only the parameters a case sets).
    std::string param(const std::string& key, const std::string& fallback) const;
    /// The case's parameter `key` as a binary32 number, else `fallback` (the documented
    /// default, as text); throws std::runtime_error naming the parameter when it is not one.
    float float_param(const std::string& key, const std::string& fallback) const;
    int width() const;  ///< the case's screen size
    int height() const;
    /// The manifest's frames, in order.
    const json& frames() const { return manifest.at("frames"); }
    /// Buffer `name` of `frame` (a manifest entry) in fovref's rows; throws naming the buffer
    /// when the frame has none.
    Image read(const json& frame, const std::string& name) const;
    /// Whether `frame` has buffer `name`.
    static bool has(const json& frame, const std::string& name);
    /// The name of the buffer `stage` writes in `frame` ("" when none; the first when several).
    static std::string output_of(const json& frame, const std::string& stage);
    /// Runs `run(frame, output)` on every frame that has stage `stage` (output: the name of the
    /// buffer it writes, the first when several) and returns how many; each frame's device time
    /// goes to notes["frame_ms"]. Throws std::runtime_error(`none`) when no frame has the stage.
    int each_frame(const std::string& stage,
                   const std::function<void(const json& frame, const std::string& output)>& run,
                   const std::string& none);
    /// The frame before `frame` (its history), null for frame 0; throws naming both frames
    /// when the bundle does not hold it.
    const json* previous_frame(const json& frame) const;
    /// Writes `image` as frame `frame`'s buffer `name` of the dump.
    void write(int frame, const std::string& name, const Image& image) const;
    /// Throws std::runtime_error naming `pass` when the case's BMFR blocks are not the authors'
    /// 32 x 32 (bmfr_block=64: the BMFR shaders' workgroups and offsets are written for 32).
    void require_bmfr_block_32(const std::string& pass) const;
    /// Writes a resolve's decisions, `decisions` holding 4 values per screen pixel (i0, j0, then
    /// the levels), as frame `frame`'s resolve_tap (i0, j0) and, when `levels` > 0,
    /// resolve_mip_level (the next `levels` values).
    void write_resolve_decisions(int frame, const std::vector<float>& decisions, int levels) const;
};

struct Pass {
    std::string name;          ///< vk_passes' first argument
    std::string summary;       ///< one line for --help
    std::string injected_bug;  ///< what -DINJECT_BUG does, for the manifest and --help
    /// Runs the pass over the bundle; returns the number of frames it wrote; throws
    /// std::runtime_error with a message naming what is missing.
    int (*run)(PassContext& context);
};

/// Adds `pass` to the registry (called from a static initialiser in each passes/*.cpp).
bool register_pass(const Pass& pass);
/// Every registered pass, sorted by name.
std::vector<Pass> registered_passes();

/// Workgroups of `local` invocations covering `size`.
inline std::uint32_t groups(int size, int local) {
    return static_cast<std::uint32_t>((size + local - 1) / local);
}

}  // namespace fovref_client
