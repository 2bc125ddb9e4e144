#include "vk/backend_choice.hpp"

#include <optional>
#include <utility>

#include "spline/errors.hpp"
#include "vk/context.hpp"

namespace cmr::vk {
namespace {

/// The Vulkan backend, opened at its first render. Opening failures become
/// EnvironmentError with what to do about them; render failures are
/// RegionFailure, itself an EnvironmentError.
class DeferredVulkanBackend final : public RegionBackend {
 public:
  explicit DeferredVulkanBackend(VulkanRegionOptions options) : options_(std::move(options)) {}
  RegionResult render(const RegionProblem& problem) override {
    if (!backend_) open();
    return backend_->render(problem);
  }
  std::string name() const override { return "vulkan"; }

 private:
  void open() {
    auto created = VulkanRegionBackend::create(options_);
    if (!created) {
      std::string message = created.error().message;
      if (message.find("VK_DRIVER_FILES") == std::string::npos)
        message += " (for lavapipe: install mesa-vulkan-drivers or export "
                   "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json)";
      throw EnvironmentError(message + "; or use --backend cpu");
    }
    backend_.emplace(created.take());
  }
  VulkanRegionOptions options_;
  std::optional<VulkanRegionBackend> backend_;
};

/// auto_backend_device on what the loader lists; empty when there is no
/// loader, driver or device at all.
std::string first_gpu() {
  auto devices = enumerate_devices();
  if (!devices) return {};
  std::vector<ListedDevice> listed;
  for (const DeviceInfo& d : devices.value()) listed.push_back({d.name, d.type == VK_PHYSICAL_DEVICE_TYPE_CPU});
  return auto_backend_device(listed);
}

/// BackendKind::automatic: Vulkan on a real GPU, else the CPU backend,
/// announced. The choice is made once, when first needed.
class AutoBackend final : public RegionBackend {
 public:
  AutoBackend(BackendChoice choice, BackendNote note) : choice_(std::move(choice)), note_(std::move(note)) {}
  RegionResult render(const RegionProblem& problem) override { return chosen().render(problem); }
  std::string name() const override { return chosen().name(); }

 private:
  RegionBackend& chosen() const {
    if (!chosen_) {
      BackendChoice c = choice_;
      if (c.device.empty()) c.device = first_gpu();
      c.kind = c.device.empty() ? BackendKind::cpu : BackendKind::vulkan;
      chosen_ = make_region_backend(c);
      if (c.kind == BackendKind::cpu && note_) note_(kCpuFallbackNote);
    }
    return *chosen_;
  }
  BackendChoice choice_;
  BackendNote note_;
  mutable std::shared_ptr<RegionBackend> chosen_;
};

}  // namespace

std::string auto_backend_device(const std::vector<ListedDevice>& devices) {
  for (const ListedDevice& d : devices)
    if (!d.cpu) return d.name;
  return {};
}

std::shared_ptr<RegionBackend> make_region_backend(const BackendChoice& choice, BackendNote note) {
  switch (choice.kind) {
    case BackendKind::cpu:
      return std::make_shared<CpuRegionBackend>();
    case BackendKind::automatic:
      return std::make_shared<AutoBackend>(choice, std::move(note));
    case BackendKind::vulkan: {
      VulkanRegionOptions o;
      o.device = choice.device;
      o.precision = choice.precision;
      return std::make_shared<DeferredVulkanBackend>(std::move(o));
    }
  }
  CMR_CHECK(false);
  return nullptr;
}

}  // namespace cmr::vk
