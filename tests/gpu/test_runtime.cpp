#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "effects/shadows/hard.h"
#include "isg/shaders/shadows_hard.spv.h"
#include "isg/shaders/shadows_isg_tiles.spv.h"
#include "shadows_hard_io.h"
#include "shadows_isg_io.h"
#include "support/gpu_fixture.h"

using isg::test::GpuTest;
namespace gpu = isg::gpu;

TEST(Devices, ListedAndRanked) {
  auto devs = gpu::list_devices();
  ASSERT_FALSE(devs.empty());
  for (const auto& d : devs) EXPECT_FALSE(d.name.empty());
}

TEST(Devices, BadSelectionsFailClearly) {
  gpu::ContextOptions o;
  o.device = "999";
  EXPECT_THROW(gpu::Context{o}, gpu::GpuError);
  o.device = "no-such-device-name";
  EXPECT_THROW(gpu::Context{o}, gpu::GpuError);
  // --require-gpu fails exactly when the best device is a CPU implementation.
  o = {};
  o.require_gpu = true;
  bool cpu_only = true;
  for (const auto& d : gpu::list_devices()) cpu_only = cpu_only && d.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  if (cpu_only) {
    EXPECT_THROW(gpu::Context{o}, gpu::GpuError);
  } else {
    EXPECT_NO_THROW(gpu::Context{o});
  }
}

TEST_F(GpuTest, BufferRoundTrip) {
  std::vector<float> v(1000);
  std::iota(v.begin(), v.end(), -3.5f);
  gpu::Buffer b(ctx(), v.size() * sizeof(float), "roundtrip");
  b.upload(std::span<const float>(v));
  EXPECT_EQ(b.download_as<float>(v.size()), v);
  // Partial transfers at an offset.
  std::vector<float> part = {42.f, 43.f};
  b.upload(part.data(), 8, 40);
  auto back = b.download_as<float>(v.size());
  EXPECT_EQ(back[10], 42.f);
  EXPECT_EQ(back[11], 43.f);
  EXPECT_EQ(back[12], v[12]);
}

// The memory accounting behind `--timings`' "memory peak": a buffer counts while alive (at least
// its size: the driver may round up), staging counts apart, and the peak outlives the buffer.
TEST_F(GpuTest, MemoryUseFollowsAllocations) {
  const auto before = ctx().memory_use();
  const VkDeviceSize bytes = 3 << 20;
  {
    gpu::Buffer b(ctx(), bytes, "accounted");
    const auto during = ctx().memory_use();
    EXPECT_GE(during.device_now - before.device_now, bytes);
    EXPECT_LT(during.device_now - before.device_now, bytes + (1 << 20));
    EXPECT_GE(during.device_peak, during.device_now);
    std::vector<float> v(bytes / sizeof(float), 1.0f);
    b.upload(std::span<const float>(v));
    if (ctx().unified_memory()) {
      // Mapped device memory: the upload is a plain copy, no staging buffer at all.
      EXPECT_EQ(ctx().memory_use().staging_peak, before.staging_peak);
    } else {
      EXPECT_GE(ctx().memory_use().staging_peak, bytes);
    }
    EXPECT_EQ(ctx().memory_use().staging_now, before.staging_now);  // the staging copy is gone
    EXPECT_EQ(b.download_as<float>(v.size()), v);
  }
  const auto after = ctx().memory_use();
  EXPECT_EQ(after.device_now, before.device_now);
  EXPECT_GE(after.device_peak, before.device_now + bytes);
}

TEST_F(GpuTest, ImageRoundTrip) {
  const uint32_t w = 13, h = 7;
  std::vector<float> v(w * h * 4);
  std::iota(v.begin(), v.end(), 0.25f);
  gpu::Image img(ctx(), w, h, VK_FORMAT_R32G32B32A32_SFLOAT, "rgba");
  img.upload(v.data(), v.size() * sizeof(float));
  std::vector<float> back(v.size());
  img.download(back.data(), back.size() * sizeof(float));
  EXPECT_EQ(back, v);
}

// A buffer larger than the device's storage-buffer range (reflections.pack's refl.pack.* at
// 3840x2160 on lavapipe): bound whole as storage it fails clearly; bound in ranges within the
// limit (Binding::part), a pass writes exactly its range.
TEST_F(GpuTest, StorageRangesOfABufferOverTheDeviceLimit) {
  const auto& info = ctx().info();
  if (info.max_storage_buffer_range > (uint64_t(1) << 30)) GTEST_SKIP() << "storage range over 1 GiB";
  const VkDeviceSize min_align = std::max<uint64_t>(1, info.min_storage_buffer_offset_alignment);
  const VkDeviceSize align = std::max<VkDeviceSize>(16, min_align);
  const uint32_t w = 37, h = 19, n = w * h;
  // Room past the range for the whole tail range below.
  const VkDeviceSize big_bytes = info.max_storage_buffer_range + ((n * 4 + align - 1) / align + 4) * align;
  gpu::Buffer big(ctx(), big_bytes, "over the range");
  std::vector<float> v(n);
  std::iota(v.begin(), v.end(), 1.0f);
  gpu::Buffer in(ctx(), n * 4, "in");
  in.upload(std::span<const float>(v));
  gpu::Kernel copy(ctx(), "shadows.hard", isg_spv_shadows_hard, {gpu::Slot::buffer, gpu::Slot::buffer},
                   sizeof(isg::shaders::ShadowsHardPush), SHADOWS_HARD_LOCAL, SHADOWS_HARD_LOCAL);
  isg::shaders::ShadowsHardPush pc{w, h};
  // The first aligned offset wholly past the storage range.
  const VkDeviceSize at = (info.max_storage_buffer_range + 2 * align - 1) / align * align;
  {
    gpu::Sequence seq(ctx());
    EXPECT_THROW(seq.dispatch(copy, {gpu::Binding::of(in), gpu::Binding::of(big)}, pc, w, h, "whole"),
                 gpu::GpuError);
    if (min_align > 4) {  // a multiple of 4 bytes that the device does not allow
      EXPECT_THROW(seq.dispatch(copy, {gpu::Binding::of(in), gpu::Binding::part(big, min_align / 2, n * 4)},
                                pc, w, h, "misaligned"),
                   gpu::GpuError);
    }
    // An aligned offset whose range runs 4 bytes past the buffer's end.
    EXPECT_THROW(seq.dispatch(copy, {gpu::Binding::of(in), gpu::Binding::part(big, at, big_bytes - at + 4)},
                              pc, w, h, "past the end"),
                 gpu::GpuError);
  }
  // The range wholly past the storage range, bound to the buffer's end: the pass writes there
  // and nowhere else.
  gpu::Sequence seq(ctx());
  seq.dispatch(copy, {gpu::Binding::of(in), gpu::Binding::part(big, at, 0)}, pc, w, h, "tail");
  seq.submit();
  std::vector<float> back(n + 2);
  big.download(back.data(), back.size() * 4, at - 4);
  EXPECT_EQ(back[0], 0.0f);
  EXPECT_EQ(std::vector<float>(back.begin() + 1, back.end() - 1), v);
  EXPECT_EQ(back[n + 1], 0.0f);
}

TEST_F(GpuTest, HardShadowPassEqualsReferenceAndIsTimed) {
  const uint32_t w = 37, h = 19;  // not a multiple of the local size
  std::vector<float> shadow(w * h);
  for (size_t i = 0; i < shadow.size(); ++i) shadow[i] = float((i * 7919) % 13) / 12.0f;
  gpu::Buffer in(ctx(), shadow.size() * 4, "L.shadow"), out(ctx(), shadow.size() * 4, "L.softshadow");
  in.upload(std::span<const float>(shadow));
  isg::effects::ShadowsHardPass pass(ctx());
  gpu::Sequence seq(ctx());
  pass.record(seq, in, out, w, h, "shadows.hard[key]");
  auto t = seq.submit();
  EXPECT_EQ(out.download_as<float>(shadow.size()), isg::effects::shadows_hard_reference(shadow));
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].name, "shadows.hard[key]");
  EXPECT_GE(t[0].ms, 0.0);
  if (ctx().timestamps()) {
    EXPECT_GT(t[0].ms, 0.0);
  }
}

// Specialization constants: one pipeline per set of values, made on first use and shared after
// (a variant the validation layer rejects fails the fixture).
TEST_F(GpuTest, KernelVariantsMakeOnePipelinePerConstantSet) {
  auto variants = [&] {
    return gpu::KernelVariants(
        ctx(), "shadows.isg.tiles", isg_spv_shadows_isg_tiles,
        {gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels, gpu::Slot::texels,
         gpu::Slot::buffer, gpu::Slot::buffer},
        sizeof(isg::shaders::ShadowsIsgTilesPush), SHADOWS_ISG_TILE, SHADOWS_ISG_TILE);
  };
  gpu::KernelVariants v = variants();
  const size_t before = ctx().built_pipelines();
  const gpu::Kernel& a = v.at({0u});
  const gpu::Kernel& b = v.at({SHADOWS_ISG_HAS_POSITION});
  EXPECT_EQ(ctx().built_pipelines(), before + 2);
  EXPECT_NE(a.pipeline(), b.pipeline());
  EXPECT_EQ(&v.at({0u}), &a);
  gpu::KernelVariants w = variants();  // a second pass of the same shader shares the pipelines
  EXPECT_EQ(w.at({SHADOWS_ISG_HAS_POSITION}).pipeline(), b.pipeline());
  EXPECT_EQ(ctx().built_pipelines(), before + 2);
}

// The persistent pipeline cache: written when a context ends, read by the next one; a damaged
// file neither fails a run nor survives it.
TEST(PipelineCache, PersistsAcrossContextsAndSurvivesDamage) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("isg-pipeline-cache-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::string file;
  {
    gpu::ContextOptions o;
    o.pipeline_cache = dir.string();
    gpu::Context c(o);
    EXPECT_EQ(c.pipeline_cache_loaded_bytes(), 0u);
    isg::effects::ShadowsHardPass pass(c);  // compiles one pipeline through the cache
    file = c.pipeline_cache_file();
    EXPECT_EQ(fs::path(file).parent_path(), dir);
  }
  ASSERT_TRUE(fs::exists(file));
  const auto size = fs::file_size(file);
  EXPECT_GT(size, 16u);  // at least the header the driver checks
  {
    gpu::ContextOptions o;
    o.pipeline_cache = dir.string();
    gpu::Context c(o);
    EXPECT_EQ(c.pipeline_cache_loaded_bytes(), size);
  }
  {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << "not a pipeline cache";
    gpu::ContextOptions o;
    o.pipeline_cache = dir.string();
    gpu::Context c(o);
    isg::effects::ShadowsHardPass pass(c);
  }
  EXPECT_NE(fs::file_size(file), std::string("not a pipeline cache").size());
  fs::remove_all(dir);
}

// Buffers start at zero unless told an upload fills them; partial transfers land at their
// offset on both transfer paths (mapped and staged).
TEST_F(GpuTest, BufferInitAndPartialTransfers) {
  gpu::Buffer z(ctx(), 64 * sizeof(float), "zeroed");
  EXPECT_EQ(z.download_as<float>(64), std::vector<float>(64, 0.0f));
  gpu::Buffer u(ctx(), 64 * sizeof(float), "filled", gpu::Buffer::Init::none);
  std::vector<float> v(64);
  std::iota(v.begin(), v.end(), 1.0f);
  u.upload(std::span<const float>(v));
  std::vector<float> tail(16);
  u.download(tail.data(), 16 * sizeof(float), 48 * sizeof(float));
  EXPECT_EQ(tail, std::vector<float>(v.begin() + 48, v.end()));
}
