// STEP models through the importer's own entry point, read_step_curves (a
// temp NAME.step, as `cmr import` reads one): the pre-scan (nesting,
// numbers out of range), OpenCASCADE's reader and transfer, and the
// conversion of every B-spline/Bezier edge, checked by evaluation. Every
// curve it returns has finite points and converts to its JSON. Seeds:
// fuzz/corpus/step (cmr_step_model OUT seed, and occt-loader-null-entity.step: a
// finding of CI run 52 that crashes OpenCASCADE's loader under ASan). -timeout in fuzz/run.sh
// stands for `cmr import`'s time budget (step_time_budget).
// Like `cmr import`, the harness must run single-threaded: the importer's
// crash probe (a forked child) is skipped beside other threads, so a fuzzer
// thread (libFuzzer's -rss_limit_mb) would hide what the probe refuses.
// fuzz/run.sh passes -rss_limit_mb=0; the harness stops if that changes.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "spline/errors.hpp"
#include "step/step.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool single_thread = [] {
    std::size_t n = 0;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) (void)task, ++n;
    return n == 1;
  }();
  if (!single_thread) {
    std::fputs("fuzz_step: another thread runs (libFuzzer's -rss_limit_mb?); the crash probe would be skipped: "
               "run with -rss_limit_mb=0\n",
               stderr);
    std::exit(2);
  }
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("cmr_fuzz_step_" + std::to_string(::getpid()) + ".step");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const cmr::import::StepCurves curves = cmr::import::read_step_curves(path);
    for (const cmr::import::StepCurve& c : curves.curves) {
      for (const auto& p : c.points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
      (void)cmr::import::step_curve_json(c).dump();
    }
  } catch (const cmr::InputError&) {
  }
  return 0;
}
