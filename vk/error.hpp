// Error reporting for cmr::vk: an error code, the VkResult behind it (if any)
// and a one-line message the user can act on. Library code never throws for
// Vulkan failures, never prints and never exits; it returns Result<T>.
#pragma once

#include <vulkan/vulkan_core.h>

#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

namespace cmr::vk {

enum class Errc {
  loader_missing,    // the Vulkan loader (libvulkan) is unusable or too old
  no_device,         // the loader found no Vulkan driver / physical device
  device_not_found,  // ContextOptions::device_name matched no device
  missing_feature,   // the chosen device lacks something required (fp64, ...)
  out_of_memory,     // host or device memory exhausted
  device_lost,       // the GPU reset or hung (e.g. driver watchdog)
  size_unsupported,  // an image/buffer/push-constant size is 0 or over a limit
  shader_invalid,    // SPIR-V rejected (bad magic, pipeline creation failed)
  other,             // any other Vulkan failure; see message
};

// Stable lower-case name of an Errc ("out_of_memory"), for logs and tests.
constexpr const char* to_string(Errc code) noexcept {
  switch (code) {
    case Errc::loader_missing: return "loader_missing";
    case Errc::no_device: return "no_device";
    case Errc::device_not_found: return "device_not_found";
    case Errc::missing_feature: return "missing_feature";
    case Errc::out_of_memory: return "out_of_memory";
    case Errc::device_lost: return "device_lost";
    case Errc::size_unsupported: return "size_unsupported";
    case Errc::shader_invalid: return "shader_invalid";
    case Errc::other: return "other";
  }
  return "unknown";
}

struct Error {
  Errc code = Errc::other;
  // The failing call's result, or VK_SUCCESS when the error was detected by
  // cmr::vk itself (bad size, device name not found, ...).
  VkResult vk_result = VK_SUCCESS;
  // One line (no '\n'), meant to be shown to the user; the options it names
  // are marked as fields (spline/fields.hpp: plain_fields, or a program's own
  // names for them).
  std::string message;
};

// Either a T or an Error. Accessing the wrong alternative (value() on an
// error, error() on a value) throws std::bad_variant_access; check first.
template <class T>
class [[nodiscard]] Result {
  static_assert(!std::is_same_v<std::remove_cv_t<T>, Error>, "Result<Error> is ambiguous");

 public:
  Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : state_(std::in_place_index<1>, std::move(error)) {}  // NOLINT: implicit by design

  bool has_value() const noexcept { return state_.index() == 0; }
  explicit operator bool() const noexcept { return has_value(); }

  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  // Moves the value out; the Result is left holding a moved-from T.
  T&& take() { return std::get<0>(std::move(state_)); }

  const Error& error() const& { return std::get<1>(state_); }

 private:
  std::variant<T, Error> state_;
};

// Success without a value, or an Error.
template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)) {}  // NOLINT: implicit by design

  bool has_value() const noexcept { return !error_.has_value(); }
  explicit operator bool() const noexcept { return has_value(); }

  const Error& error() const& {
    if (!error_) throw std::bad_variant_access();
    return *error_;
  }

 private:
  std::optional<Error> error_;
};

}  // namespace cmr::vk
