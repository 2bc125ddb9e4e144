#pragma once
/// The errno of the first failed write to standard output by a writer that
/// streams while it works (report/analyze_json.cpp): std::ostream keeps only
/// a bad bit, and by the time cmr's main checks stdout after the command
/// (tools/main.cpp, finish_stdout) errno is long gone. 0: none seen.
#include <atomic>
#include <cerrno>
#include <iostream>

namespace cmr {

inline std::atomic<int>& first_stdout_error() {
  static std::atomic<int> error{0};
  return error;
}

/// Writes `n` bytes to `out` (n = 0 and bytes = nullptr: flushes it); when
/// `out` is std::cout and that fails, remembers its errno (the first one)
/// for finish_stdout.
inline void write_noting_stdout_error(std::ostream& out, const char* bytes, std::streamsize n) {
  if (!out) return;  // failed before: nothing more goes out
  errno = 0;
  if (bytes != nullptr) out.write(bytes, n);
  else out.flush();
  if (!out && &out == &std::cout && errno != 0) {
    int expected = 0;
    first_stdout_error().compare_exchange_strong(expected, errno);
  }
}

}  // namespace cmr
