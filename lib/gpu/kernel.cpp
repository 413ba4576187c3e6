#include <algorithm>
#include <map>

#include "gpu/gpu.h"

namespace isg::gpu {

namespace {

VkDescriptorType descriptor_type(Slot s) {
  switch (s) {
    case Slot::buffer: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case Slot::image: return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    case Slot::texels: return VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  }
  return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

uint32_t texel_bytes(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT: return 4;
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32_UINT: return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT: return 16;
    default: throw GpuError("texel view: unsupported format " + std::to_string(int(f)));
  }
}

}  // namespace

Kernel::Kernel(Context& ctx, std::string name, std::span<const uint32_t> spirv,
               std::vector<Slot> slots, uint32_t push_bytes, uint32_t local_x, uint32_t local_y,
               const std::vector<uint32_t>& constants)
    : name_(std::move(name)), slots_(std::move(slots)), push_bytes_(push_bytes),
      local_x_(local_x), local_y_(local_y),
      p_(ctx.pipeline(name_, spirv, slots_, push_bytes, constants)) {}

const Kernel& KernelVariants::at(const std::vector<uint32_t>& constants) {
  auto it = made_.find(constants);
  if (it == made_.end())
    it = made_.emplace(constants, std::make_unique<Kernel>(ctx_, name_, spirv_, slots_, push_bytes_,
                                                           local_x_, local_y_, constants))
             .first;
  return *it->second;
}

Pipeline::~Pipeline() {
  if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
  if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
  if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
  if (module) vkDestroyShaderModule(device, module, nullptr);
}

std::shared_ptr<const Pipeline> Context::pipeline(const std::string& name,
                                                  std::span<const uint32_t> spirv,
                                                  const std::vector<Slot>& slots,
                                                  uint32_t push_bytes,
                                                  const std::vector<uint32_t>& constants) {
  auto key = std::make_tuple(spirv.data(), spirv.size(), slots, push_bytes, constants);
  auto it = pipelines_.find(key);
  if (it != pipelines_.end()) return it->second;
  auto p = std::make_shared<Pipeline>();
  p->device = device_;
  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = spirv.size_bytes();
  mi.pCode = spirv.data();
  check(vkCreateShaderModule(device_, &mi, nullptr, &p->module), "vkCreateShaderModule");

  std::vector<VkDescriptorSetLayoutBinding> b(slots.size());
  for (uint32_t i = 0; i < slots.size(); ++i) {
    b[i].binding = i;
    b[i].descriptorType = descriptor_type(slots[i]);
    b[i].descriptorCount = 1;
    b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  li.bindingCount = static_cast<uint32_t>(b.size());
  li.pBindings = b.data();
  check(vkCreateDescriptorSetLayout(device_, &li, nullptr, &p->set_layout), "descriptor set layout");

  VkPushConstantRange pr{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &p->set_layout;
  pli.pushConstantRangeCount = push_bytes ? 1 : 0;
  pli.pPushConstantRanges = &pr;
  check(vkCreatePipelineLayout(device_, &pli, nullptr, &p->layout), "pipeline layout");

  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = p->module;
  ci.stage.pName = "main";
  std::vector<VkSpecializationMapEntry> entries(constants.size());
  for (uint32_t k = 0; k < entries.size(); ++k)
    entries[k] = {k, uint32_t(k * sizeof(uint32_t)), sizeof(uint32_t)};
  VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(),
                            constants.size() * sizeof(uint32_t), constants.data()};
  if (!constants.empty()) ci.stage.pSpecializationInfo = &spec;
  ci.layout = p->layout;
  check(vkCreateComputePipelines(device_, pipeline_cache_, 1, &ci, nullptr, &p->pipeline),
        "vkCreateComputePipelines");
  set_debug_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(p->pipeline), name);
  set_debug_name(VK_OBJECT_TYPE_SHADER_MODULE, reinterpret_cast<uint64_t>(p->module), name);
  pipelines_.emplace(key, p);
  return p;
}

// ---- Sequence ----

Sequence::Sequence(Context& ctx) : ctx_(ctx) {
  VkDevice dev = ctx.device();
  VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, max_passes_ * 16},
                                   {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, max_passes_ * 8},
                                   {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, max_passes_ * 8}};
  VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pi.maxSets = max_passes_;
  pi.poolSizeCount = 3;
  pi.pPoolSizes = sizes;
  check(vkCreateDescriptorPool(dev, &pi, nullptr, &pool_), "vkCreateDescriptorPool");

  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = ctx.command_pool();
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkResult r = vkAllocateCommandBuffers(dev, &ai, &cmd_);
  if (r == VK_SUCCESS && ctx.timestamps()) {
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = 2 * max_passes_;
    r = vkCreateQueryPool(dev, &qi, nullptr, &queries_);
  }
  if (r != VK_SUCCESS) {
    release();
    check(r, "Sequence set-up");
  }
}

Sequence::~Sequence() { release(); }

void Sequence::release() {
  VkDevice dev = ctx_.device();
  for (VkBufferView v : views_) vkDestroyBufferView(dev, v, nullptr);
  views_.clear();
  if (queries_) vkDestroyQueryPool(dev, queries_, nullptr);
  if (cmd_) vkFreeCommandBuffers(dev, ctx_.command_pool(), 1, &cmd_);
  if (pool_) vkDestroyDescriptorPool(dev, pool_, nullptr);
  queries_ = VK_NULL_HANDLE;
  cmd_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

void Sequence::begin() {
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
  if (queries_) vkCmdResetQueryPool(cmd_, queries_, 0, 2 * max_passes_);
  recording_ = true;
}

void Sequence::dispatch(const Kernel& k, const std::vector<Binding>& bindings, const void* push,
                        uint32_t width, uint32_t height, const std::string& label) {
  uint32_t gx = (width + k.local_x() - 1) / k.local_x();
  uint32_t gy = (height + k.local_y() - 1) / k.local_y();
  const auto& lim = ctx_.info().max_workgroup_count;
  if (gx > lim[0] || gy > lim[1]) {
    throw GpuError(k.name() + ": " + std::to_string(width) + "x" + std::to_string(height) +
                   " needs more workgroups than the device allows");
  }
  record(k, bindings, push, label, [&](VkCommandBuffer cmd) { vkCmdDispatch(cmd, gx, gy, 1); });
}

uint32_t Sequence::open_pass(const std::string& label) {
  if (labels_.size() >= max_passes_) throw GpuError("Sequence: too many dispatches");
  if (!recording_) begin();
  uint32_t q = static_cast<uint32_t>(labels_.size());
  labels_.push_back(label);
  if (queries_) vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 2 * q);
  return q;
}

// Every pass ends with one barrier: its writes (shader or transfer) visible to the next pass's
// shader reads and writes, transfers and indirect arguments.
void Sequence::close_pass(uint32_t q) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                     VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT;
  const VkPipelineStageFlags stages =
      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(cmd_, stages, stages | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &mb, 0,
                       nullptr, 0, nullptr);
  if (queries_) {
    vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 2 * q + 1);
  }
}

void Sequence::copy(const Buffer& src, const Buffer& dst, VkDeviceSize bytes,
                    const std::string& label) {
  if (bytes > src.size() || bytes > dst.size()) {
    throw GpuError("Sequence::copy: " + label + ": " + std::to_string(bytes) +
                   " bytes exceed a buffer");
  }
  const uint32_t q = open_pass(label);
  VkBufferCopy c{0, 0, bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &c);
  close_pass(q);
}

void Sequence::record(const Kernel& k, const std::vector<Binding>& bindings, const void* push,
                      const std::string& label, const std::function<void(VkCommandBuffer)>& work) {
  if (bindings.size() != k.slots().size()) {
    throw GpuError(k.name() + ": expects " + std::to_string(k.slots().size()) + " bindings, got " +
                   std::to_string(bindings.size()));
  }
  if (labels_.size() >= max_passes_) throw GpuError("Sequence: too many dispatches");

  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool_;
  ai.descriptorSetCount = 1;
  VkDescriptorSetLayout sl = k.set_layout();
  ai.pSetLayouts = &sl;
  VkDescriptorSet set = VK_NULL_HANDLE;
  check(vkAllocateDescriptorSets(ctx_.device(), &ai, &set), "vkAllocateDescriptorSets");

  std::vector<VkDescriptorBufferInfo> bufs(bindings.size());
  std::vector<VkDescriptorImageInfo> imgs(bindings.size());
  std::vector<VkBufferView> views(bindings.size(), VK_NULL_HANDLE);
  std::vector<VkWriteDescriptorSet> writes(bindings.size());
  for (uint32_t i = 0; i < bindings.size(); ++i) {
    VkWriteDescriptorSet& w = writes[i];
    w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = i;
    w.descriptorCount = 1;
    if (k.slots()[i] == Slot::buffer) {
      const Binding& bi = bindings[i];
      if (!bi.buffer) throw GpuError(k.name() + ": binding " + std::to_string(i) + " needs a buffer");
      const VkDeviceSize size = bi.buffer->size();
      const VkDeviceSize range = bi.bytes ? bi.bytes : size - std::min(bi.offset, size);
      const auto& info = ctx_.info();
      if (bi.offset + range > size || range == 0 ||
          bi.offset % std::max<uint64_t>(1, info.min_storage_buffer_offset_alignment) != 0) {
        throw GpuError(k.name() + ": binding " + std::to_string(i) + ": bytes " +
                       std::to_string(bi.offset) + "+" + std::to_string(range) + " of " +
                       std::to_string(size) + " is not an aligned range of the buffer");
      }
      if (range > info.max_storage_buffer_range) {
        throw GpuError(k.name() + ": binding " + std::to_string(i) + ": " + std::to_string(range) +
                       " bytes exceeds the device's storage buffer range (" +
                       std::to_string(info.max_storage_buffer_range) + ")");
      }
      bufs[i] = {bi.buffer->handle(), bi.offset, range};
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      w.pBufferInfo = &bufs[i];
    } else if (k.slots()[i] == Slot::texels) {
      const Buffer* b = bindings[i].buffer;
      if (!b) throw GpuError(k.name() + ": binding " + std::to_string(i) + " needs a buffer");
      const uint32_t tb = texel_bytes(bindings[i].format);
      const VkDeviceSize texels = b->size() / tb;
      if (texels > ctx_.info().max_texel_buffer_elements) {
        throw GpuError(k.name() + ": binding " + std::to_string(i) + " holds " +
                       std::to_string(texels) + " texels, over the device's texel buffer limit (" +
                       std::to_string(ctx_.info().max_texel_buffer_elements) + ")");
      }
      VkBufferViewCreateInfo vi{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
      vi.buffer = b->handle();
      vi.format = bindings[i].format;
      vi.offset = 0;
      vi.range = texels * tb;
      check(vkCreateBufferView(ctx_.device(), &vi, nullptr, &views[i]), "vkCreateBufferView");
      views_.push_back(views[i]);
      w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
      w.pTexelBufferView = &views[i];
    } else {
      if (!bindings[i].image) throw GpuError(k.name() + ": binding " + std::to_string(i) + " needs an image");
      imgs[i] = {VK_NULL_HANDLE, bindings[i].image->view(), VK_IMAGE_LAYOUT_GENERAL};
      w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      w.pImageInfo = &imgs[i];
    }
  }
  vkUpdateDescriptorSets(ctx_.device(), static_cast<uint32_t>(writes.size()), writes.data(), 0,
                         nullptr);

  const uint32_t q = open_pass(label.empty() ? k.name() : label);
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline());
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout(), 0, 1, &set, 0, nullptr);
  if (k.push_bytes()) {
    vkCmdPushConstants(cmd_, k.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, k.push_bytes(), push);
  }
  work(cmd_);
  close_pass(q);
}

std::vector<PassTime> Sequence::submit() {
  std::vector<PassTime> out;
  if (!recording_) return out;
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  recording_ = false;
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  check(vkQueueSubmit(ctx_.queue(), 1, &si, VK_NULL_HANDLE), "vkQueueSubmit");
  check(vkQueueWaitIdle(ctx_.queue()), "vkQueueWaitIdle");

  uint32_t n = static_cast<uint32_t>(labels_.size());
  std::vector<uint64_t> ts(2 * n, 0);
  if (queries_ && n) {
    check(vkGetQueryPoolResults(ctx_.device(), queries_, 0, 2 * n, ts.size() * sizeof(uint64_t),
                                ts.data(), sizeof(uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
  }
  // Passes with the same label (e.g. one per light) add up.
  std::map<std::string, size_t> where;
  for (uint32_t i = 0; i < n; ++i) {
    double ms = queries_ ? double(ts[2 * i + 1] - ts[2 * i]) * ctx_.timestamp_period_ns() * 1e-6
                         : 0.0;
    auto it = where.find(labels_[i]);
    if (it == where.end()) {
      where[labels_[i]] = out.size();
      out.push_back({labels_[i], ms});
    } else {
      out[it->second].ms += ms;
    }
  }
  labels_.clear();
  vkResetDescriptorPool(ctx_.device(), pool_, 0);
  for (VkBufferView v : views_) vkDestroyBufferView(ctx_.device(), v, nullptr);
  views_.clear();
  vkResetCommandBuffer(cmd_, 0);
  return out;
}

}  // namespace isg::gpu
