#include <cstring>
#include <utility>

#include "gpu/gpu.h"

namespace isg::gpu {

namespace {

// A host-visible staging buffer, alive for one transfer.
struct Staging {
  Context& ctx;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;

  Staging(Context& c, VkDeviceSize bytes) : ctx(c) {
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = bytes;
    bi.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(ctx.device(), &bi, nullptr, &buffer), "vkCreateBuffer(staging)");
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(ctx.device(), buffer, &req);
    try {
      memory = ctx.allocate_memory(
          req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
          "a staging buffer");
    } catch (...) {
      vkDestroyBuffer(ctx.device(), buffer, nullptr);
      throw;
    }
    vkBindBufferMemory(ctx.device(), buffer, memory, 0);
    check(vkMapMemory(ctx.device(), memory, 0, bytes, 0, &mapped), "vkMapMemory");
  }
  ~Staging() {
    vkUnmapMemory(ctx.device(), memory);
    vkDestroyBuffer(ctx.device(), buffer, nullptr);
    ctx.free_memory(memory);
  }
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;
};

void transition(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       0, 0, nullptr, 0, nullptr, 1, &b);
}

void barrier_all(VkCommandBuffer cmd) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       0, 1, &mb, 0, nullptr, 0, nullptr);
}

}  // namespace

// ---- Buffer ----

Buffer::Buffer(Context& ctx, VkDeviceSize bytes, const std::string& debug_name, Init init)
    : ctx_(&ctx) {
  if (bytes == 0) bytes = 4;
  size_ = bytes;
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = bytes;
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
             VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
             VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(ctx.device(), &bi, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
  try {
    const VkMemoryPropertyFlags props =
        ctx.unified_memory() ? VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                   VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                             : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    memory_ = ctx.allocate_memory(req, props, debug_name);
    vkBindBufferMemory(ctx.device(), buffer_, memory_, 0);
    if (ctx.unified_memory()) {
      check(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
    }
  } catch (...) {
    release();
    throw;
  }
  ctx.set_debug_name(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(buffer_), debug_name);
  // Defined contents: zero, unless an upload is about to define them.
  if (init == Init::none) return;
  if (mapped_) {
    std::memset(mapped_, 0, size_);
    return;
  }
  ctx.run_once([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, buffer_, 0, VK_WHOLE_SIZE, 0);
    barrier_all(cmd);
  });
}

Buffer::~Buffer() { release(); }

void Buffer::release() {
  if (ctx_) {
    if (mapped_) vkUnmapMemory(ctx_->device(), memory_);
    if (buffer_) vkDestroyBuffer(ctx_->device(), buffer_, nullptr);
    if (memory_) ctx_->free_memory(memory_);
  }
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  size_ = 0;
}

Buffer::Buffer(Buffer&& o) noexcept
    : ctx_(o.ctx_), buffer_(std::exchange(o.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)), mapped_(std::exchange(o.mapped_, nullptr)),
      size_(std::exchange(o.size_, 0)) {}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    ctx_ = o.ctx_;
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    mapped_ = std::exchange(o.mapped_, nullptr);
    size_ = std::exchange(o.size_, 0);
  }
  return *this;
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw GpuError("Buffer::upload past the end");
  if (mapped_) {
    // Coherent memory: host writes before the next vkQueueSubmit are visible to it.
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  Staging st(*ctx_, bytes);
  std::memcpy(st.mapped, data, bytes);
  ctx_->run_once([&](VkCommandBuffer cmd) {
    VkBufferCopy c{0, offset, bytes};
    vkCmdCopyBuffer(cmd, st.buffer, buffer_, 1, &c);
    barrier_all(cmd);
  });
}

void Buffer::upload_with(VkDeviceSize bytes, const std::function<void(void*)>& write) {
  if (bytes == 0) return;
  if (bytes > size_) throw GpuError("Buffer::upload_with past the end");
  if (mapped_) {
    write(mapped_);
    return;
  }
  Staging st(*ctx_, bytes);
  write(st.mapped);
  ctx_->run_once([&](VkCommandBuffer cmd) {
    VkBufferCopy c{0, 0, bytes};
    vkCmdCopyBuffer(cmd, st.buffer, buffer_, 1, &c);
    barrier_all(cmd);
  });
}

void Buffer::download(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw GpuError("Buffer::download past the end");
  if (mapped_) {
    // The device's writes made visible to the host, then read in place.
    ctx_->run_once([](VkCommandBuffer cmd) {
      VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      mb.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
      mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                           &mb, 0, nullptr, 0, nullptr);
    });
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  Staging st(*ctx_, bytes);
  ctx_->run_once([&](VkCommandBuffer cmd) {
    barrier_all(cmd);
    VkBufferCopy c{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, st.buffer, 1, &c);
    barrier_all(cmd);
  });
  std::memcpy(data, st.mapped, bytes);
}

// ---- Image ----

namespace {
uint32_t texel_bytes(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R32_SFLOAT: return 4;
    case VK_FORMAT_R32G32B32A32_SFLOAT: return 16;
    default: throw GpuError("Image: unsupported format");
  }
}
}  // namespace

Image::Image(Context& ctx, uint32_t width, uint32_t height, VkFormat format,
             const std::string& debug_name)
    : ctx_(&ctx), width_(width), height_(height), format_(format) {
  texel_bytes(format);
  if (width == 0 || height == 0 || width > ctx.info().max_image_dimension_2d ||
      height > ctx.info().max_image_dimension_2d) {
    throw GpuError(debug_name + ": image size " + std::to_string(width) + "x" +
                   std::to_string(height) + " is beyond the device's limit (" +
                   std::to_string(ctx.info().max_image_dimension_2d) + ")");
  }
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {width, height, 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
             VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  ii.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(ctx.device(), &ii, nullptr, &image_), "vkCreateImage");
  VkMemoryRequirements req{};
  vkGetImageMemoryRequirements(ctx.device(), image_, &req);
  try {
    memory_ = ctx.allocate_memory(req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, debug_name);
    vkBindImageMemory(ctx.device(), image_, memory_, 0);
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image_;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    check(vkCreateImageView(ctx.device(), &vi, nullptr, &view_), "vkCreateImageView");
  } catch (...) {
    release();
    throw;
  }
  ctx.set_debug_name(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(image_), debug_name);
  ctx.run_once([&](VkCommandBuffer cmd) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = 0;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image_;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         0, 0, nullptr, 0, nullptr, 1, &b);
    VkClearColorValue zero{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    transition(cmd, image_, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    vkCmdClearColorImage(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &range);
    transition(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL);
  });
}

VkDeviceSize Image::bytes() const {
  return VkDeviceSize(width_) * height_ * texel_bytes(format_);
}

Image::~Image() { release(); }

void Image::release() {
  if (ctx_) {
    if (view_) vkDestroyImageView(ctx_->device(), view_, nullptr);
    if (image_) vkDestroyImage(ctx_->device(), image_, nullptr);
    if (memory_) ctx_->free_memory(memory_);
  }
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

Image::Image(Image&& o) noexcept
    : ctx_(o.ctx_), image_(std::exchange(o.image_, VK_NULL_HANDLE)),
      view_(std::exchange(o.view_, VK_NULL_HANDLE)),
      memory_(std::exchange(o.memory_, VK_NULL_HANDLE)), width_(o.width_), height_(o.height_),
      format_(o.format_) {}

Image& Image::operator=(Image&& o) noexcept {
  if (this != &o) {
    release();
    ctx_ = o.ctx_;
    image_ = std::exchange(o.image_, VK_NULL_HANDLE);
    view_ = std::exchange(o.view_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    width_ = o.width_;
    height_ = o.height_;
    format_ = o.format_;
  }
  return *this;
}

void Image::upload(const void* data, VkDeviceSize n) {
  if (n != bytes()) throw GpuError("Image::upload size mismatch");
  Staging st(*ctx_, n);
  std::memcpy(st.mapped, data, n);
  ctx_->run_once([&](VkCommandBuffer cmd) {
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    c.imageExtent = {width_, height_, 1};
    transition(cmd, image_, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    vkCmdCopyBufferToImage(cmd, st.buffer, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
    transition(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL);
  });
}

void Image::download(void* data, VkDeviceSize n) const {
  if (n != bytes()) throw GpuError("Image::download size mismatch");
  Staging st(*ctx_, n);
  ctx_->run_once([&](VkCommandBuffer cmd) {
    transition(cmd, image_, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy c{};
    c.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    c.imageExtent = {width_, height_, 1};
    vkCmdCopyImageToBuffer(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, st.buffer, 1, &c);
    transition(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL);
    barrier_all(cmd);
  });
  std::memcpy(data, st.mapped, n);
}

}  // namespace isg::gpu
