#pragma once
/// Shared pieces of the cmr command: exit codes, stdout and output files, and
/// the registration of each subcommand. Only the command links CLI11; this
/// header names CLI::App without including it.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "bezierize/region.hpp"
#include "tools/io.hpp"

namespace CLI {
class App;
}

namespace cmr::cli {

/// The command's exit codes.
enum Exit : int { kOk = 0, kFail = 1, kInvalid = 2, kEnvironment = 3 };

/// Environment failures (exit 3) are the libraries' error type.
using EnvironmentError = cmr::EnvironmentError;

/// The region backend of --backend (vulkan|cpu), --precision (fp64|fp32)
/// and --device NAME: one per command run, so Vulkan contexts and compiled
/// pipelines are reused by every render. The Vulkan device is opened at the
/// first render (a run that renders nothing needs none); when it is missing
/// or fails, render throws EnvironmentError with a line that says how to
/// select lavapipe, or to use --backend cpu.
std::shared_ptr<RegionBackend> make_region_backend(const std::string& backend, const std::string& precision = "fp64",
                                                   const std::string& device = "");

/// Prints JSON to stdout (2-space indent, one trailing newline).
void print_json(const nlohmann::ordered_json& doc);

/// Throws InputError unless `path`'s folder exists (checked before any work,
/// so that a bad output path fails fast and writes nothing).
void check_output_path(const std::filesystem::path& path, const std::string& option);

/// Files written by one command: all or none. Each file is written with
/// cmr::write_file_atomic; if a later one fails, the earlier ones are removed
/// again before the error propagates.
class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();
  /// Writes bytes to path (atomically) and remembers it.
  void write(const std::filesystem::path& path, std::string_view bytes);
  /// Keeps the files: call after the last write.
  void keep() { written_.clear(); }

 private:
  std::vector<std::filesystem::path> written_;
};

/// Each command registers itself; the callback sets the exit code.
void add_segments_command(CLI::App& app, int& exit_code);
/// `cmr analyze`: see README "Command line".
void add_analyze_command(CLI::App& app, int& exit_code);
/// `cmr region`: see README "Command line".
void add_region_command(CLI::App& app, int& exit_code);
/// `cmr figures`: see README "Command line".
void add_figures_command(CLI::App& app, int& exit_code);
/// `cmr report`: see README "Command line".
void add_report_command(CLI::App& app, int& exit_code);
void add_knots_command(CLI::App& app, int& exit_code);
void add_kcurve_command(CLI::App& app, int& exit_code);
/// `cmr import`: fonts and SVG paths as spline files (tools/cmd_import.cpp).
void add_import_command(CLI::App& app, int& exit_code);

/// A κ-curve points file: {"points": [[x,y],...], "closed": false} ("closed"
/// optional). Errors name the file, field and index (InputError).
struct KCurvePoints {
  std::vector<glm::dvec2> points;
  bool closed = false;
};
KCurvePoints kcurve_points_from_json(const nlohmann::json& doc);
KCurvePoints read_kcurve_points_file(const std::filesystem::path& path);
void add_edit_command(CLI::App& app, int& exit_code);  // tools/cmd_edit.cpp, built with the editor

}  // namespace cmr::cli
