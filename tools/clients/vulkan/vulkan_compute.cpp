#include "tools/clients/vulkan/vulkan_compute.h"

#include <chrono>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace fovref_client {

namespace {

// A Vulkan info structure with its type set and every other member zero.
template <class T>
T vk_struct(VkStructureType type) {
    T value{};
    value.sType = type;
    return value;
}

void check(VkResult result, const char* what) {
    if (result != VK_SUCCESS)
        throw std::runtime_error(std::string("Vulkan: ") + what + " failed (VkResult " +
                                 std::to_string(static_cast<int>(result)) + ")");
}

std::vector<std::uint32_t> read_spirv(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    if (bytes.empty() || bytes.size() % 4 != 0)
        throw std::runtime_error(path + ": missing or not a SPIR-V module");
    std::vector<std::uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), bytes.size());
    return words;
}

// The device's rank for DevicePreference::any (lower first); lavapipe wants the CPU.
int rank(VkPhysicalDeviceType type, DevicePreference preference) {
    if (preference == DevicePreference::lavapipe)
        return type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 0 : 9;
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
        default: return 4;
    }
}

}  // namespace

VulkanCompute::VulkanCompute(DevicePreference preference) {
    auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "fovref vk_passes";
    app.apiVersion = VK_API_VERSION_1_2;
    auto instance_info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    instance_info.pApplicationInfo = &app;
    check(vkCreateInstance(&instance_info, nullptr, &instance_), "vkCreateInstance");

    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance_, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance_, &count, devices.data());
    int best = 9;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        const int r = rank(p.deviceType, preference);
        if (r < best) best = r, physical_ = d;
    }
    if (physical_ == VK_NULL_HANDLE)
        throw std::runtime_error(preference == DevicePreference::lavapipe
                                     ? "Vulkan: no CPU device (Mesa's lavapipe: Debian's "
                                       "mesa-vulkan-drivers)"
                                     : "Vulkan: no device");

    auto floats = vk_struct<VkPhysicalDeviceFloatControlsProperties>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES);
    auto driver = vk_struct<VkPhysicalDeviceDriverProperties>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
    driver.pNext = &floats;
    auto properties =
        vk_struct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    properties.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physical_, &properties);
    const std::uint32_t api = properties.properties.apiVersion;
    description_ = std::string(properties.properties.deviceName) + ", " + driver.driverName + " " +
                   driver.driverInfo + ", Vulkan " + std::to_string(VK_VERSION_MAJOR(api)) + "." +
                   std::to_string(VK_VERSION_MINOR(api)) + "." +
                   std::to_string(VK_VERSION_PATCH(api));
    float_controls_ = std::string("binary32 denormals ") +
                      (floats.shaderDenormPreserveFloat32 ? "preservable" : "not preservable") +
                      ", round-to-nearest-even " +
                      (floats.shaderRoundingModeRTEFloat32 ? "available" : "not guaranteed");

    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, families.data());
    bool found = false;
    for (std::uint32_t k = 0; k < count && !found; ++k)
        if (families[k].queueFlags & VK_QUEUE_COMPUTE_BIT) queue_family_ = k, found = true;
    if (!found) throw std::runtime_error("Vulkan: the device has no compute queue");
    const float priority = 1.0f;
    auto queue_info =
        vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    queue_info.queueFamilyIndex = queue_family_;
    queue_info.queueCount = 1;
    queue_info.pQueuePriorities = &priority;
    auto device_info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue_info;
    check(vkCreateDevice(physical_, &device_info, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pool_info.queueFamilyIndex = queue_family_;
    check(vkCreateCommandPool(device_, &pool_info, nullptr, &pool_), "vkCreateCommandPool");
}

VulkanCompute::~VulkanCompute() {
    if (device_ != VK_NULL_HANDLE) {
        vkDestroyCommandPool(device_, pool_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

std::uint32_t VulkanCompute::memory_type(std::uint32_t bits, VkMemoryPropertyFlags flags) const {
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory);
    for (std::uint32_t k = 0; k < memory.memoryTypeCount; ++k)
        if ((bits & (1u << k)) && (memory.memoryTypes[k].propertyFlags & flags) == flags) return k;
    throw std::runtime_error("Vulkan: no host-visible, coherent memory");
}

// Host-visible, coherent storage buffers holding `data` (a renderer would keep device-local
// ones; the client uploads once per pass).
void VulkanCompute::upload(const std::vector<HostBuffer>& data, Buffers& b) const {
    const auto n = static_cast<std::uint32_t>(data.size());
    b.buffers.resize(n);
    b.memories.resize(n);
    for (std::uint32_t k = 0; k < n; ++k) {
        auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
        info.size = std::max<VkDeviceSize>(data[k].bytes, 4);
        info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        check(vkCreateBuffer(device_, &info, nullptr, &b.buffers[k]), "vkCreateBuffer");
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device_, b.buffers[k], &req);
        auto alloc = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
        alloc.allocationSize = req.size;
        alloc.memoryTypeIndex =
            memory_type(req.memoryTypeBits,
                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        check(vkAllocateMemory(device_, &alloc, nullptr, &b.memories[k]), "vkAllocateMemory");
        check(vkBindBufferMemory(device_, b.buffers[k], b.memories[k], 0), "vkBindBufferMemory");
        void* mapped = nullptr;
        check(vkMapMemory(device_, b.memories[k], 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
        if (data[k].bytes > 0) std::memcpy(mapped, data[k].data, data[k].bytes);
        vkUnmapMemory(device_, b.memories[k]);
    }
}

// The pipeline of the shader in `spirv_path`: n storage buffers, push constants, one set.
void VulkanCompute::create_pipeline(const std::string& spirv_path, const Buffers& b,
                                    std::uint32_t push_size, Pipeline& p) const {
    const auto n = static_cast<std::uint32_t>(b.buffers.size());
    std::vector<VkDescriptorSetLayoutBinding> bindings(n);
    for (std::uint32_t k = 0; k < n; ++k)
        bindings[k] = {k, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT,
                       nullptr};
    auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(
        VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    set_info.bindingCount = n;
    set_info.pBindings = bindings.data();
    check(vkCreateDescriptorSetLayout(device_, &set_info, nullptr, &p.set_layout),
          "vkCreateDescriptorSetLayout");
    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
    auto layout_info =
        vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &p.set_layout;
    layout_info.pushConstantRangeCount = push_size > 0 ? 1 : 0;
    layout_info.pPushConstantRanges = &range;
    check(vkCreatePipelineLayout(device_, &layout_info, nullptr, &p.layout),
          "vkCreatePipelineLayout");
    const std::vector<std::uint32_t> code = read_spirv(spirv_path);
    auto module_info =
        vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    module_info.codeSize = code.size() * 4;
    module_info.pCode = code.data();
    check(vkCreateShaderModule(device_, &module_info, nullptr, &p.module), "vkCreateShaderModule");
    auto pipeline_info =
        vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    pipeline_info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                           nullptr,
                           0,
                           VK_SHADER_STAGE_COMPUTE_BIT,
                           p.module,
                           "main",
                           nullptr};
    pipeline_info.layout = p.layout;
    check(
        vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &p.pipeline),
        "vkCreateComputePipelines");
    // The descriptor set
    const VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, n};
    auto pool_info =
        vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &pool_size;
    check(vkCreateDescriptorPool(device_, &pool_info, nullptr, &p.descriptor_pool),
          "vkCreateDescriptorPool");
    auto set_alloc =
        vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
    set_alloc.descriptorPool = p.descriptor_pool;
    set_alloc.descriptorSetCount = 1;
    set_alloc.pSetLayouts = &p.set_layout;
    check(vkAllocateDescriptorSets(device_, &set_alloc, &p.set), "vkAllocateDescriptorSets");
    std::vector<VkDescriptorBufferInfo> infos(n);
    std::vector<VkWriteDescriptorSet> writes(n);
    for (std::uint32_t k = 0; k < n; ++k) {
        infos[k] = {b.buffers[k], 0, VK_WHOLE_SIZE};
        writes[k] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, p.set,     k,      0, 1,
                     VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,      nullptr, &infos[k], nullptr};
    }
    vkUpdateDescriptorSets(device_, n, writes.data(), 0, nullptr);
}

// Records the dispatch, submits it and waits for it.
void VulkanCompute::run(const Pipeline& p, const void* push, std::uint32_t push_size,
                        std::uint32_t groups_x, std::uint32_t groups_y, std::uint32_t groups_z) {
    auto cb_info =
        vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cb_info.commandPool = pool_;
    cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cb_info.commandBufferCount = 1;
    VkCommandBuffer cb;
    check(vkAllocateCommandBuffers(device_, &cb_info, &cb), "vkAllocateCommandBuffers");
    auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cb, &begin), "vkBeginCommandBuffer");
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, 1, &p.set, 0, nullptr);
    if (push_size > 0)
        vkCmdPushConstants(cb, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size, push);
    vkCmdDispatch(cb, groups_x, groups_y, groups_z);
    check(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
    auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cb;
    const auto start = std::chrono::steady_clock::now();
    check(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
    check(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
    last_run_ms_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    vkFreeCommandBuffers(device_, pool_, 1, &cb);
}

// Copies the buffers back into `data` and releases them.
void VulkanCompute::download(const std::vector<HostBuffer>& data, Buffers& b) const {
    for (std::size_t k = 0; k < data.size(); ++k) {
        void* mapped = nullptr;
        check(vkMapMemory(device_, b.memories[k], 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
        if (data[k].bytes > 0) std::memcpy(data[k].data, mapped, data[k].bytes);
        vkUnmapMemory(device_, b.memories[k]);
        vkDestroyBuffer(device_, b.buffers[k], nullptr);
        vkFreeMemory(device_, b.memories[k], nullptr);
    }
}

void VulkanCompute::destroy(const Pipeline& p) const {
    vkDestroyDescriptorPool(device_, p.descriptor_pool, nullptr);
    vkDestroyPipeline(device_, p.pipeline, nullptr);
    vkDestroyShaderModule(device_, p.module, nullptr);
    vkDestroyPipelineLayout(device_, p.layout, nullptr);
    vkDestroyDescriptorSetLayout(device_, p.set_layout, nullptr);
}

void VulkanCompute::dispatch(const std::string& spirv_path, const std::vector<HostBuffer>& data,
                             const void* push, std::uint32_t push_size, std::uint32_t groups_x,
                             std::uint32_t groups_y, std::uint32_t groups_z) {
    Buffers buffers;
    upload(data, buffers);
    Pipeline pipeline;
    create_pipeline(spirv_path, buffers, push_size, pipeline);
    run(pipeline, push, push_size, groups_x, groups_y, groups_z);
    download(data, buffers);
    destroy(pipeline);
}

}  // namespace fovref_client
