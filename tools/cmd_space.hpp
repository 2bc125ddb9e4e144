#pragma once
/// Space curves on the command line (issue 25): what `cmr analyze`, `cmr
/// region` and `cmr report` do when FILE has [x, y, z] points
/// (spline_file_dimension == 3). The planar commands call these; nothing
/// here links CLI11.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/space_analyze.hpp"
#include "report/space_report.hpp"
#include "step/step.hpp"

namespace cmr::cli {

/// `cmr analyze FILE [--torsion]` on a space curve: prints the JSON.
void run_space_analyze(const std::string& file, int depth, bool torsion, const ContinuityTolerances& continuity,
                       bool pretty, double torsion_tolerance = 0);

struct SpaceRegionArgs {
  std::string file, point, plane, size = "256x256", view, backend = "auto";
  int depth = kDefaultDepth;
  std::string png, labels, depth_map;
  bool stats = false, pretty = false;
  std::string mesh;        ///< --mesh OUT.obj|OUT.ply: the tube and the plane patch (draw/space_mesh.hpp)
  double tube_radius = 0;  ///< --tube-radius (0: mesh::default_tube_radius)
};
/// `cmr region FILE --point K [--plane xy|yz|zx|O,U,V]` on a space curve:
/// writes the outputs (all or none) and prints the JSON summary. The CPU
/// backend only: --backend vulkan is an InputError.
void run_space_region(const SpaceRegionArgs& args);

/// `cmr report FILES --out DIR` when every file of the run is a space curve:
/// DIR/report.json (the planar report's schema, with findings) and
/// DIR/index.html (report/space_report.hpp), and the CI files the planar
/// run writes: --junit (one suite per file, one case per curve), --sarif
/// (one result per finding, invalid inputs as results), --markdown (the
/// planar run's summary) and --baseline (only new findings fail). All outputs are one OutputSet (all or none).
struct SpaceReportRun {
  std::vector<std::string> files;  ///< collected (report::collect_files)
  std::vector<std::string> bases;  ///< per file, its folder argument (collect_files' bases)
  std::string out;
  report::SpaceReportOptions options;
  report::ReportOptions parsed;  ///< --require as the planar report reads it (SARIF's rules)
  std::optional<std::filesystem::path> junit, sarif, baseline, source_root;
  std::optional<std::filesystem::path> markdown;  ///< --markdown (report/markdown.hpp)
  bool pretty = false;
  /// No summary line (the space part of a run with planar inputs too:
  /// tools/cmd_report.cpp prints the merged run's line).
  bool quiet = false;
};
/// Returns the exit code: 2 when a file is invalid, else with a baseline 1
/// when a finding is new, else 1 when a required check or gate fails.
int run_space_report(const SpaceReportRun& run);

/// `cmr edit MODEL.step --edge '#1234'`: that edge of the STEP model as a
/// space spline (read_step_curves, the spline `cmr import` writes for it),
/// and where the editor saves it: `cmr import`'s file name beside the model
/// (MODEL_1234.json), never the model. InputError, one line: a spec that is
/// not one #id, an id that names no B-spline or Bezier edge (with the ids
/// that do), a file that is not STEP.
struct StepEdge {
  SpaceSpline spline;
  std::filesystem::path save_path;
};
StepEdge open_step_edge(const std::filesystem::path& model, const std::string& spec);

/// `cmr fix FILE` on a space curve (design/space_fix.hpp, docs/fix.md):
/// the nearest certified move of one point in a plane through it; prints the
/// JSON and writes --out and --png (all or none). InputError (exit 2) when none
/// is found.
struct SpaceFixArgs {
  std::string file, require = "cmr", points, keep = "g1", plane, out, png;
  double max_move = 0, tolerance = 1e-6;
  int depth = kDefaultDepth;
  bool pretty = false;
};
void run_space_fix(const SpaceFixArgs& args);

/// A STEP model's curves and chains (import::read_step_curves) under its
/// time budget (5 s + 4 s per MB, or the environment's
/// CMR_STEP_TIME_BUDGET): past it the process ends with one line and exit 2,
/// before anything is written (tools/cmd_import.cpp).
import::StepCurves read_step_within_budget(const std::string& file);

/// `cmr fix MODEL.step --chain N` (step/chain_fix.hpp, docs/fix.md "Chains
/// of STEP edges"): every failing edge of the chain fixed with its ends'
/// jets held; prints the JSON and writes the chain's edges into --out DIR
/// (all or none). InputError (exit 2) when no certified fix is found.
struct ChainFixArgs {
  std::string file, require = "cmr", keep = "g2", out;
  int chain = 0;  ///< 1-based, as `cmr import` numbers the chains
  double max_move = 0, tolerance = 1e-6;
  int depth = kDefaultDepth;
  bool pretty = false;
};
void run_chain_fix(const ChainFixArgs& args);

}  // namespace cmr::cli
