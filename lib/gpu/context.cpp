#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "gpu/gpu.h"

namespace isg::gpu {

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) {
    throw GpuError(std::string("Vulkan: ") + what + " failed (VkResult " + std::to_string(r) +
                   ")");
  }
}

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

// Lower is preferred: discrete > integrated > virtual > cpu > other.
int type_rank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool has_instance_extension(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> ext(n);
  vkEnumerateInstanceExtensionProperties(nullptr, &n, ext.data());
  return std::any_of(ext.begin(), ext.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

// Compute queue family with timestamps if possible.
int compute_family(VkPhysicalDevice pd, bool* timestamps) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
  int best = -1;
  for (uint32_t i = 0; i < n; ++i) {
    if (!(fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    if (best < 0 || (fams[i].timestampValidBits > 0 && fams[best].timestampValidBits == 0)) {
      best = static_cast<int>(i);
    }
  }
  if (best >= 0 && timestamps) *timestamps = fams[best].timestampValidBits > 0;
  return best;
}

DeviceInfo describe(VkPhysicalDevice pd, uint32_t index) {
  VkPhysicalDeviceProperties p{};
  vkGetPhysicalDeviceProperties(pd, &p);
  VkPhysicalDeviceMemoryProperties mp{};
  vkGetPhysicalDeviceMemoryProperties(pd, &mp);
  DeviceInfo d;
  d.index = index;
  d.name = p.deviceName;
  d.type = p.deviceType;
  d.type_name = type_name(p.deviceType);
  d.api_version = p.apiVersion;
  d.max_storage_buffer_range = p.limits.maxStorageBufferRange;
  d.min_storage_buffer_offset_alignment = p.limits.minStorageBufferOffsetAlignment;
  d.max_texel_buffer_elements = p.limits.maxTexelBufferElements;
  for (int i = 0; i < 3; ++i) d.max_workgroup_count[i] = p.limits.maxComputeWorkGroupCount[i];
  d.max_image_dimension_2d = p.limits.maxImageDimension2D;
  for (uint32_t i = 0; i < mp.memoryHeapCount; ++i) {
    if (mp.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) {
      d.device_local_bytes = std::max<uint64_t>(d.device_local_bytes, mp.memoryHeaps[i].size);
    }
  }
  bool ts = false;
  compute_family(pd, &ts);
  d.timestamps = ts && p.limits.timestampComputeAndGraphics;
  VkPhysicalDeviceFeatures f{};
  vkGetPhysicalDeviceFeatures(pd, &f);
  d.float64 = f.shaderFloat64 == VK_TRUE;
  return d;
}

VkInstance make_instance(bool validation, bool debug_utils) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "isg";
  app.apiVersion = VK_API_VERSION_1_1;
  std::vector<const char*> layers;
  std::vector<const char*> exts;
  if (validation) layers.push_back(kValidationLayer);
  if (debug_utils) exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = static_cast<uint32_t>(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = static_cast<uint32_t>(exts.size());
  ci.ppEnabledExtensionNames = exts.data();
  VkInstance inst = VK_NULL_HANDLE;
  check(vkCreateInstance(&ci, nullptr, &inst), "vkCreateInstance");
  return inst;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance inst) {
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(inst, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> pds(n);
  check(vkEnumeratePhysicalDevices(inst, &n, pds.data()), "vkEnumeratePhysicalDevices");
  return pds;
}

VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT && data && data->pMessage) {
    static_cast<Context*>(user)->on_message(data->pMessage);
  }
  return VK_FALSE;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  VkInstance inst = make_instance(false, false);
  std::vector<DeviceInfo> out;
  try {
    auto pds = physical_devices(inst);
    for (uint32_t i = 0; i < pds.size(); ++i) out.push_back(describe(pds[i], i));
  } catch (...) {
    vkDestroyInstance(inst, nullptr);
    throw;
  }
  vkDestroyInstance(inst, nullptr);
  return out;
}

Context::Context(const ContextOptions& opt) : user_callback_(opt.on_message) {
  if (opt.validation && !has_layer(kValidationLayer)) {
    throw GpuError(std::string("validation requested but ") + kValidationLayer +
                   " is not installed (Debian package vulkan-validationlayers)");
  }
  debug_utils_ = has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  instance_ = make_instance(opt.validation, debug_utils_);
  try {
    if (debug_utils_ && opt.validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
      mi.pfnUserCallback = debug_callback;
      mi.pUserData = this;
      if (create) check(create(instance_, &mi, nullptr, &messenger_), "create debug messenger");
    }
    auto pds = physical_devices(instance_);
    if (pds.empty()) throw GpuError("no Vulkan device found (install mesa-vulkan-drivers)");
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < pds.size(); ++i) infos.push_back(describe(pds[i], i));

    int chosen = -1;
    if (opt.device.empty()) {
      for (uint32_t i = 0; i < infos.size(); ++i) {
        if (compute_family(pds[i], nullptr) < 0) continue;
        if (chosen < 0 || type_rank(infos[i].type) < type_rank(infos[chosen].type)) {
          chosen = static_cast<int>(i);
        }
      }
    } else if (std::all_of(opt.device.begin(), opt.device.end(), ::isdigit)) {
      int idx = std::stoi(opt.device);
      if (idx < 0 || idx >= static_cast<int>(infos.size())) {
        throw GpuError("--device " + opt.device + ": no such device index (see `isg devices`)");
      }
      chosen = idx;
    } else {
      for (uint32_t i = 0; i < infos.size(); ++i) {
        if (infos[i].name.find(opt.device) != std::string::npos) {
          chosen = static_cast<int>(i);
          break;
        }
      }
      if (chosen < 0) {
        throw GpuError("--device " + opt.device + ": no device name contains it (see `isg devices`)");
      }
    }
    if (chosen < 0) throw GpuError("no Vulkan device with a compute queue");
    info_ = infos[chosen];
    info_.float64 = info_.float64 && opt.float64;
    physical_ = pds[chosen];
    if (opt.require_gpu && info_.type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
      throw GpuError("--require-gpu: the only usable device is a CPU implementation (" +
                     info_.name + ")");
    }
    // Subgroup reductions (subgroupOr, subgroupMax, subgroupAdd) stand in for shared-memory
    // barriers where a pass only reduces (shadows.isg.tiles; the statistics of reflections.isg's
    // dispatches), and shuffles add the parts of shadows.isg's sums on GPUs: Vulkan 1.1 devices,
    // lavapipe included, have them.
    VkPhysicalDeviceSubgroupProperties sg{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &sg;
    constexpr VkSubgroupFeatureFlags kNeeded =
        VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT | VK_SUBGROUP_FEATURE_SHUFFLE_BIT;
    if (info_.api_version >= VK_API_VERSION_1_1) vkGetPhysicalDeviceProperties2(physical_, &p2);
    if (info_.api_version < VK_API_VERSION_1_1 ||
        !(sg.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
        (sg.supportedOperations & kNeeded) != kNeeded) {
      throw GpuError("device " + info_.name + " has no subgroup arithmetic and shuffles in compute " +
                     "(Vulkan 1.1), which isg needs");
    }
    info_.subgroup_size = sg.subgroupSize;
    bool ts = false;
    int fam = compute_family(physical_, &ts);
    if (fam < 0) throw GpuError("device " + info_.name + " has no compute queue");
    queue_family_ = static_cast<uint32_t>(fam);

    float prio = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = queue_family_;
    qi.queueCount = 1;
    qi.pQueuePriorities = &prio;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    VkPhysicalDeviceFeatures features{};
    features.shaderFloat64 = info_.float64 ? VK_TRUE : VK_FALSE;
    di.pEnabledFeatures = &features;
    check(vkCreateDevice(physical_, &di, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = queue_family_;
    check(vkCreateCommandPool(device_, &pi, nullptr, &cmd_pool_), "vkCreateCommandPool");

    VkPhysicalDeviceProperties p{};
    vkGetPhysicalDeviceProperties(physical_, &p);
    timestamp_period_ns_ = p.limits.timestampPeriod;
    if (info_.type == VK_PHYSICAL_DEVICE_TYPE_CPU || info_.type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU) {
      constexpr VkMemoryPropertyFlags kUnified = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT |
                                                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                 VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      VkPhysicalDeviceMemoryProperties mp{};
      vkGetPhysicalDeviceMemoryProperties(physical_, &mp);
      for (uint32_t i = 0; i < mp.memoryTypeCount; ++i)
        unified_memory_ = unified_memory_ || (mp.memoryTypes[i].propertyFlags & kUnified) == kUnified;
    }
    open_pipeline_cache(opt.pipeline_cache);
    if (debug_utils_) {
      set_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
          vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
    }
  } catch (...) {
    release();
    throw;
  }
}

Context::~Context() { release(); }

VkDeviceMemory Context::allocate_memory(const VkMemoryRequirements& req,
                                        VkMemoryPropertyFlags props, const std::string& what) {
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = memory_type(req.memoryTypeBits, props);
  VkDeviceMemory mem = VK_NULL_HANDLE;
  if (vkAllocateMemory(device_, &ai, nullptr, &mem) != VK_SUCCESS) {
    throw GpuError("out of GPU memory allocating " + std::to_string(req.size >> 20) + " MiB for " +
                   what);
  }
  // Mapped device-local memory (unified_memory) is the buffer itself, not staging.
  const bool staging = (props & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0 &&
                       (props & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) == 0;
  allocations_[mem] = {req.size, staging};
  auto& now = staging ? memory_use_.staging_now : memory_use_.device_now;
  auto& peak = staging ? memory_use_.staging_peak : memory_use_.device_peak;
  now += req.size;
  peak = std::max(peak, now);
  return mem;
}

void Context::free_memory(VkDeviceMemory memory) {
  const auto it = allocations_.find(memory);
  if (it != allocations_.end()) {
    (it->second.second ? memory_use_.staging_now : memory_use_.device_now) -= it->second.first;
    allocations_.erase(it);
  }
  vkFreeMemory(device_, memory, nullptr);
}

std::string default_pipeline_cache() {
  if (const char* e = std::getenv("ISG_PIPELINE_CACHE")) return std::string(e) == "off" ? "" : e;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::string(x) + "/isg";
  if (const char* h = std::getenv("HOME"); h && *h) return std::string(h) + "/.cache/isg";
  return "";
}

// The driver checks the header (vendor, device, pipelineCacheUUID) and starts empty on a
// mismatch; the file name carries them too so that several devices keep their own caches.
void Context::open_pipeline_cache(const std::string& folder) {
  std::vector<char> data;
  if (!folder.empty()) {
    VkPhysicalDeviceProperties p{};
    vkGetPhysicalDeviceProperties(physical_, &p);
    char uuid[2 * VK_UUID_SIZE + 1] = {};
    for (uint32_t i = 0; i < VK_UUID_SIZE; ++i) std::snprintf(uuid + 2 * i, 3, "%02x", p.pipelineCacheUUID[i]);
    cache_file_ = folder + "/pipelines-" + std::to_string(p.vendorID) + "-" +
                  std::to_string(p.deviceID) + "-" + std::to_string(p.driverVersion) + "-" + uuid + ".bin";
    std::error_code ec;
    const auto size = std::filesystem::file_size(cache_file_, ec);
    std::ifstream in(cache_file_, std::ios::binary);
    if (!ec && in && size < (uint64_t(1) << 30)) {
      data.resize(size);
      if (!in.read(data.data(), std::streamsize(size))) data.clear();
    }
    cache_loaded_bytes_ = data.size();
  }
  cache_loaded_ = data;
  VkPipelineCacheCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  ci.initialDataSize = data.size();
  ci.pInitialData = data.empty() ? nullptr : data.data();
  if (vkCreatePipelineCache(device_, &ci, nullptr, &pipeline_cache_) != VK_SUCCESS) {
    // A damaged file is no reason to fail a run: start empty and overwrite it on exit.
    ci.initialDataSize = 0;
    ci.pInitialData = nullptr;
    cache_loaded_bytes_ = 0;
    cache_loaded_.clear();
    check(vkCreatePipelineCache(device_, &ci, nullptr, &pipeline_cache_), "vkCreatePipelineCache");
  }
}

// Written to a temporary file and renamed, so concurrent processes (a farm node running
// several frames) never read a half-written cache; failures only cost the next run a compile.
void Context::save_pipeline_cache() {
  if (!pipeline_cache_ || cache_file_.empty()) return;
  size_t size = 0;
  if (vkGetPipelineCacheData(device_, pipeline_cache_, &size, nullptr) != VK_SUCCESS || size == 0) return;
  std::vector<char> data(size);
  if (vkGetPipelineCacheData(device_, pipeline_cache_, &size, data.data()) != VK_SUCCESS) return;
  data.resize(size);
  if (data == cache_loaded_) return;  // nothing new was compiled
  std::error_code ec;
  const std::filesystem::path file(cache_file_);
  std::filesystem::create_directories(file.parent_path(), ec);
  const auto tmp = file.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return;
    out.write(data.data(), std::streamsize(data.size()));
    if (!out) {
      std::filesystem::remove(tmp, ec);
      return;
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) std::filesystem::remove(tmp, ec);
}

void Context::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    pipelines_.clear();  // kernels still held elsewhere keep theirs until they go
    save_pipeline_cache();
    if (pipeline_cache_) vkDestroyPipelineCache(device_, pipeline_cache_, nullptr);
    pipeline_cache_ = VK_NULL_HANDLE;
    if (cmd_pool_) vkDestroyCommandPool(device_, cmd_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  device_ = VK_NULL_HANDLE;
  cmd_pool_ = VK_NULL_HANDLE;
  messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
}

void Context::on_message(const char* text) {
  messages_.emplace_back(text);
  if (user_callback_) user_callback_(text);
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags props) const {
  VkPhysicalDeviceMemoryProperties mp{};
  vkGetPhysicalDeviceMemoryProperties(physical_, &mp);
  for (uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
    if ((type_bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & props) == props) return i;
  }
  throw GpuError("no Vulkan memory type with the required properties");
}

void Context::set_debug_name(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!set_name_ || name.empty()) return;
  VkDebugUtilsObjectNameInfoEXT ni{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  ni.objectType = type;
  ni.objectHandle = handle;
  ni.pObjectName = name.c_str();
  set_name_(device_, &ni);
}

void Context::run_once(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = cmd_pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VkResult r = vkBeginCommandBuffer(cmd, &bi);
  if (r == VK_SUCCESS) {
    record(cmd);
    r = vkEndCommandBuffer(cmd);
  }
  if (r == VK_SUCCESS) {
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    r = vkQueueSubmit(queue_, 1, &si, VK_NULL_HANDLE);
    if (r == VK_SUCCESS) r = vkQueueWaitIdle(queue_);
  }
  vkFreeCommandBuffers(device_, cmd_pool_, 1, &cmd);
  check(r, "one-shot submit");
}

}  // namespace isg::gpu
