#include "tools/cli_common.hpp"

#include <algorithm>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>

#include "region/box_reuse.hpp"
#include "region/pixel_lanes.hpp"
#include "region/pixel_simd.hpp"
#include "region/space_region.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#ifdef CMR_WITH_VULKAN
#include "vk/backend_choice.hpp"
#endif

namespace cmr::cli {
namespace {

#ifndef CMR_WITH_VULKAN
/// --backend vulkan in a build without Vulkan.
class NoVulkanBackend final : public RegionBackend {
 public:
  RegionResult render(const RegionProblem&) override {
    throw EnvironmentError("this cmr was built without Vulkan; use --backend cpu");
  }
  std::string name() const override { return "vulkan"; }
};
#endif

/// A number as the range message shows it: integers without a fraction.
std::string number_text(double x) {
  std::ostringstream s;
  s << std::setprecision(15) << x;
  return s.str();
}

}  // namespace

std::string user_cache_dir() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg != nullptr && *xdg == '/') return std::string(xdg) + "/cmr";
  const char* home = std::getenv("HOME");
  if (home != nullptr && *home == '/') return std::string(home) + "/.cache/cmr";
  return {};
}

namespace {

#ifdef CMR_WITH_VULKAN
/// The backend each --backend word (kBackendChoices) chooses: the one place
/// the CLI reads them.
vk::BackendKind backend_kind(const std::string& word) {
  static const std::map<std::string, vk::BackendKind> kinds = {
      {"auto", vk::BackendKind::automatic}, {"vulkan", vk::BackendKind::vulkan}, {"cpu", vk::BackendKind::cpu}};
  const auto it = kinds.find(word);
  CMR_CHECK(it != kinds.end());  // CLI11 checked the choices
  return it->second;
}

/// The library's aggregate for the options (see make_region_backend).
vk::BackendChoice backend_choice(const std::string& backend, const std::string& precision, const std::string& device,
                                 int frames) {
  CMR_CHECK(precision == "fp64" || precision == "fp32");  // CLI11 checked the choices
  vk::BackendChoice choice;
  choice.kind = backend_kind(backend);
  choice.precision = precision == "fp32" ? vk::RegionPrecision::fp32 : vk::RegionPrecision::fp64;
  choice.device = device;
  choice.frames = frames;
  choice.cache_dir = user_cache_dir();
  for (const char* var : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"})
    if (const char* value = std::getenv(var); value != nullptr && *value != '\0') {
      if (!choice.loader_selection.empty()) choice.loader_selection += ", ";
      choice.loader_selection.append(var).append("='").append(value).append("'");
    }
  // Failure injection for the tests of the Vulkan fallbacks (tests/tools).
  if (const char* fault = std::getenv("CMR_VK_FAULT"); fault != nullptr) {
    const std::string f = fault;
    choice.fault = f == "device_lost"         ? vk::InjectedFault::device_lost
                   : f == "out_of_memory"     ? vk::InjectedFault::out_of_memory
                   : f == "pipeline_rejected" ? vk::InjectedFault::pipeline_rejected
                                              : vk::InjectedFault::none;
  }
  return choice;
}
#else
/// Whether each --backend word (kBackendChoices) renders on the CPU in a
/// build without Vulkan: the one place the CLI reads them.
bool on_cpu(const std::string& word) {
  static const std::map<std::string, bool> cpu = {{"auto", true}, {"vulkan", false}, {"cpu", true}};
  const auto it = cpu.find(word);
  CMR_CHECK(it != cpu.end());  // CLI11 checked the choices
  return it->second;
}

/// --backend vulkan of space regions in a build without Vulkan.
class NoVulkanSpaceBackend final : public SpaceRegionBackend {
 public:
  RegionResult render(const SpaceRegionProblem&) override {
    throw EnvironmentError("this cmr was built without Vulkan; use --backend cpu");
  }
  std::string name() const override { return "vulkan"; }
};
#endif

}  // namespace

std::shared_ptr<RegionBackend> make_region_backend(const std::string& backend, const std::string& precision,
                                                   const std::string& device, int frames) {
#ifdef CMR_WITH_VULKAN
  return vk::make_region_backend(backend_choice(backend, precision, device, frames), [](const std::string& note) {
    std::cerr << "note: " << show_fields(note) << '\n';
  });
#else
  (void)precision;
  (void)device;
  (void)frames;
  if (on_cpu(backend)) return std::make_shared<CpuRegionBackend>();
  return std::make_shared<NoVulkanBackend>();
#endif
}

std::shared_ptr<SpaceRegionBackend> make_space_region_backend(const std::string& backend) {
#ifdef CMR_WITH_VULKAN
  return vk::make_space_region_backend(backend_choice(backend, "fp64", "", 1));
#else
  if (on_cpu(backend)) return std::make_shared<CpuSpaceRegionBackend>();
  return std::make_shared<NoVulkanSpaceBackend>();
#endif
}

void read_environment() {
  std::string warning;
  const backend::SimdLevel level = backend::simd_level_for(std::getenv("CMR_SIMD"), warning);
  if (!warning.empty()) std::cerr << warning << '\n';
  backend::set_simd_level(level);
  const char* reuse = std::getenv("CMR_BLOCK_REUSE");
  if (reuse && std::string_view(reuse) == "0") backend::set_block_reuse(0);
  const char* lanes = std::getenv("CMR_PIXEL_LANES");
  if (lanes && std::string_view(lanes) == "0") backend::detail::set_pixel_lanes(0);
}

std::string json_text(const nlohmann::ordered_json& doc, bool pretty) {
  return doc.dump(pretty ? 2 : -1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

void print_json(const nlohmann::ordered_json& doc, bool pretty) { std::cout << json_text(doc, pretty); }

JsonObjectStream::JsonObjectStream(std::ostream& out, bool pretty) : out_(out), pretty_(pretty) { out_ << '{'; }

void JsonObjectStream::key(const std::string& name) {
  out_ << (first_member_ ? "" : ",") << (pretty_ ? "\n  " : "");
  first_member_ = false;
  value(nlohmann::ordered_json(name), 0);
  out_ << (pretty_ ? ": " : ":");
}

// v as dump() writes it nested `indent` spaces deep: every line after the
// first shifted right by `indent`.
void JsonObjectStream::value(const nlohmann::ordered_json& v, int indent) {
  const std::string text = v.dump(pretty_ ? 2 : -1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  if (!pretty_ || indent == 0) {
    out_ << text;
    return;
  }
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  std::size_t start = 0;
  for (std::size_t nl = text.find('\n'); nl != std::string::npos; nl = text.find('\n', start)) {
    out_.write(text.data() + start, static_cast<std::streamsize>(nl + 1 - start));
    out_ << pad;
    start = nl + 1;
  }
  out_.write(text.data() + start, static_cast<std::streamsize>(text.size() - start));
}

void JsonObjectStream::member(const std::string& name, const nlohmann::ordered_json& v) {
  key(name);
  value(v, 2);
}

void JsonObjectStream::begin_array(const std::string& name) {
  key(name);
  out_ << '[';
  first_element_ = true;
}

void JsonObjectStream::element(const nlohmann::ordered_json& v) {
  out_ << (first_element_ ? "" : ",") << (pretty_ ? "\n    " : "");
  first_element_ = false;
  value(v, 4);
}

void JsonObjectStream::end_array() { out_ << (pretty_ && !first_element_ ? "\n  ]" : "]"); }

void JsonObjectStream::finish() { out_ << (pretty_ && !first_member_ ? "\n}" : "}") << '\n'; }

void add_pretty_flag(CLI::App& cmd, bool& pretty) {
  cmd.add_flag("--pretty", pretty, "indent the JSON (default: compact, one line)");
}

void add_backend_options(CLI::App& cmd, std::string& backend, std::string& device, std::string* precision) {
  cmd.add_option("--backend", backend, "region backend: auto (a real GPU where measured faster for the job, else cpu), vulkan, cpu")
      ->check(CLI::IsMember(kBackendChoices))
      ->capture_default_str();
  cmd.add_option("--device", device, "Vulkan device name (case-insensitive substring); default: the first suitable");
  if (precision)
    cmd.add_option("--precision", *precision, "shader arithmetic; labels are certified either way")
        ->check(CLI::IsMember({"fp64", "fp32"}))
        ->capture_default_str();
}

void add_continuity_options(CLI::App& cmd, ContinuityTolerances& tolerances) {
  cmd.add_option("--angle-tol", tolerances.angle_deg, "G1 at a joint: end tangents within this angle (degrees)")
      ->capture_default_str();
  cmd.add_option("--curvature-tol", tolerances.curvature_rel,
                 "G2 at a joint: G1 and curvatures equal within this relative tolerance")
      ->capture_default_str();
}

CLI::Option* in_range(CLI::Option* option, double lo, double hi) {
  const std::string range = number_text(lo) + ".." + number_text(hi);
  option->check(CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        std::string message = text;  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string
        if (text.empty() || end != text.c_str() + text.size()) message += " is not a number";
        else if (!(x >= lo && x <= hi)) message += " is outside " + range;
        else message.clear();
        return message;
      },
      range));
  return option;
}

std::pair<int, int> parse_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra))
    throw InputError("--size: expected WxH, e.g. 512x512 (got '" + text + "')");
  return {w, h};
}

void check_total_pixels(long long images, int width, int height, const std::string& what) {
  const long long w = std::max(width, 0), h = std::max(height, 0);
  if (images <= 0 || w * h <= kMaxTotalPixels / images) return;
  throw InputError(std::to_string(images) + " " + what + " of " + std::to_string(w) + "x" + std::to_string(h) +
                   " pixels: more than the limit of " + std::to_string(kMaxTotalPixels) +
                   " pixels (2^28) per run (fewer " + what + " or a smaller --size)");
}

std::vector<std::string> comma_items(const std::string& text) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    out.push_back(text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos));
    pos = comma == std::string::npos ? text.size() + 1 : comma + 1;
  }
  return out;
}

std::vector<int> parse_point_list(const std::string& text, const std::vector<std::string>& names) {
  std::vector<int> out;
  for (const std::string& item : comma_items(text)) {
    // A name of the file's: whole ("O/c0/p3") or its last part ("p3") when one point has it.
    int named = -1, matches = 0;
    for (std::size_t k = 0; k < names.size(); ++k) {
      const std::string& n = names[k];
      const std::size_t slash = n.rfind('/');
      if (n == item) {
        named = static_cast<int>(k), matches = 1;
        break;
      }
      if (slash != std::string::npos && n.compare(slash + 1, std::string::npos, item) == 0) named = static_cast<int>(k), ++matches;
    }
    if (matches == 1) {
      out.push_back(named);
      continue;
    }
    if (matches > 1) throw InputError("--points: '" + item + "' names " + std::to_string(matches) + " points (give the whole name)");
    std::string digits = item;
    if (!digits.empty() && (digits[0] == 'P' || digits[0] == 'p')) digits = digits.substr(1);
    try {
      std::size_t used = 0;
      const int k = std::stoi(digits, &used);
      if (used != digits.size()) throw std::invalid_argument(digits);
      out.push_back(k);
    } catch (const std::exception&) {
      throw InputError("--points: '" + item + "' is neither a point index (K or PK) nor a name of the file's points");
    }
  }
  return out;
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

}  // namespace cmr::cli
