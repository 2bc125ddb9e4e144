#pragma once
// Error channels shared by every cmr module.
//
//  * Programming errors (a broken internal invariant): CMR_CHECK, always on,
//    aborts with file:line. Never used for anything a user can cause.
//  * Bad user data (a malformed spline file, a point index out of range):
//    cmr::InputError, whose message names the field and index and says what is
//    wrong in one line. The CLI maps it to exit code 2.
//  * Environment failures (no Vulkan device, out of memory) are result types in
//    vk/; the CLI maps them to exit code 3.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace cmr {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

[[noreturn]] inline void check_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "cmr: internal error: %s (%s:%d)\n", expr, file, line);
  std::abort();
}

}  // namespace cmr

#define CMR_CHECK(expr) ((expr) ? void(0) : ::cmr::check_failed(#expr, __FILE__, __LINE__))
