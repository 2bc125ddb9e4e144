// Device enumeration and selection on the device under test (lavapipe unless
// CMR_TEST_VK_DRIVER_FILES names a GPU's driver; see CMakeLists.txt).
#include "vk/context.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>
#include <utility>

#include "device_under_test.hpp"

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

using test::device_under_test;
using test::is_lavapipe;

/// The name with the case of every letter swapped ("NVIDIA H200" -> "nvidia h200").
std::string swap_case(std::string s) {
  for (char& c : s) {
    const auto u = static_cast<unsigned char>(c);
    c = static_cast<char>(std::isupper(u) ? std::tolower(u) : std::toupper(u));
  }
  return s;
}

TEST(EnumerateDevices, ListsTheDeviceUnderTestWithFloat64) {
  auto devices = enumerate_devices();
  ASSERT_TRUE(devices) << devices.error().message;
  ASSERT_FALSE(devices.value().empty());
  const std::string wanted = device_under_test();
  bool found = false;
  for (const DeviceInfo& d : devices.value()) {
    if (d.name != wanted) continue;
    found = true;
    if (is_lavapipe(d.name)) {
      EXPECT_EQ(d.type, VK_PHYSICAL_DEVICE_TYPE_CPU) << d.name;
    }
    EXPECT_TRUE(d.float64) << d.name << " should support shaderFloat64";
    EXPECT_GE(d.max_image_dimension_2d, 4096u) << d.name;
  }
  EXPECT_TRUE(found) << "'" << wanted << "' not among the enumerated devices";
  // CI's device: when the driver file is lavapipe's, lavapipe is what runs.
  const char* driver = std::getenv("VK_DRIVER_FILES");
  if (driver != nullptr && std::string(driver).find("lvp_icd") != std::string::npos) {
    EXPECT_TRUE(is_lavapipe(wanted)) << "VK_DRIVER_FILES=" << driver << " but the device is '" << wanted << "'";
  }
}

TEST(Context, DefaultPicksADeviceWithFloat64) {
  auto context = Context::create({});
  ASSERT_TRUE(context) << context.error().message;
  EXPECT_TRUE(context.value().device().float64);
  EXPECT_NE(context.value().device_handle(), VK_NULL_HANDLE);
  EXPECT_NE(context.value().queue(), VK_NULL_HANDLE);
}

TEST(Context, NameMatchIsCaseInsensitiveSubstring) {
  const std::string name = device_under_test();
  ASSERT_FALSE(name.empty());
  auto context = Context::create(test_options(swap_case(name.substr(0, std::min<std::size_t>(name.size(), 8)))));
  ASSERT_TRUE(context) << context.error().message;
  EXPECT_EQ(context.value().device().name, name);
}

TEST(Context, WorksWithoutRequiringFloat64) {
  auto context = Context::create(test_options(device_under_test(), false));
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
  std::string quoted = device_under_test();
  quoted.insert(quoted.begin(), '\'');
  quoted.push_back('\'');
  EXPECT_NE(e.message.find(quoted), std::string::npos) << e.message;
  EXPECT_EQ(e.message.find('\n'), std::string::npos) << "message must be one line: " << e.message;
}

// A program may open and close Contexts many times: NVIDIA's driver (580)
// failed the 30th vkCreateInstance when the loader unloaded it with each
// instance (vk/context.cpp keeps it loaded). Lavapipe passes either way; run
// with CMR_TEST_VK_DRIVER_FILES naming a GPU's driver to check that.
TEST(Context, FortyContextsOneAfterAnother) {
  for (int i = 0; i < 40; ++i) {
    auto context = Context::create({});
    ASSERT_TRUE(context) << "context " << i + 1 << ": " << context.error().message;
  }
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
