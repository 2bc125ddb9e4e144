#pragma once
// The error channels of every cmr module, in one header (spline is the
// bottom module, so every library can include it):
//
//  * Programming errors (a broken internal invariant): CMR_CHECK, always on
//    (Release too), prints "cmr: internal error: EXPR (FILE:LINE)" and
//    aborts. Never used for anything a user can cause.
//  * Bad user data (a malformed spline file, a point index out of range, an
//    option outside its range): cmr::InputError, whose message names the
//    field and index and says what is wrong in one line. The cmr command
//    maps it to exit code 2.
//  * Environment failures (no Vulkan device, a device lost, out of device
//    memory, a full disk, an I/O error, a permission the process lacks):
//    cmr::EnvironmentError. The cmr command maps it to exit code 3. The
//    backends' errors derive from it (BackendError, region/region.hpp;
//    vk::RegionFailure, which also carries the vk::Error); inside vk/ the
//    Vulkan boundary returns vk::Result (vk/error.hpp), and vk/ turns a
//    failure into an EnvironmentError where it leaves that boundary.
//  * A computation stopped because its caller asked (a cancel flag it
//    handed in was set: the Python module's KeyboardInterrupt):
//    cmr::Cancelled. No result exists; nothing was written.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace cmr {

/// Bad user data (exit code 2 of the cmr command).
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// An environment failure (exit code 3 of the cmr command).
class EnvironmentError : public std::runtime_error {
 public:
  explicit EnvironmentError(const std::string& message) : std::runtime_error(message) {}
};

/// A computation stopped at its caller's request (a set cancel flag).
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

[[noreturn]] inline void check_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "cmr: internal error: %s (%s:%d)\n", expr, file, line);
  std::abort();
}

}  // namespace cmr

/// A programming-error check, always on: aborts with the expression and file:line.
#define CMR_CHECK(expr) ((expr) ? void(0) : ::cmr::check_failed(#expr, __FILE__, __LINE__))
