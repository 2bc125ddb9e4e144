// Device enumeration and selection on Mesa lavapipe (VK_DRIVER_FILES is set
// by CTest; see CMakeLists.txt).
#include "vk/context.hpp"

#include <gtest/gtest.h>

#include <string>
#include <utility>

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

bool is_lavapipe(const DeviceInfo& d) { return d.name.find("llvmpipe") != std::string::npos; }

TEST(EnumerateDevices, FindsLavapipeWithFloat64) {
  auto devices = enumerate_devices();
  ASSERT_TRUE(devices) << devices.error().message;
  ASSERT_FALSE(devices.value().empty());
  bool found = false;
  for (const DeviceInfo& d : devices.value()) {
    if (!is_lavapipe(d)) continue;
    found = true;
    EXPECT_EQ(d.type, VK_PHYSICAL_DEVICE_TYPE_CPU) << d.name;
    EXPECT_TRUE(d.float64) << d.name << " should support shaderFloat64";
    EXPECT_GE(d.max_image_dimension_2d, 4096u) << d.name;
  }
  EXPECT_TRUE(found) << "lavapipe (llvmpipe) not among the enumerated devices";
}

TEST(Context, DefaultPicksADeviceWithFloat64) {
  auto context = Context::create({});
  ASSERT_TRUE(context) << context.error().message;
  EXPECT_TRUE(context.value().device().float64);
  EXPECT_NE(context.value().device_handle(), VK_NULL_HANDLE);
  EXPECT_NE(context.value().queue(), VK_NULL_HANDLE);
}

TEST(Context, NameMatchIsCaseInsensitiveSubstring) {
  auto context = Context::create(test_options("LLVMPipe"));
  ASSERT_TRUE(context) << context.error().message;
  EXPECT_TRUE(is_lavapipe(context.value().device())) << context.value().device().name;
}

TEST(Context, WorksWithoutRequiringFloat64) {
  auto context = Context::create(test_options("llvmpipe", false));
  ASSERT_TRUE(context) << context.error().message;
  // fp64 is enabled whenever supported, required or not.
  EXPECT_TRUE(context.value().device().float64);
}

TEST(Context, UnknownNameIsDeviceNotFoundAndListsDevices) {
  auto context = Context::create(test_options("no-such-gpu-xyz"));
  ASSERT_FALSE(context) << "picked '" << context.value().device().name << "' for an unknown name";
  const Error& e = context.error();
  EXPECT_EQ(e.code, Errc::device_not_found) << to_string(e.code) << ": " << e.message;
  EXPECT_NE(e.message.find("'no-such-gpu-xyz'"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("available:"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("llvmpipe"), std::string::npos) << e.message;
  EXPECT_EQ(e.message.find('\n'), std::string::npos) << "message must be one line: " << e.message;
}

TEST(Context, MoveTransfersOwnership) {
  auto created = Context::create({});
  ASSERT_TRUE(created) << created.error().message;
  Context a = created.take();
  const VkDevice device = a.device_handle();
  Context b = std::move(a);
  EXPECT_EQ(b.device_handle(), device);
  Context c = Context::create({}).take();
  c = std::move(b);  // releases c's own device, keeps b's
  EXPECT_EQ(c.device_handle(), device);
}

}  // namespace
}  // namespace cmr::vk
