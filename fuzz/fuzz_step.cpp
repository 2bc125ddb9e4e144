// STEP models through the importer's own entry point, read_step_curves (a
// temp NAME.step, as `cmr import` reads one): the pre-scan (nesting,
// numbers out of range), OpenCASCADE's reader and transfer, and the
// conversion of every B-spline/Bezier edge, checked by evaluation. Every
// curve it returns has finite points and converts to its JSON. Seeds:
// fuzz/corpus/step (cmr_step_model OUT seed). -timeout in fuzz/run.sh
// stands for `cmr import`'s time budget (step_time_budget).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "spline/errors.hpp"
#include "step/step.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
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
