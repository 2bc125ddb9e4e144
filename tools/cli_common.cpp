#include "tools/cli_common.hpp"

#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>

#include "spline/errors.hpp"
#ifdef CMR_WITH_VULKAN
#include "vk/region_vk.hpp"
#endif

namespace cmr::cli {
namespace {

/// The Vulkan backend, opened at its first render; its failures become
/// EnvironmentError (exit 3) with what to do about them.
class DeferredVulkanBackend final : public RegionBackend {
 public:
#ifdef CMR_WITH_VULKAN
  explicit DeferredVulkanBackend(vk::VulkanRegionOptions options) : options_(std::move(options)) {}
  RegionResult render(const RegionProblem& problem) override {
    if (!backend_) open();
    try {
      return backend_->render(problem);
    } catch (const vk::RegionFailure& e) {
      throw EnvironmentError(e.what());
    }
  }
#else
  RegionResult render(const RegionProblem&) override {
    throw EnvironmentError("this cmr was built without Vulkan; use --backend cpu");
  }
#endif
  std::string name() const override { return "vulkan"; }

#ifdef CMR_WITH_VULKAN
 private:
  void open() {
    auto created = vk::VulkanRegionBackend::create(options_);
    if (!created) {
      std::string message = created.error().message;
      if (message.find("VK_DRIVER_FILES") == std::string::npos)
        message += " (for lavapipe: install mesa-vulkan-drivers or export "
                   "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json)";
      throw EnvironmentError(message + "; or use --backend cpu");
    }
    backend_.emplace(created.take());
  }
  vk::VulkanRegionOptions options_;
  std::optional<vk::VulkanRegionBackend> backend_;
#endif
};

}  // namespace

std::shared_ptr<RegionBackend> make_region_backend(const std::string& backend, const std::string& precision,
                                                   const std::string& device) {
  if (backend == "cpu") return std::make_shared<CpuRegionBackend>();
  CMR_CHECK(backend == "vulkan" && (precision == "fp64" || precision == "fp32"));  // CLI11 checked the choices
#ifdef CMR_WITH_VULKAN
  vk::VulkanRegionOptions o;
  o.device = device;
  o.precision = precision == "fp32" ? vk::RegionPrecision::fp32 : vk::RegionPrecision::fp64;
  return std::make_shared<DeferredVulkanBackend>(std::move(o));
#else
  (void)device;
  return std::make_shared<DeferredVulkanBackend>();
#endif
}

void print_json(const nlohmann::ordered_json& doc) { std::cout << doc.dump(2) << '\n'; }

void check_output_path(const std::filesystem::path& path, const std::string& option) {
  const std::filesystem::path folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(option + " " + path.string() + ": the folder " + folder.string() + " does not exist");
  if (std::filesystem::is_directory(path, ec)) throw InputError(option + " " + path.string() + ": is a directory");
}

std::pair<int, int> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra))
    throw InputError("--size: expected WxH, e.g. 512x512 (got '" + text + "')");
  return {w, h};
}

View parse_view(const std::string& text) {
  std::vector<double> v;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    // strtod, not stod: subnormal numbers are numbers (stod reports them as out of range).
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size())
      throw InputError("--view: '" + item + "' is not a number (expected X0,Y0,X1,Y1)");
    v.push_back(x);
  }
  if (v.size() != 4) throw InputError("--view: expected four numbers X0,Y0,X1,Y1 (got '" + text + "')");
  return {v[0], v[1], v[2], v[3]};
}

OutputFiles::~OutputFiles() {
  for (const auto& p : written_) {
    std::error_code ec;
    std::filesystem::remove(p, ec);
  }
}

void OutputFiles::write(const std::filesystem::path& path, std::string_view bytes) {
  write_file_atomic(path, bytes);
  written_.push_back(path);
}

}  // namespace cmr::cli
