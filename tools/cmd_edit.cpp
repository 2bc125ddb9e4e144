// cmr edit [FILE]: the interactive designer (tools/edit/), its scripted mode
// and its benchmark.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

#include "spline/errors.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"

#include <CLI/CLI.hpp>
#include "tools/edit/window.hpp"

namespace cmr::cli {
namespace {

struct EditArgs {
  std::string file, script, screenshot, device, glyph;
  std::string size = "1024x768";
  bool bench = false;
  int frames = 200;
  int points = 10000;
  int point = 3;
  bool no_vsync = false;
  std::string region_path = "auto";
  std::string precision;
  std::string edge;  // --edge '#1234': a STEP model's edge
};

edit::RegionPath parse_region_path(const std::string& text) {
  if (text == "auto") return edit::RegionPath::automatic;
  if (text == "gpu") return edit::RegionPath::gpu;
  if (text == "upload") return edit::RegionPath::upload;
  throw InputError("--region-path: expected auto, gpu or upload (got '" + text + "')");
}

std::pair<int, int> parse_window_size(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra))
    throw InputError("--size: expected WxH, e.g. 1024x768 (got '" + text + "')");
  return {w, h};
}

}  // namespace

void add_edit_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<EditArgs>();
  auto* cmd = app.add_subcommand("edit", "Design interactively: drag points and see their regions live");
  cmd->add_option("FILE", a->file,
                  "spline file (JSON), font or UFO (with --glyph), .glif or SVG file to open; without it, a cubic "
                  "Bezier curve");
  cmd->add_option("--glyph", a->glyph,
                  "a font's glyph to edit, all its contours (one character or U+hex; a UFO's: the glyph name, "
                  "and save writes back into its .glif)");
  cmd->add_option("--script", a->script, "run these input events (format: docs/edit.md) in the real window, then exit");
  cmd->add_option("--screenshot", a->screenshot, "PNG of the presented window after the script");
  cmd->add_option("--size", a->size, "window size WxH")->capture_default_str();
  cmd->add_option("--device", a->device, "Vulkan device name (substring, case-insensitive)");
  cmd->add_flag("--no-vsync", a->no_vsync, "do not wait for the display between frames");
  cmd->add_option("--region-path", a->region_path,
                  "auto (gpu on a GPU, upload on a CPU device such as lavapipe), gpu (region shader drawn into "
                  "the window) or upload (CPU engine, uploaded)")
      ->capture_default_str();
  cmd->add_option("--precision", a->precision, "gpu path: the region shader's arithmetic (default: fp64 where "
                  "the device has it); labels are certified either way")
      ->check(CLI::IsMember({"fp64", "fp32"}));
  cmd->add_flag("--bench", a->bench, "replay a scripted drag (FILE or the Fig. 8 spline) and print frame times");
  cmd->add_option("--frames", a->frames, "--bench: frames per run")->capture_default_str();
  cmd->add_option("--points", a->points,
                  "--bench: region frames of a spline of this many points against a 6-point one's (0: skip)")
      ->capture_default_str();
  cmd->add_option("--point", a->point,
                  "the point selected when the editor opens (default: the first point whose region shows in the "
                  "view); --bench: the dragged point (default 3)");
  cmd->add_option("--edge", a->edge,
                  "a STEP model's B-spline or Bezier edge to edit, by its entity id ('#1234', as cmr import names "
                  "it); save writes it as MODEL_1234.json beside the model");
  cmd->callback([a, cmd, &exit_code] {
    const auto [w, h] = parse_window_size(a->size);
    std::string ext = std::filesystem::path(a->file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
    const bool step = ext == ".step" || ext == ".stp";
    if (step && a->edge.empty())
      throw InputError(a->file + ": a STEP model: name the edge to edit with --edge '#1234' (cmr import " + a->file +
                       " lists them)");
    if (!step && !a->edge.empty()) throw InputError("--edge: for STEP models (.step, .stp), not for " + a->file);
    if (a->bench) {
      edit::BenchOptions b;
      b.file = a->file;  // empty: the embedded Fig. 8 spline
      b.width = w;
      b.height = h;
      if (a->frames < 1) throw InputError("--frames must be at least 1");
      b.frames = a->frames;
      b.point = a->point;
      if (a->points != 0 && (a->points < 7 || a->points > 1000000))
        throw InputError("--points must be 0 or lie in 7..1000000");
      b.points = a->points;
      b.device = a->device;
      b.region_path = parse_region_path(a->region_path);
      exit_code = edit::run_bench(b);
      return;
    }
    edit::EditOptions o;
    o.file = a->file;
    if (step) {  // the edge as a space curve (tools/cmd_space.hpp); save writes MODEL_ID.json
      StepEdge e = open_step_edge(a->file, a->edge);
      o.file = e.save_path;
      o.source_label = std::filesystem::path(a->file).filename().string() + ", " + e.spline.name();
      o.space = std::move(e.spline);
    }
    o.glyph = a->glyph;
    o.script = a->script;
    o.screenshot = a->screenshot;
    o.width = w;
    o.height = h;
    o.device = a->device;
    o.vsync = !a->no_vsync;
    o.region_path = parse_region_path(a->region_path);
    if (cmd->count("--point") > 0) o.point = a->point;
    if (!a->precision.empty())
      o.precision = a->precision == "fp32" ? vk::RegionPrecision::fp32 : vk::RegionPrecision::fp64;
    exit_code = edit::run_editor(o);
  });
}

}  // namespace cmr::cli
