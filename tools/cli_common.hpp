#pragma once
/// Shared pieces of the cmr command: exit codes, stdout and output files, and
/// the registration of each subcommand. Only the command links CLI11; this
/// header names CLI::App without including it.
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"
#include "io/output.hpp"
#include "tools/field_flags.hpp"

namespace CLI {
class App;
class Option;
}

namespace cmr {
class SpaceRegionBackend;  // region/space_region.hpp
}

namespace cmr::cli {

/// The command's exit codes.
enum Exit : int { kOk = 0, kFail = 1, kInvalid = 2, kEnvironment = 3 };

/// Environment failures (exit 3) are the libraries' error type (spline/errors.hpp).
using cmr::EnvironmentError;

/// The region backend of --backend (auto|vulkan|cpu), --precision (fp64|fp32)
/// and --device NAME: one per command run, so Vulkan contexts and compiled
/// pipelines are reused by every render. The choice is the library's
/// (vk::make_region_backend, vk/backend_choice.hpp: "auto" is Vulkan on a
/// candidate GPU when measured faster for the job, else the CPU backend);
/// this maps the option strings onto its aggregate, with `frames` the
/// frames the command will render (0: many, not known), the cache directory
/// user_cache_dir() and, for tests, CMR_VK_FAULT=device_lost|out_of_memory|
/// pipeline_rejected (a Vulkan failure to inject), and prints its notes on
/// stderr ("note: ..."). A build
/// without Vulkan renders "auto" and "cpu" on the CPU; "vulkan" throws
/// EnvironmentError at the first render.
std::shared_ptr<RegionBackend> make_region_backend(const std::string& backend, const std::string& precision = "fp64",
                                                   const std::string& device = "", int frames = 1);
/// The space-region backend of --backend (vk::make_space_region_backend):
/// "vulkan" the first device with shaderFloat64, "auto" and "cpu" the CPU.
std::shared_ptr<SpaceRegionBackend> make_space_region_backend(const std::string& backend);
/// $XDG_CACHE_HOME/cmr, else $HOME/.cache/cmr (only absolute paths count);
/// empty when neither is set: nothing is kept across runs.
std::string user_cache_dir();
/// The --backend choices, in help order.
inline const std::vector<std::string> kBackendChoices = {"auto", "vulkan", "cpu"};

/// JSON text as cmr emits it: compact on one line, or with `pretty` indented
/// by 2 spaces; one trailing newline either way. File names that are not
/// UTF-8 (JSON cannot hold them) have each invalid byte replaced by U+FFFD.
std::string json_text(const nlohmann::ordered_json& doc, bool pretty);
/// Prints json_text(doc, pretty) to stdout.
void print_json(const nlohmann::ordered_json& doc, bool pretty);
/// One JSON object printed to stdout member by member, so that a long array
/// (analyze's segments and joints) is never held as one tree: memory stays
/// that of one element. The text is byte for byte json_text of the whole
/// object (compact or indented by 2). Members and arrays are written in call
/// order; finish() closes the object and ends the line.
class JsonObjectStream {
 public:
  JsonObjectStream(std::ostream& out, bool pretty);
  void member(const std::string& key, const nlohmann::ordered_json& value);
  void begin_array(const std::string& key);
  void element(const nlohmann::ordered_json& value);
  void end_array();
  void finish();

 private:
  void key(const std::string& name);
  void value(const nlohmann::ordered_json& v, int indent);
  std::ostream& out_;
  bool pretty_;
  bool first_member_ = true;
  bool first_element_ = true;
};
/// Adds the --pretty flag (indented JSON) every JSON-printing command has.
void add_pretty_flag(CLI::App& cmd, bool& pretty);
/// Adds --backend auto|vulkan|cpu, --device NAME and, where `precision` is
/// given, --precision fp64|fp32: the options of make_region_backend, the same
/// on every command that renders regions.
void add_backend_options(CLI::App& cmd, std::string& backend, std::string& device, std::string* precision = nullptr);
/// Adds --angle-tol DEG and --curvature-tol REL (G1/G2 at joints), the same
/// on analyze and report; validate(tolerances) checks them.
void add_continuity_options(CLI::App& cmd, ContinuityTolerances& tolerances);

/// Checks a numeric option against LO..HI with the one range message of the
/// command: "--depth: 99 is outside 0..30". Returns `option`.
CLI::Option* in_range(CLI::Option* option, double lo, double hi);

/// The output path check of every command (io/output.hpp).
using cmr::check_output_path;

/// --size WxH (InputError otherwise; the range is RegionProblem::make's).
std::pair<int, int> parse_size(const std::string& text);
/// Refuses (InputError) `images` x `width` x `height` above kMaxTotalPixels:
/// "10001 steps of 16384x16384 pixels: more than the limit of 268435456 pixels (2^28) per run ...".
void check_total_pixels(long long images, int width, int height, const std::string& what);
/// --view X0,Y0,X1,Y1 (InputError otherwise; the extent is RegionProblem::make's).
View parse_view(const std::string& text);
/// The items of a comma-separated list, in order ("a,,b" has an empty
/// second item; "" is one empty item).
std::vector<std::string> comma_items(const std::string& text);
/// --points K,K2,... or P1,P2,... (cmr fix, planar and space), or names of
/// the file's points (`names`: its "point_names", as `cmr import` writes
/// them: the whole name "O/c0/p3", or its last part "p3" when just one point
/// has it): the indices (InputError for anything else; the caller checks the
/// range).
std::vector<int> parse_point_list(const std::string& text, const std::vector<std::string>& names = {});

/// Each command registers itself; the callback sets the exit code.
/// The environment switches of the region render, read here and nowhere in
/// the libraries: CMR_SIMD=scalar|sse2|avx2 (set_simd_level; an unknown or
/// unavailable level prints one line on stderr and the best is used) and
/// CMR_BLOCK_REUSE=0 (set_block_reuse(0)). cmr and the benchmarks call it
/// first thing.
void read_environment();

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
/// `cmr sweep`: see README "Command line".
void add_sweep_command(CLI::App& app, int& exit_code);
/// `cmr import`: fonts and SVG paths as spline files (tools/cmd_import.cpp).
void add_import_command(CLI::App& app, int& exit_code);
/// `cmr fix`: the nearest certified repair (tools/cmd_fix.cpp, docs/fix.md).
void add_fix_command(CLI::App& app, int& exit_code);

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
