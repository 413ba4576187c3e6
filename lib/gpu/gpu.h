// Vulkan compute runtime: device, buffers, images, kernels, command sequences with timing.
// A handful of RAII owners (after Kompute's manager/tensor/algorithm/sequence); nothing here
// knows about effects. No vkDestroy* outside this folder.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <tuple>
#include <string>
#include <unordered_map>
#include <vector>

namespace isg::gpu {

struct GpuError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct DeviceInfo {
  uint32_t index = 0;
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  std::string type_name;  // "discrete", "integrated", "virtual", "cpu", "other"
  uint32_t api_version = 0;
  uint64_t max_storage_buffer_range = 0;
  uint64_t min_storage_buffer_offset_alignment = 1;
  uint32_t max_texel_buffer_elements = 0;
  uint32_t max_workgroup_count[3] = {0, 0, 0};
  uint32_t max_image_dimension_2d = 0;
  uint64_t device_local_bytes = 0;
  bool timestamps = false;
  bool float64 = false;  // shaderFloat64, enabled where present (VSSM's moments use it)
  uint32_t subgroup_size = 1;  // lanes of a subgroup in compute shaders
};

struct ContextOptions {
  // Empty: best device by type (discrete > integrated > virtual > cpu). A number picks that
  // index of `isg devices`; anything else matches a substring of the device name.
  std::string device;
  bool require_gpu = false;  // fail when the chosen device is a CPU implementation
  bool validation = false;   // Khronos validation layer + debug messenger
  bool float64 = true;       // use shaderFloat64 where the device has it (false: as if it had not)
  // Called for every validation/debug message (severity >= warning). The context counts
  // them too: tests fail on any.
  std::function<void(const std::string&)> on_message;
  // Folder of the persistent pipeline cache (one file per device, driver and cache UUID), so a
  // pipeline is compiled once per machine rather than once per process. Empty: no cache file
  // ($ISG_PIPELINE_CACHE, else $XDG_CACHE_HOME/isg, else ~/.cache/isg: default_pipeline_cache()).
  std::string pipeline_cache;
};

// The pipeline cache folder a user gets by default; "" when $ISG_PIPELINE_CACHE is "off" or no
// home folder is known.
std::string default_pipeline_cache();

// Lists physical devices without creating a logical device.
std::vector<DeviceInfo> list_devices();

class Context;

// A device-local storage buffer. On a device whose memory is the host's (lavapipe, integrated
// GPUs: Context::unified_memory) the buffer is mapped and host transfers are plain copies;
// elsewhere they go through a staging copy.
class Buffer {
 public:
  // `zero`: contents start at zero; false for buffers that an upload fills whole.
  enum class Init { zero, none };
  Buffer() = default;
  Buffer(Context& ctx, VkDeviceSize bytes, const std::string& debug_name, Init init = Init::zero);
  ~Buffer();
  Buffer(Buffer&& o) noexcept;
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  // Uploads `bytes` from offset 0 that `write` puts straight into the buffer's mapped memory
  // (unified memory) or into the staging copy: no intermediate host array.
  void upload_with(VkDeviceSize bytes, const std::function<void(void*)>& write);
  void download(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  template <class T>
  void upload(std::span<const T> v, VkDeviceSize offset = 0) {
    upload(v.data(), v.size_bytes(), offset);
  }
  template <class T>
  std::vector<T> download_as(size_t count) const {
    std::vector<T> v(count);
    download(v.data(), count * sizeof(T));
    return v;
  }

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }

 private:
  void release();
  Context* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;  // unified memory: the buffer's bytes, mapped for its life
  VkDeviceSize size_ = 0;
};

// A 2D storage image (r32f or rgba32f) in GENERAL layout, for passes that want texture-style
// addressing.
class Image {
 public:
  Image() = default;
  Image(Context& ctx, uint32_t width, uint32_t height, VkFormat format,
        const std::string& debug_name);
  ~Image();
  Image(Image&& o) noexcept;
  Image& operator=(Image&& o) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  void upload(const void* data, VkDeviceSize bytes);
  void download(void* data, VkDeviceSize bytes) const;
  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  VkDeviceSize bytes() const;

 private:
  void release();
  Context* ctx_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  uint32_t width_ = 0, height_ = 0;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
};

// What a kernel binds, in binding order: storage buffers, storage images, and read-only texel
// views of buffers (uniform texel buffers: `samplerBuffer` / `usamplerBuffer`, texelFetch).
// A gather reads its inputs through texel views: lavapipe fetches texels as vector gathers,
// where each storage-buffer load is a loop over the SIMD lanes, each component on its own
// (Mesa 22's llvmpipe; issue 18's measurements in docs/design.md). GPUs read both alike.
enum class Slot { buffer, image, texels };

struct Binding {
  const Buffer* buffer = nullptr;
  const Image* image = nullptr;
  VkFormat format = VK_FORMAT_UNDEFINED;  // Slot::texels: the texel format of the view
  // Slot::buffer: the bound range, from `offset` (a multiple of the device's
  // minStorageBufferOffsetAlignment), `bytes` long (0: to the end).
  VkDeviceSize offset = 0, bytes = 0;
  static Binding of(const Buffer& b) { return Binding{&b, nullptr}; }
  static Binding part(const Buffer& b, VkDeviceSize offset, VkDeviceSize bytes) {
    return Binding{&b, nullptr, VK_FORMAT_UNDEFINED, offset, bytes};
  }
  static Binding of(const Image& i) { return Binding{nullptr, &i}; }
  // A texel view of the whole buffer (its size a multiple of the format's texel).
  static Binding texels(const Buffer& b, VkFormat f) { return Binding{&b, nullptr, f}; }
  static Binding floats(const Buffer& b) { return texels(b, VK_FORMAT_R32_SFLOAT); }
  static Binding float4s(const Buffer& b) { return texels(b, VK_FORMAT_R32G32B32A32_SFLOAT); }
};

// A compute pipeline from embedded SPIR-V, its layout (one descriptor set, `slots` in binding
// order) and push-constant block.
// A compiled compute pipeline, shared by every Kernel of the same SPIR-V, slots and push
// constants made on one Context: the context builds it once and keeps it for its life, so a
// pass object made per frame or per tile costs no pipeline creation (a runner lives for the job).
struct Pipeline {
  VkDevice device = VK_NULL_HANDLE;
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  Pipeline() = default;
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;
  ~Pipeline();
};

// `constants`: the shader's specialization constants, constant_id k = constants[k] (32-bit
// each). A setting that chooses between code paths is one: the driver compiles only the path
// taken. On lavapipe that is what makes it cost nothing, since llvmpipe (Mesa 22) executes both
// sides of every branch under a lane mask. Only a loop's further iterations are skipped. Issue
// 18's measurements are in docs/design.md.
class Kernel {
 public:
  Kernel(Context& ctx, std::string name, std::span<const uint32_t> spirv,
         std::vector<Slot> slots, uint32_t push_bytes, uint32_t local_x, uint32_t local_y,
         const std::vector<uint32_t>& constants = {});
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  const std::string& name() const { return name_; }
  uint32_t local_x() const { return local_x_; }
  uint32_t local_y() const { return local_y_; }
  uint32_t push_bytes() const { return push_bytes_; }
  const std::vector<Slot>& slots() const { return slots_; }
  VkPipeline pipeline() const { return p_->pipeline; }
  VkPipelineLayout layout() const { return p_->layout; }
  VkDescriptorSetLayout set_layout() const { return p_->set_layout; }

 private:
  std::string name_;
  std::vector<Slot> slots_;
  uint32_t push_bytes_, local_x_, local_y_;
  std::shared_ptr<const Pipeline> p_;
};

// The kernels of one SPIR-V, one per value of its specialization constants, each made on first
// use (the Context shares their pipelines).
class KernelVariants {
 public:
  KernelVariants(Context& ctx, std::string name, std::span<const uint32_t> spirv,
                 std::vector<Slot> slots, uint32_t push_bytes, uint32_t local_x,
                 uint32_t local_y)
      : ctx_(ctx), name_(std::move(name)), spirv_(spirv), slots_(std::move(slots)),
        push_bytes_(push_bytes), local_x_(local_x), local_y_(local_y) {}
  const Kernel& at(const std::vector<uint32_t>& constants);

 private:
  Context& ctx_;
  std::string name_;
  std::span<const uint32_t> spirv_;
  std::vector<Slot> slots_;
  uint32_t push_bytes_, local_x_, local_y_;
  std::map<std::vector<uint32_t>, std::unique_ptr<Kernel>> made_;
};

struct PassTime {
  std::string name;
  double ms = 0.0;
};

// Records dispatches into one command buffer, each bracketed by timestamps and followed by a
// compute->compute barrier; submit() runs them and reads back per-pass GPU time.
class Sequence {
 public:
  explicit Sequence(Context& ctx);
  ~Sequence();
  Sequence(const Sequence&) = delete;
  Sequence& operator=(const Sequence&) = delete;

  // `label` names the pass in timings; groups cover width x height with the kernel's local size.
  void dispatch(const Kernel& k, const std::vector<Binding>& bindings, const void* push,
                uint32_t width, uint32_t height, const std::string& label = {});
  template <class P>
  void dispatch(const Kernel& k, const std::vector<Binding>& bindings, const P& push,
                uint32_t width, uint32_t height, const std::string& label = {}) {
    static_assert(std::is_trivially_copyable_v<P>);
    if (sizeof(P) != k.push_bytes()) throw GpuError("push constant size mismatch for " + k.name());
    dispatch(k, bindings, static_cast<const void*>(&push), width, height, label);
  }
  // The same with the workgroup counts read on the device from `args` at `offset` (a
  // VkDispatchIndirectCommand an earlier pass wrote: e.g. only the tiles that need the work).
  template <class P>
  void dispatch_indirect(const Kernel& k, const std::vector<Binding>& bindings, const P& push,
                         const Buffer& args, VkDeviceSize offset, const std::string& label = {}) {
    static_assert(std::is_trivially_copyable_v<P>);
    if (sizeof(P) != k.push_bytes()) throw GpuError("push constant size mismatch for " + k.name());
    record(k, bindings, &push, label, [&](VkCommandBuffer cmd) {
      vkCmdDispatchIndirect(cmd, args.handle(), offset);
    });
  }
  // Copies the first `bytes` of `src` into `dst`, timed as `label`.
  void copy(const Buffer& src, const Buffer& dst, VkDeviceSize bytes, const std::string& label);
  // Submits, waits, and returns the GPU time of each dispatch (empty names merged by kernel).
  std::vector<PassTime> submit();

 private:
  Context& ctx_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  std::vector<std::string> labels_;
  std::vector<VkBufferView> views_;  // texel views of the recorded dispatches, until submit()
  uint32_t max_passes_ = 256;
  bool recording_ = false;
  void begin();
  void release();
  // Binds k with its bindings and push constants, runs `work` between the pass's timestamps and
  // ends the pass with the barrier that makes its writes visible to the next pass.
  void record(const Kernel& k, const std::vector<Binding>& bindings, const void* push,
              const std::string& label, const std::function<void(VkCommandBuffer)>& work);
  uint32_t open_pass(const std::string& label);
  void close_pass(uint32_t q);
};

class Context {
 public:
  explicit Context(const ContextOptions& opt = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& info() const { return info_; }
  VkDevice device() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkQueue queue() const { return queue_; }
  VkCommandPool command_pool() const { return cmd_pool_; }
  VkPipelineCache pipeline_cache() const { return pipeline_cache_; }
  // The cache file, and how many bytes it held when the context started ("" / 0: none).
  const std::string& pipeline_cache_file() const { return cache_file_; }
  size_t pipeline_cache_loaded_bytes() const { return cache_loaded_bytes_; }
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags props) const;
  // Device memory is host memory (a CPU device or an integrated GPU with a device-local,
  // host-visible, coherent type): buffers are mapped and transfers skip the staging copy.
  bool unified_memory() const { return unified_memory_; }
  double timestamp_period_ns() const { return timestamp_period_ns_; }
  bool timestamps() const { return info_.timestamps; }

  // Number of validation/debug messages seen so far (warnings and errors).
  size_t message_count() const { return messages_.size(); }
  const std::vector<std::string>& messages() const { return messages_; }

  void set_debug_name(VkObjectType type, uint64_t handle, const std::string& name) const;
  // Every vkAllocateMemory and vkFreeMemory goes through these two, so the memory a run holds is
  // known: `props` with HOST_VISIBLE counts as staging, anything else as device memory.
  VkDeviceMemory allocate_memory(const VkMemoryRequirements& req, VkMemoryPropertyFlags props,
                                 const std::string& what);
  void free_memory(VkDeviceMemory memory);
  struct MemoryUse {
    VkDeviceSize device_now = 0, device_peak = 0;    // device-local buffers and images
    VkDeviceSize staging_now = 0, staging_peak = 0;  // host-visible transfer buffers
  };
  const MemoryUse& memory_use() const { return memory_use_; }

  // Runs `record` in a one-shot command buffer and waits for it.
  void run_once(const std::function<void(VkCommandBuffer)>& record);

  // Called from the debug messenger (public for the C callback).
  void on_message(const char* text);

  // The pipeline of this SPIR-V with these slots and push constants: built on first use, then
  // shared (Kernel's constructor); `built_pipelines` counts the builds.
  std::shared_ptr<const Pipeline> pipeline(const std::string& name, std::span<const uint32_t> spirv,
                                           const std::vector<Slot>& slots, uint32_t push_bytes,
                                           const std::vector<uint32_t>& constants = {});
  size_t built_pipelines() const { return pipelines_.size(); }

 private:
  std::map<std::tuple<const uint32_t*, size_t, std::vector<Slot>, uint32_t, std::vector<uint32_t>>,
           std::shared_ptr<const Pipeline>>
      pipelines_;
  void release();
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool cmd_pool_ = VK_NULL_HANDLE;
  VkPipelineCache pipeline_cache_ = VK_NULL_HANDLE;
  std::string cache_file_;
  size_t cache_loaded_bytes_ = 0;
  std::vector<char> cache_loaded_;  // the file as read: unchanged data is not written back
  void open_pipeline_cache(const std::string& folder);
  void save_pipeline_cache();
  DeviceInfo info_;
  double timestamp_period_ns_ = 1.0;
  bool unified_memory_ = false;
  bool debug_utils_ = false;
  PFN_vkSetDebugUtilsObjectNameEXT set_name_ = nullptr;
  std::vector<std::string> messages_;
  std::function<void(const std::string&)> user_callback_;
  std::unordered_map<VkDeviceMemory, std::pair<VkDeviceSize, bool>> allocations_;  // size, staging
  MemoryUse memory_use_;
};

void check(VkResult r, const char* what);

}  // namespace isg::gpu
