// The Vulkan side of fovref's compute client (tools/clients/vulkan/): one instance, one device
// with a compute queue, and one call that runs a compute shader over storage buffers. Written as
// a GPU engine would, with nothing of fovref's: the passes (vk_passes.cpp) upload a bundle's
// buffers, dispatch, read back and write PFM files that `fovref diff` checks.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fovref_client {

/// Which device to run on: the first GPU (discrete, then integrated, then virtual), else the CPU
/// (Mesa's lavapipe); `lavapipe` asks for the CPU device even when a GPU is there.
enum class DevicePreference { any, lavapipe };

/// Host memory bound as one storage buffer: uploaded before the dispatch, written back after.
struct HostBuffer {
    void* data;
    std::size_t bytes;
};
/// The whole of `v` as a HostBuffer (floats, packed binary16 pairs, BVH nodes...).
template <class T>
HostBuffer host(std::vector<T>& v) {
    return {v.data(), v.size() * sizeof(T)};
}

class VulkanCompute {
public:
    explicit VulkanCompute(DevicePreference preference);
    VulkanCompute(const VulkanCompute&) = delete;
    VulkanCompute& operator=(const VulkanCompute&) = delete;
    ~VulkanCompute();

    /// "llvmpipe (LLVM 15.0.6, 256 bits), Mesa 22.3.6, Vulkan 1.3.230": for the dump's manifest.
    std::string device_description() const { return description_; }
    /// Whether the device keeps the shaders' binary32 denormals and rounds to nearest even
    /// (VkPhysicalDeviceFloatControlsProperties), for the manifest.
    std::string float_controls() const { return float_controls_; }

    /// Runs the SPIR-V compute shader in `spirv_path` once: `buffers[k]` is bound as storage
    /// buffer k (read and written back in place), `push` (at most 128 bytes) as its push
    /// constants, over groups_x x groups_y x groups_z workgroups. Throws std::runtime_error.
    void dispatch(const std::string& spirv_path, const std::vector<HostBuffer>& buffers,
                  const void* push, std::uint32_t push_size, std::uint32_t groups_x,
                  std::uint32_t groups_y, std::uint32_t groups_z = 1);
    /// Milliseconds of the last dispatch's run on the device (submit to completion; not the
    /// upload, the pipeline's creation or the read-back), from the host's steady clock.
    double last_run_ms() const { return last_run_ms_; }

private:
    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queue_family_ = 0;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    std::string description_, float_controls_;
    double last_run_ms_ = 0.0;

    // dispatch's steps
    struct Buffers {
        std::vector<VkBuffer> buffers;
        std::vector<VkDeviceMemory> memories;
    };
    struct Pipeline {
        VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
        VkPipelineLayout layout = VK_NULL_HANDLE;
        VkShaderModule module = VK_NULL_HANDLE;
        VkPipeline pipeline = VK_NULL_HANDLE;
        VkDescriptorPool descriptor_pool = VK_NULL_HANDLE;
        VkDescriptorSet set = VK_NULL_HANDLE;
    };
    std::uint32_t memory_type(std::uint32_t bits, VkMemoryPropertyFlags flags) const;
    void upload(const std::vector<HostBuffer>& data, Buffers& buffers) const;
    void create_pipeline(const std::string& spirv_path, const Buffers& buffers,
                         std::uint32_t push_size, Pipeline& pipeline) const;
    void run(const Pipeline& pipeline, const void* push, std::uint32_t push_size,
             std::uint32_t groups_x, std::uint32_t groups_y, std::uint32_t groups_z);
    void download(const std::vector<HostBuffer>& data, Buffers& buffers) const;
    void destroy(const Pipeline& pipeline) const;
};

}  // namespace fovref_client
