// cmr import FONT [--glyphs A-Z,a-z] [--out DIR] | cmr import FILE.svg [--out DIR]:
// font glyph contours (io/font.hpp) and SVG subpaths
// (io/svg.hpp) as spline files, one per contour or subpath, all
// written or none (cmr::OutputSet; the output folder is created if missing).
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <set>

#include <CLI/CLI.hpp>

#include "spline/errors.hpp"
#include "tools/cli_common.hpp"
#include "io/font.hpp"
#include "io/ufo.hpp"
#include "io/svg.hpp"
#include "io/obj.hpp"
#include "step/step.hpp"
#include "tools/cmd_space.hpp"

namespace cmr::cli {

namespace {

struct ImportArgs {
  std::string input;
  std::string glyphs = "A-Z,a-z";
  std::string out = ".";
  bool y_down = false;
  std::string location;
  std::string edges;
};

/// The STEP read's time budget: import::step_time_budget, or the environment
/// variable CMR_STEP_TIME_BUDGET (seconds, > 0), which replaces it for tests.
double step_read_budget(std::uintmax_t bytes) {
  if (const char* env = std::getenv("CMR_STEP_TIME_BUDGET"); env != nullptr && *env != '\0') {
    char* end = nullptr;
    const double s = std::strtod(env, &end);
    if (*end == '\0' && s > 0 && std::isfinite(s)) return s;
  }
  return import::step_time_budget(bytes);
}

// Ends the process with one line on stderr and exit 2 when `seconds` pass
// before it is destroyed: the STEP reader's budget (step_time_budget).
// OpenCASCADE's shape healing runs loops that poll nothing, so an alarm,
// not a cancel flag; it fires before the output set exists, so nothing is
// half-written. A process timer (setitimer, SIGALRM), not a thread: the
// reader forks a crash probe (step/step_occt.cpp), and a child forked
// beside another thread can inherit a lock that thread held (the
// sanitizers' allocator's) and never finish. A fork's child inherits no
// timer; the probe's child dies with this process (PR_SET_PDEATHSIG).
char budget_line[8192];
std::size_t budget_line_size = 0;

extern "C" void budget_spent(int) {
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, budget_line, budget_line_size);
  std::_Exit(kInvalid);
}

class BudgetAlarm {
 public:
  BudgetAlarm(double seconds, const std::string& message) {
    const std::string line = "cmr: " + message + "\n";
    budget_line_size = std::min(line.size(), sizeof budget_line);
    std::memcpy(budget_line, line.data(), budget_line_size);
    budget_line[budget_line_size - 1] = '\n';  // one line, even when cut
    struct sigaction on_alarm {};
    on_alarm.sa_handler = budget_spent;
    sigemptyset(&on_alarm.sa_mask);
    ::sigaction(SIGALRM, &on_alarm, &previous_);
    const double s = std::min(seconds, 1e8);  // time_t holds it
    itimerval t{};
    t.it_value.tv_sec = static_cast<time_t>(s);
    // At least 1 us: a zero it_value disarms the timer.
    t.it_value.tv_usec = std::max<suseconds_t>(1, static_cast<suseconds_t>((s - std::floor(s)) * 1e6));
    ::setitimer(ITIMER_REAL, &t, nullptr);
  }
  BudgetAlarm(const BudgetAlarm&) = delete;
  BudgetAlarm& operator=(const BudgetAlarm&) = delete;
  ~BudgetAlarm() {
    const itimerval off{};
    ::setitimer(ITIMER_REAL, &off, nullptr);
    ::sigaction(SIGALRM, &previous_, nullptr);
  }

 private:
  struct sigaction previous_ {};
};

}  // namespace

import::StepCurves read_step_within_budget(const std::string& file) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  const double budget = step_read_budget(ec ? 0 : bytes);
  char secs[32];
  std::snprintf(secs, sizeof secs, "%.3g", budget);
  const BudgetAlarm alarm(budget, file + ": not read within its time budget of " + secs + " s (" +
                                      std::to_string(ec ? 0 : bytes) +
                                      " bytes: 5 s + 4 s per MB; OpenCASCADE did not finish with it)");
  return import::read_step_curves(file);
}

void add_import_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ImportArgs>();
  auto* cmd = app.add_subcommand("import", "Font glyphs (TrueType, CFF), SVG paths, OBJ or STEP curves as spline files");
  cmd->add_option("INPUT", args->input, "font file (.ttf, .otf, ...), font source (NAME.ufo folder, .glif), SVG file (.svg), Wavefront OBJ curves "
                  "(.obj) or STEP model (.step, .stp)")->required();
  cmd->add_option("--glyphs", args->glyphs, "characters of a font: A-Z,a-z,U+00E9 (ranges, comma separated), or all")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output folder (created if missing)")->capture_default_str();
  cmd->add_option("--location", args->location, "variable fonts: the instance, axis tags and user values (wght=700,opsz=14)");
  cmd->add_option("--edges", args->edges,
                  "STEP: only these edges, by STEP entity id ('#1234,#1240'; cmr import names each curve by its id)");
  cmd->add_flag("--y-down", args->y_down,
                "SVG: keep SVG's y-down coordinates (default: flipped to cmr's y-up frame, (x, y) -> (x, -y))");
  cmd->callback([args, cmd, &exit_code] {
    const std::filesystem::path input = args->input;
    std::string ext = input.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    OutputSet files;
    int written = 0, rational = 0;
    if (ext != ".svg" && args->y_down) throw InputError("--y-down: only for SVG files, not for " + args->input);
    if (ext != ".step" && ext != ".stp" && cmd->count("--edges") > 0)
      throw InputError("--edges: only for STEP files (.step, .stp), not for " + args->input);
    if (ext == ".svg") {
      if (cmd->count("--glyphs") > 0) throw InputError("--glyphs: only for fonts, not for " + args->input);
      const auto paths = import::read_svg(input, {.flip_y = !args->y_down});
      const std::filesystem::path dir = args->out;
      files.create_folder(dir);
      files.own_folder(dir);  // the files an earlier import wrote there and this one does not go
      int index = 0;
      for (const import::PathSpline& s : paths) {
        files.stage(dir / (input.stem().string() + "_" + std::to_string(index++) + ".json"),
                    import::path_json(s).dump(2) + "\n");
        ++written;
        rational += s.rational() ? 1 : 0;
      }
      files.commit();
      std::cout << "imported " << written << (written == 1 ? " subpath" : " subpaths") << " (" << rational
                << " rational) from " << args->input << " into " << dir.string() << '\n';
    } else if (ext == ".obj") {  // space curves (io/obj.hpp, docs/space.md)
      if (cmd->count("--glyphs") > 0) throw InputError("--glyphs: only for fonts, not for " + args->input);
      const auto curves = import::read_obj_curves(input);
      const std::filesystem::path dir = args->out;
      files.create_folder(dir);
      files.own_folder(dir);  // as the other importers: an earlier import's files that this one does not write go
      for (const import::ObjCurve& c : curves) {
        files.stage(dir / (input.stem().string() + "_" + std::to_string(written) + "_" + import::file_stem(c.spline.name()) +
                           ".json"),
                    space_spline_to_json(c.spline).dump(2) + "\n");
        ++written;
      }
      files.commit();
      std::cout << "imported " << written << (written == 1 ? " space curve" : " space curves") << " from "
                << args->input << " into " << dir.string() << '\n';
    } else if (ext == ".step" || ext == ".stp") {  // B-spline curves and edges through OpenCASCADE (step/step.hpp)
      if (cmd->count("--glyphs") > 0) throw InputError("--glyphs: only for fonts, not for " + args->input);
      const std::vector<long long> ids =
          cmd->count("--edges") > 0 ? import::parse_step_edge_ids(args->edges) : std::vector<long long>{};
      import::StepCurves curves = read_step_within_budget(args->input);
      if (!ids.empty()) curves = import::select_step_edges(curves, ids, args->input);
      const std::filesystem::path dir = args->out;
      files.create_folder(dir);
      files.own_folder(dir);  // the files an earlier import wrote there and this one does not go
      for (const import::StepCurve& c : curves.curves) {
        files.stage(dir / (input.stem().string() + "_" + import::step_curve_stem(c) + ".json"),
                    import::step_curve_json(c).dump(2) + "\n");
        ++written;
        rational += c.weights.empty() ? 0 : 1;
      }
      files.commit();
      const std::string skipped = import::skipped_summary(curves);
      std::cout << "imported " << written << (written == 1 ? " space curve" : " space curves") << " (" << rational
                << " rational) of " << curves.edges << " edges from " << args->input << " into " << dir.string()
                << (skipped.empty() ? "" : "; skipped " + skipped) << '\n';
      // Chains of edges (the model's wires; step/step.hpp, StepChain): their
      // junctions' G1/G2/G3 and monotonicity, one line each.
      for (const std::string& line : import::step_chain_report(curves)) std::cout << line << '\n';
    } else if (import::is_font_path(input) || import::is_ufo_path(input)) {
      const bool all = args->glyphs == "all";
      const import::Font font =
          import::is_ufo_path(input)
              ? import::read_ufo(input, {all, all ? std::vector<std::uint32_t>{} : import::parse_glyph_spec(args->glyphs), {}})
              : import::read_font(input, all ? std::vector<std::uint32_t>{} : import::parse_glyph_spec(args->glyphs),
                                  args->location.empty() ? import::Location{} : import::parse_location(args->location));
      if (!args->location.empty() && import::is_ufo_path(input))
        throw InputError("--location: for variable fonts (.ttf, .otf), not for " + args->input);
      for (const import::Glyph& g : font.glyphs) {
        if (!g.error.empty()) throw InputError(g.error);  // all or none: the source names the line
        for (const std::string& n : g.notes) std::cerr << "note: " << g.name << ": " << n << '\n';
      }
      const std::filesystem::path dir = args->out;
      files.create_folder(dir);
      files.own_folder(dir);  // the files an earlier import wrote there and this one does not go
      std::set<std::string> stems;
      for (const import::Glyph& g : font.glyphs)
        for (const import::Contour& c : g.contours) {
          const std::string stem = import::file_stem(g.name) + "_c" + std::to_string(c.index);
          if (!stems.insert(stem).second) continue;  // a glyph asked for twice (two code points, one glyph)
          const bool labelled = c.index < static_cast<int>(g.point_labels.size());
          files.stage(dir / (stem + ".json"),
                      import::contour_json(c, labelled ? &g.point_labels[c.index] : nullptr).dump(2) + "\n");
          ++written;
        }
      files.commit();
      const auto counted = [](std::size_t n, const char* noun) {
        return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
      };
      std::cout << "imported " << counted(font.glyphs.size(), "glyph") << ", "
                << counted(static_cast<std::size_t>(written), "contour") << " (" << (font.cubic ? "cubic" : "quadratic")
                << ", "
                << (font.units_per_em > 0 ? std::to_string(font.units_per_em) + " units per em"
                                          : std::string("units per em unknown"))
                << ") from " << args->input << " into " << dir.string();
      if (!font.missing.empty()) std::cout << "; " << font.missing.size() << " characters not in the font";
      std::cout << '\n';
    } else {
      throw InputError(args->input + ": not a font (.ttf, .otf, .ttc, .otc, .cff, .pfb, .pfa, .t1, .woff), a font source "
                       "(.ufo, .glif), .svg, .obj or .step/.stp file");
    }
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
