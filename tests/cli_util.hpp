#pragma once
// Runs the cmr binary (CMR_BINARY, set by CMake) and captures its outcome.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace cmr::test {

namespace fs = std::filesystem;

/// A sanitizer build (tools/sanitize.sh: -fsanitize=address,undefined, -O1).
/// Its programs run several times slower than a Release build's, ASan cannot
/// start under `ulimit -v` (it reserves terabytes of shadow address space),
/// and LeakSanitizer cannot run under ptrace (strace). The few tests that rely
/// on those skip or give cmr more time there, saying so (docs/outputs.md).
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif

/// The environment a command traced by strace needs: LeakSanitizer off in a
/// sanitizer build (it refuses to run under ptrace), nothing otherwise.
inline std::string traced_env() { return kSanitizerBuild ? "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 " : ""; }

struct Outcome {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / ("cmr_cli_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

/// Runs a shell command with stdout and stderr captured (killed by a signal:
/// code 128 + the signal, as a shell reports it).
inline Outcome run_captured(const std::string& command) {
  const fs::path dir = scratch();
  const std::string cmd = command + " >" + (dir / "out").string() + " 2>" + (dir / "err").string();
  const int status = std::system(cmd.c_str());
  Outcome r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(dir / "out");
  r.err = slurp(dir / "err");
  return r;
}

/// Runs cmr with `args` (a shell word list), its cache directory (the
/// pipeline cache, the measured backend rates) this test's own: a rate
/// another test or another run on the machine recorded in ~/.cache would
/// change what `--backend auto` does and notes here.
inline Outcome run(const std::string& args) {
  return run_captured("XDG_CACHE_HOME=" + (scratch() / "cache").string() + " " + std::string(CMR_BINARY) + " " + args);
}

inline std::string write(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace cmr::test
