// FragmentPipeline on Mesa lavapipe, checked pixel by pixel against the host
// evaluation of shaders/test_pattern.frag.
#include "vk/fragment_pipeline.hpp"

#include "fullscreen_vert.h"   // cmr_fullscreen_vert_spv (a vertex shader)
#include "test_pattern_frag.h"  // cmr_test_pattern_frag_spv
#include "device_under_test.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace cmr::vk {
namespace {

/// Context options naming a device (designated initializers would leave the
/// other members to -Wmissing-field-initializers).
ContextOptions test_options(const std::string& device, bool require_float64 = true) {
  ContextOptions o;
  o.device_name = device;
  o.require_float64 = require_float64;
  return o;
}

constexpr uint32_t kPushBytes = 4;  // test_pattern.frag: uint salt

// Storage-buffer contents: n doubles whose low bits lie far below fp32
// precision: an integer plus multiples of 2^-18 and 2^-30. The sizes used
// here keep |v| < 2^22 in the shader, so every product and sum fits in 53
// significant bits and is exact in fp64 (no rounding or FMA differences).
std::vector<double> pattern_values(std::size_t n) {
  std::vector<double> d(n);
  for (std::size_t k = 0; k < n; ++k) {
    d[k] = 1000.0 + 37.0 * static_cast<double>(k) + static_cast<double>(k + 1) * 0x1p-18 + 0x1p-30;
  }
  return d;
}

// Host mirror of test_pattern.frag, generic over the floating-point type so
// the test can also show that fp32 would not reproduce it.
template <class F>
uint32_t pattern_pixel(uint32_t x, uint32_t y, const std::vector<double>& d, uint32_t salt) {
  const F value = static_cast<F>(d[(x + 3u * y) % d.size()]);
  const F v = value * static_cast<F>(x + 1u) + static_cast<F>(y) * static_cast<F>(0x1p-30);
  const F whole = std::floor(v);
  const auto fraction_bits = static_cast<uint32_t>((v - whole) * static_cast<F>(0x1p30));
  return fraction_bits + static_cast<uint32_t>(whole) * 2654435761u + salt;
}

template <class F = double>
std::vector<uint32_t> expected_image(uint32_t width, uint32_t height, const std::vector<double>& d,
                                     uint32_t salt) {
  std::vector<uint32_t> out(std::size_t{width} * height);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) out[std::size_t{y} * width + x] = pattern_pixel<F>(x, y, d, salt);
  }
  return out;
}

std::span<const std::byte> bytes_of(const std::vector<double>& v) { return std::as_bytes(std::span(v)); }
std::span<const std::byte> bytes_of(const uint32_t& v) { return std::as_bytes(std::span(&v, 1)); }

// Equal images, or which pixel differs first and how many differ.
::testing::AssertionResult same_image(const std::vector<uint32_t>& got, const std::vector<uint32_t>& want,
                                      uint32_t width, uint32_t height) {
  if (got.size() != std::size_t{width} * height) {
    return ::testing::AssertionFailure() << "got " << got.size() << " pixels, want " << width << "x" << height;
  }
  std::size_t differing = 0;
  std::ostringstream first;
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const std::size_t i = std::size_t{y} * width + x;
      if (got[i] == want[i]) continue;
      if (differing++ == 0) {
        first << "pixel (x=" << x << ", y=" << y << "): got " << got[i] << ", want " << want[i];
      }
    }
  }
  if (differing == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << first.str() << " (" << differing << " of " << got.size()
                                       << " pixels differ, image " << width << "x" << height << ")";
}

Context make_context() {
  auto context = Context::create(test_options(cmr::vk::test::device_under_test()));
  if (!context) ADD_FAILURE() << context.error().message;
  return context.take();
}

class FragmentPipelineTest : public ::testing::Test {
 protected:
  // One device for the suite, as a program keeps one; closed in
  // TearDownTestSuite, before exit() (vk/context.hpp says why).
  static void SetUpTestSuite() {
    auto context = Context::create(test_options(cmr::vk::test::device_under_test()));
    if (context) {
      context_.emplace(context.take());
    } else {
      setup_error_ = context.error().message;
    }
  }
  static void TearDownTestSuite() { context_.reset(); }
  void SetUp() override { ASSERT_TRUE(context_) << setup_error_; }
  Context& context() { return *context_; }

  Result<FragmentPipeline> make(uint32_t width, uint32_t height,
                                uint32_t band_rows = FragmentPipeline::kDefaultBandRows) {
    return FragmentPipeline::create(context(), cmr_test_pattern_frag_spv, width, height, kPushBytes, band_rows);
  }

  // Renders the pattern and compares it with the host evaluation.
  void expect_pattern(FragmentPipeline& pipeline, std::size_t values, uint32_t salt) {
    const std::vector<double> d = pattern_values(values);
    auto image = pipeline.run(bytes_of(d), bytes_of(salt));
    ASSERT_TRUE(image) << image.error().message;
    EXPECT_TRUE(same_image(image.value(), expected_image(pipeline.width(), pipeline.height(), d, salt),
                           pipeline.width(), pipeline.height()))
        << values << " values, salt " << salt << ", band_rows " << pipeline.band_rows();
  }

 private:
  static inline std::optional<Context> context_;
  static inline std::string setup_error_;
};

TEST_F(FragmentPipelineTest, PatternMatchesHostFp64AndRowOrder) {
  // Odd sizes and a band height that does not divide the height exercise
  // partial bands; 45 rows / 16 = 3 submissions.
  auto pipeline = make(67, 45, 16);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  expect_pattern(pipeline.value(), 7, 0x5eed1234u);
}

TEST_F(FragmentPipelineTest, PatternIsSensitiveToFp32AndFlips) {
  // Guards the test itself: fp32 arithmetic and an upside-down image must
  // both fail the comparison above for most pixels.
  const uint32_t w = 67, h = 45;
  const std::vector<double> d = pattern_values(7);
  const auto fp64 = expected_image<double>(w, h, d, 1);
  const auto fp32 = expected_image<float>(w, h, d, 1);
  std::size_t same_fp32 = 0, same_flipped = 0;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const std::size_t i = std::size_t{y} * w + x;
      same_fp32 += fp64[i] == fp32[i];
      same_flipped += fp64[i] == fp64[std::size_t{h - 1 - y} * w + x];
    }
  }
  EXPECT_LT(same_fp32, fp64.size() / 10) << "fp32 reproduces too many pixels";
  EXPECT_LE(same_flipped, std::size_t{w}) << "a vertically flipped image matches too many pixels";
}

TEST_F(FragmentPipelineTest, RunTwiceGivesSameResult) {
  auto pipeline = make(50, 40, 8);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  const std::vector<double> d = pattern_values(5);
  const uint32_t salt = 42;
  auto first = pipeline.value().run(bytes_of(d), bytes_of(salt));
  ASSERT_TRUE(first) << first.error().message;
  auto second = pipeline.value().run(bytes_of(d), bytes_of(salt));
  ASSERT_TRUE(second) << second.error().message;
  EXPECT_TRUE(same_image(second.value(), first.value(), 50, 40));
  EXPECT_TRUE(same_image(first.value(), expected_image(50, 40, d, salt), 50, 40));
}

TEST_F(FragmentPipelineTest, LargerSizeWithDefaultBands) {
  // 600 rows = bands of 256, 256 and 88 rows.
  auto pipeline = make(333, 600);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  EXPECT_EQ(pipeline.value().band_rows(), FragmentPipeline::kDefaultBandRows);
  expect_pattern(pipeline.value(), 11, 7);
}

TEST_F(FragmentPipelineTest, OneRowPerBandAndSinglePixel) {
  auto rows = make(5, 7, 1);
  ASSERT_TRUE(rows) << rows.error().message;
  expect_pattern(rows.value(), 3, 9);

  auto pixel = make(1, 1);
  ASSERT_TRUE(pixel) << pixel.error().message;
  expect_pattern(pixel.value(), 1, 0);
}

TEST_F(FragmentPipelineTest, StorageBufferGrowsAndShrinks) {
  // d.length() in the shader must follow the data passed to each run, also
  // after the buffer is reallocated and when smaller data reuses it.
  auto pipeline = make(64, 48, 20);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  for (const std::size_t n : {3, 200, 5, 1000, 2}) {
    SCOPED_TRACE("values: " + std::to_string(n));
    expect_pattern(pipeline.value(), n, static_cast<uint32_t>(n));
  }
}

TEST_F(FragmentPipelineTest, EmptyPushConstantsPushZeros) {
  auto pipeline = make(16, 16);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  const std::vector<double> d = pattern_values(4);
  auto image = pipeline.value().run(bytes_of(d));
  ASSERT_TRUE(image) << image.error().message;
  EXPECT_TRUE(same_image(image.value(), expected_image(16, 16, d, 0), 16, 16));
}

TEST_F(FragmentPipelineTest, OutlivesItsContext) {
  std::optional<FragmentPipeline> pipeline;
  {
    Context local = make_context();
    auto created = FragmentPipeline::create(local, cmr_test_pattern_frag_spv, 20, 10, kPushBytes);
    ASSERT_TRUE(created) << created.error().message;
    pipeline.emplace(created.take());
  }
  expect_pattern(*pipeline, 6, 3);
  FragmentPipeline moved = std::move(*pipeline);
  pipeline.reset();
  expect_pattern(moved, 6, 4);
}

TEST_F(FragmentPipelineTest, ZeroSizeIsUnsupported) {
  for (const auto& [w, h] : {std::pair{0u, 10u}, std::pair{10u, 0u}, std::pair{0u, 0u}}) {
    auto pipeline = make(w, h);
    ASSERT_FALSE(pipeline) << w << "x" << h << " was accepted";
    EXPECT_EQ(pipeline.error().code, Errc::size_unsupported)
        << w << "x" << h << ": " << pipeline.error().message;
    EXPECT_EQ(pipeline.error().message.find('\n'), std::string::npos);
  }
}

TEST_F(FragmentPipelineTest, SizeAboveDeviceLimitIsUnsupported) {
  const uint32_t limit = context().device().max_image_dimension_2d;
  for (const auto& [w, h] : {std::pair{limit + 1, 1u}, std::pair{1u, limit + 1}}) {
    auto pipeline = make(w, h);
    ASSERT_FALSE(pipeline) << w << "x" << h << " was accepted";
    EXPECT_EQ(pipeline.error().code, Errc::size_unsupported)
        << w << "x" << h << ": " << pipeline.error().message;
    EXPECT_NE(pipeline.error().message.find(std::to_string(limit)), std::string::npos)
        << pipeline.error().message;
  }
}

TEST_F(FragmentPipelineTest, BadPushConstantAndBandSizes) {
  for (const uint32_t bytes : {2u, 132u}) {
    auto pipeline = FragmentPipeline::create(context(), cmr_test_pattern_frag_spv, 8, 8, bytes);
    ASSERT_FALSE(pipeline) << bytes << " push-constant bytes accepted";
    EXPECT_EQ(pipeline.error().code, Errc::size_unsupported) << pipeline.error().message;
  }
  auto zero_band = make(8, 8, 0);
  ASSERT_FALSE(zero_band);
  EXPECT_EQ(zero_band.error().code, Errc::size_unsupported) << zero_band.error().message;

  auto pipeline = make(8, 8);
  ASSERT_TRUE(pipeline) << pipeline.error().message;
  const std::vector<double> d = pattern_values(2);
  const std::vector<double> eight_bytes{1.0};
  auto image = pipeline.value().run(bytes_of(d), bytes_of(eight_bytes));
  ASSERT_FALSE(image);
  EXPECT_EQ(image.error().code, Errc::size_unsupported) << image.error().message;
  // The pipeline stays usable after a rejected call.
  expect_pattern(pipeline.value(), 2, 1);
}

TEST_F(FragmentPipelineTest, RejectsWhatIsNotAFragmentShader) {
  const std::vector<uint32_t> garbage{1, 2, 3, 4, 5, 6};
  auto not_spirv = FragmentPipeline::create(context(), garbage, 8, 8, kPushBytes);
  ASSERT_FALSE(not_spirv);
  EXPECT_EQ(not_spirv.error().code, Errc::shader_invalid) << not_spirv.error().message;

  auto empty = FragmentPipeline::create(context(), std::span<const uint32_t>{}, 8, 8, kPushBytes);
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error().code, Errc::shader_invalid) << empty.error().message;

  const std::span<const uint32_t> whole(cmr_test_pattern_frag_spv);
  // Header plus the first word of a two-word instruction (OpCapability).
  auto truncated = FragmentPipeline::create(context(), whole.first(6), 8, 8, kPushBytes);
  ASSERT_FALSE(truncated);
  EXPECT_EQ(truncated.error().code, Errc::shader_invalid) << truncated.error().message;

  auto vertex = FragmentPipeline::create(context(), cmr_fullscreen_vert_spv, 8, 8, kPushBytes);
  ASSERT_FALSE(vertex);
  EXPECT_EQ(vertex.error().code, Errc::shader_invalid) << vertex.error().message;
}

}  // namespace
}  // namespace cmr::vk
