// GPU tests run on whatever device the context picks (lavapipe on CI) with the Khronos
// validation layer on; any validation message fails the test.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "gpu/gpu.h"

namespace isg::test {

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    gpu::ContextOptions o;
    o.validation = true;
    ctx_ = std::make_unique<gpu::Context>(o);
  }
  static void TearDownTestSuite() { ctx_.reset(); }
  void TearDown() override {
    for (const auto& m : ctx_->messages()) ADD_FAILURE() << "Vulkan validation: " << m;
    EXPECT_EQ(ctx_->message_count(), seen_);
    seen_ = ctx_->message_count();
  }
  gpu::Context& ctx() { return *ctx_; }
  static inline std::unique_ptr<gpu::Context> ctx_;
  size_t seen_ = 0;
};

}  // namespace isg::test
