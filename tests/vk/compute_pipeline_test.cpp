// ComputePipeline on the device under test, item by item against the host
// evaluation of shaders/test_count.comp, its chain of two passes
// (test_queue_first.comp queues items, test_queue_follow.comp takes the
// queue), and its refusals.
#include "vk/compute_pipeline.hpp"

#include "device_under_test.hpp"
#include "test_count_comp.h"     // cmr_test_count_comp_spv
#include "test_pattern_frag.h"  // cmr_test_pattern_frag_spv (a fragment shader)
#include "test_queue_first_comp.h"
#include "test_queue_follow_comp.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cmr::vk {
namespace {

struct Push {
  uint32_t count, add;
};

std::span<const std::byte> bytes_of(const auto& v) { return std::as_bytes(std::span(v)); }

class ComputePipelineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto c = Context::create({});
    ASSERT_TRUE(c) << c.error().message;
    context_.emplace(c.take());
  }
  std::optional<Context> context_;
};

// Runs `count` items of test_count.comp and checks every word.
void expect_counts(ComputePipeline& p, const std::vector<uint32_t>& input, uint32_t count, uint32_t add) {
  const Push push{count, add};
  auto words = p.run(bytes_of(input), count, std::as_bytes(std::span(&push, 1)));
  ASSERT_TRUE(words) << words.error().message;
  ASSERT_EQ(words.value().size(), count);
  std::size_t wrong = 0, first = 0;
  for (uint32_t at = 0; at < count; ++at) {
    const uint32_t want = input[at % input.size()] * 3u + at + add;
    if (words.value()[at] != want && wrong++ == 0) first = at;
  }
  EXPECT_EQ(wrong, 0u) << count << " items: first wrong item " << first;
}

TEST_F(ComputePipelineTest, EveryItemOnceAcrossGroupsRowsAndRuns) {
  auto p = ComputePipeline::create(*context_, cmr_test_count_comp_spv, sizeof(Push));
  ASSERT_TRUE(p) << p.error().message;
  std::vector<uint32_t> input(1000);
  for (std::size_t k = 0; k < input.size(); ++k) input[k] = static_cast<uint32_t>(k * 7919u + 13u);
  // Partial and whole groups; then more groups than one dispatch row holds
  // (32768 groups of 64), so the second row's indexing is used; then a
  // smaller run after a larger one (the buffers are reused) and a larger
  // input (they grow).
  for (const uint32_t count : {1u, 63u, 64u, 65u, 4097u, 32768u * 64u + 130u, 5u}) expect_counts(p.value(), input, count, count);
  input.resize(5000, 99u);
  expect_counts(p.value(), input, 5000, 1);
}

TEST_F(ComputePipelineTest, NoItemsGiveNoWords) {
  auto p = ComputePipeline::create(*context_, cmr_test_count_comp_spv, sizeof(Push));
  ASSERT_TRUE(p) << p.error().message;
  const std::vector<uint32_t> input(4, 1u);
  auto words = p.value().run(bytes_of(input), 0);
  ASSERT_TRUE(words) << words.error().message;
  EXPECT_TRUE(words.value().empty());
}

TEST_F(ComputePipelineTest, RefusesAFragmentShaderAndBadPushConstants) {
  auto frag = ComputePipeline::create(*context_, cmr_test_pattern_frag_spv, 4);
  ASSERT_FALSE(frag);
  EXPECT_EQ(frag.error().code, Errc::shader_invalid);
  EXPECT_NE(frag.error().message.find("no compute-stage entry point"), std::string::npos) << frag.error().message;

  const std::vector<uint32_t> not_spirv{1, 2, 3, 4, 5, 6};
  auto junk = ComputePipeline::create(*context_, not_spirv);
  ASSERT_FALSE(junk);
  EXPECT_EQ(junk.error().code, Errc::shader_invalid);

  auto odd = ComputePipeline::create(*context_, cmr_test_count_comp_spv, 6);
  ASSERT_FALSE(odd);
  EXPECT_EQ(odd.error().code, Errc::size_unsupported);

  auto p = ComputePipeline::create(*context_, cmr_test_count_comp_spv, sizeof(Push));
  ASSERT_TRUE(p) << p.error().message;
  const std::vector<uint32_t> input(4, 1u);
  const uint32_t too_short = 3;
  auto run = p.value().run(bytes_of(input), 3, std::as_bytes(std::span(&too_short, 1)));
  ASSERT_FALSE(run);
  EXPECT_EQ(run.error().code, Errc::size_unsupported);
}

// run_chain: the counters start as `init` says whatever the last run left,
// the first pass's queue is complete when the follow-up reads it, and the
// follow-up runs the groups the first pass counted, each queued item once.
TEST_F(ComputePipelineTest, AChainRunsTheFollowUpOverWhatTheFirstPassQueued) {
  const ComputePipeline::FollowUp follow[] = {{cmr_test_queue_follow_comp_spv}};
  const uint32_t groups[] = {1};  // the follow-up's group counts: result words 1-3
  auto p = ComputePipeline::create(*context_, cmr_test_queue_first_comp_spv, {}, follow);
  ASSERT_TRUE(p) << p.error().message;
  std::mt19937 rng(5);
  for (const uint32_t n : {100000u, 1u, 0u, 5000u}) {
    std::vector<uint32_t> input(1 + std::max(n, 1u));
    input[0] = n;
    for (uint32_t k = 1; k < input.size(); ++k) input[k] = rng() % 1000;
    const uint32_t init[4] = {0, 0, 1, 1};
    std::vector<uint32_t> out;
    const uint32_t words = 8 + 2 * std::max(n, 1u);
    auto r = p.value().run_chain(bytes_of(input), n, words, {0, init, groups, words}, [&](std::span<const std::byte> b) {
      out.resize(words);
      std::memcpy(out.data(), b.data(), 4 * words);
    });
    ASSERT_TRUE(r) << r.error().message;
    std::vector<uint32_t> odd;
    for (uint32_t at = 0; at < n; ++at)
      if (input[1 + at] % 2 == 1) odd.push_back(at);
    ASSERT_EQ(out[0], odd.size()) << n << " items";
    EXPECT_EQ(out[1], (odd.size() + 63) / 64) << n << " items: the follow-up's groups";
    std::vector<uint32_t> queued(out.begin() + 8, out.begin() + 8 + out[0]);
    std::size_t wrong = 0;
    for (uint32_t q = 0; q < out[0]; ++q) wrong += out[8 + n + q] != 10 * input[1 + queued[q]] + 1;
    EXPECT_EQ(wrong, 0u) << n << " items: queued items the follow-up missed or misread";
    std::sort(queued.begin(), queued.end());
    EXPECT_EQ(queued, odd) << n << " items";
    // Words no pass writes are the zeros zero_words asked for, on every run.
    std::size_t dirty = 0;
    for (std::size_t k = 8 + out[0]; k < 8 + n; ++k) dirty += out[k] != 0;
    for (std::size_t k = 8 + n + out[0]; k < words; ++k) dirty += out[k] != 0;
    EXPECT_EQ(dirty, 0u) << n << " items: words left over from an earlier run";
    // One time per pass, where the device has compute timestamps (lavapipe
    // and the GPUs tested have).
    const std::vector<double>& t = p.value().last_pass_seconds();
    if (!t.empty()) {
      ASSERT_EQ(t.size(), 2u);
    }
    for (const double s : t) EXPECT_TRUE(s >= 0 && s < 10) << s;
  }
  // Refusals: counters or group counts outside the result, and a chain on a
  // pipeline without a follow-up.
  const std::vector<uint32_t> input{1, 1};
  const uint32_t init[4] = {0, 0, 1, 1};
  const auto ignore = [](std::span<const std::byte>) {};
  auto outside = p.value().run_chain(bytes_of(input), 1, 10, {8, init, groups}, ignore);
  ASSERT_FALSE(outside);
  EXPECT_EQ(outside.error().code, Errc::other);
  const uint32_t two[] = {1, 4};
  auto miscounted = p.value().run_chain(bytes_of(input), 1, 10, {0, init, two}, ignore);
  ASSERT_FALSE(miscounted);
  EXPECT_EQ(miscounted.error().code, Errc::other);
  auto plain = ComputePipeline::create(*context_, cmr_test_count_comp_spv, sizeof(Push));
  ASSERT_TRUE(plain) << plain.error().message;
  auto no_follow = plain.value().run_chain(bytes_of(input), 1, 10, {0, init, groups}, ignore);
  ASSERT_FALSE(no_follow);
  EXPECT_EQ(no_follow.error().code, Errc::other);
  const ComputePipeline::FollowUp fragment[] = {{cmr_test_pattern_frag_spv}};
  auto bad_follow = ComputePipeline::create(*context_, cmr_test_queue_first_comp_spv, {}, fragment);
  ASSERT_FALSE(bad_follow);
  EXPECT_EQ(bad_follow.error().code, Errc::shader_invalid);
}

// The pass times are the last finished run's, read from the device when
// first asked (a frame that does not ask pays nothing): asked twice they
// are the same; a run refused before its submission has none. Lavapipe has
// compute timestamps, so there they must be there.
TEST_F(ComputePipelineTest, PassTimesAreTheLastFinishedRunsReadWhenAsked) {
  const ComputePipeline::FollowUp follow[] = {{cmr_test_queue_follow_comp_spv}};
  const uint32_t groups[] = {1};
  auto p = ComputePipeline::create(*context_, cmr_test_queue_first_comp_spv, {}, follow);
  ASSERT_TRUE(p) << p.error().message;
  const uint32_t n = 5000, words = 8 + 2 * n, init[4] = {0, 0, 1, 1};
  std::vector<uint32_t> input(1 + n, 7);
  input[0] = n;
  const auto ignore = [](std::span<const std::byte>) {};
  ASSERT_TRUE(p.value().run_chain(bytes_of(input), n, words, {0, init, groups, words}, ignore));
  const std::vector<double> first = p.value().last_pass_seconds();
  if (context_->device().type == VK_PHYSICAL_DEVICE_TYPE_CPU) {
    EXPECT_EQ(first.size(), 2u) << "lavapipe has timestamps";
  }
  if (!first.empty()) {
    EXPECT_EQ(first.size(), 2u);
  }
  EXPECT_EQ(p.value().last_pass_seconds(), first);
  ASSERT_FALSE(p.value().run_chain(bytes_of(input), n, 10, {8, init, groups}, ignore));  // counters outside
  EXPECT_TRUE(p.value().last_pass_seconds().empty()) << "a refused run's pass times";
}

}  // namespace
}  // namespace cmr::vk
