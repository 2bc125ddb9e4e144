// cmr sweep FILE (--knot I --from U0 --to U1 | --to-knots K0,K1,...) --steps N
// [region options] [--out-dir DIR]: the region of one control point while the
// knot vector moves.
//
// Step s = 0..N takes t = s / N and the knot vector
//   --knot I:     knot I set to U0 + (U1 - U0) t (the others as in FILE);
//   --to-knots K: (1 - t) * FILE's knots + t * K, every knot at once (a convex
//                 combination of two valid knot vectors is non-decreasing, so
//                 only multiplicities can make a step invalid);
// with the same control points. Every step's spline and region problem is
// built and validated before anything is rendered (bad input writes nothing).
// All steps share one view (without --view: the union of the steps' regions
// and the moved point, with a margin, fitted_view; the control points do
// not move). Each frame carries a knot ruler (the knot vector, the moving
// knot in red, its value) and its legend ends with the knot value. Per step:
// the region (any backend), its refined contours (region/contour.hpp),
// the curve's own verdict (analyze) and why the region is empty or full
// (region_reason), printed as one JSON line. With --out-dir (created if
// missing; files an earlier sweep wrote there and this one does not are
// removed), all or none of: steps.jsonl, contours/step_NNN.svg,
// frames/step_NNN.png, kappa/step_NNN.png (the step's curvature with each
// segment's certified class), index.html (a slider over the frames and
// kappa plots, the current step marked on the area plot), area.png (area
// per label against the knot value) and tube.obj / tube.ply (the monotone
// voxels of the stacked label maps, x, y and the knot value, as a closed
// mesh: draw/mesh.hpp).
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>
#include <sstream>

#include <CLI/CLI.hpp>

#include "bezierize/analyze.hpp"
#include "region/contour.hpp"
#include "bezierize/knot_ops.hpp"
#include "region/region_memo.hpp"
#include "region/region_reason.hpp"
#include "region/view_fit.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "draw/draw.hpp"
#include "draw/mesh.hpp"

namespace cmr::cli {
namespace {

inline constexpr int kMaxSweepSteps = 10000;
/// What a sweep holds per pixel of all its steps until it writes them (each
/// step's region maps, contours, frame and the tube's stack): 4 steps of
/// 1024 x 1024 peaked at 425 MB resident, 4 of 512 x 512 at 129 MB: about 100
/// bytes a pixel (16 steps of 4096 x 4096, within the pixel count limit,
/// took 20 GB).
inline constexpr long long kSweepBytesPerPixel = 100;
/// And per step, whatever its size: the kappa plot's PNG (about 20 kB at 392 x 494 pixels).
inline constexpr long long kSweepBytesPerStep = 64 * 1024;

/// The memory a sweep may plan to use: 3/4 of the smaller of the machine's
/// memory and the address space limit (ulimit -v).
long long sweep_memory_limit() {
  long long limit = static_cast<long long>(::sysconf(_SC_PHYS_PAGES)) * ::sysconf(_SC_PAGE_SIZE);
  rlimit r{};
  if (::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    limit = std::min(limit, static_cast<long long>(r.rlim_cur));
  return limit / 4 * 3;
}

/// Refuses (InputError) a sweep whose pixels would not fit in memory
/// (sweep_memory_limit), before anything is rendered.
void check_sweep_memory(long long images, int width, int height) {
  const long long bytes = images * (width * height * kSweepBytesPerPixel + kSweepBytesPerStep),
                  limit = sweep_memory_limit();
  if (bytes <= limit) return;
  const auto mb = [](long long b) { return std::to_string(b / (1024 * 1024)) + " MB"; };
  throw InputError(std::to_string(images) + " steps of " + std::to_string(width) + "x" + std::to_string(height) +
                   " pixels need about " + mb(bytes) + " (" + std::to_string(kSweepBytesPerPixel) +
                   " bytes a pixel and " + std::to_string(kSweepBytesPerStep / 1024) +
                   " kB a step): more than the limit of " + mb(limit) +
                   " (3/4 of this machine's memory or of ulimit -v; fewer steps or a smaller --size)");
}

struct SweepArgs {
  std::string file;
  std::optional<int> knot;
  std::optional<double> from, to;
  std::vector<double> to_knots;
  int steps = 0;
  int point = 0;
  std::vector<int> with;
  std::string mode = "cmrwi";
  std::optional<int> split;
  int depth = kDefaultDepth;
  std::string size = "128x128";
  std::string view;
  std::string backend = "auto";
  std::string precision = "fp64";
  std::string device;
  std::string out_dir;
};

/// One step, prepared: its knot value (the plot's and the tube's axis), spline and problem.
struct Step {
  double value = 0;
  BSpline spline;
  RegionProblem problem;
};

std::string step_name(int s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "step_%03d", s);
  return buf;
}

/// The spline of step s (see the header comment); InputError names the step.
BSpline step_spline(const SweepArgs& a, const BSpline& base, int s, double& value) {
  const double t = static_cast<double>(s) / a.steps;
  try {
    if (a.knot) {
      value = *a.from + (*a.to - *a.from) * t;
      if (s == a.steps) value = *a.to;
      return set_knot(base, *a.knot, value);
    }
    value = t;
    std::vector<double> knots = base.knots();
    for (std::size_t i = 0; i < knots.size(); ++i) knots[i] = s == a.steps ? a.to_knots[i] : (1 - t) * knots[i] + t * a.to_knots[i];
    return BSpline::make(base.degree(), knots, base.points());
  } catch (const InputError& e) {
    std::ostringstream m;
    m.precision(17);
    m << "step " << s << " (" << (a.knot ? "knot value " : "t = ") << value << "): " << shown_message(e);
    throw InputError(m.str());
  }
}

/// Without --view (issue 40 item 6): the union of the regions over the run
/// and the moved point (with the --with points), with a margin. Each step
/// is probed on the CPU at 48 x 48 over three times the polygon's view (its
/// centre kept); the box of every step's region pixels and the moved points,
/// widened by 15% of its larger side each way and then to square pixels, is
/// the view (region/view_fit.hpp, as report::fit_space_view for one
/// space region). No region at any step: the polygon's view.
View fitted_view(const SweepArgs& a, const BSpline& base, const RegionRequest& rq, RegionMemo& memo) {
  const View v0 = *rq.view;
  constexpr int kProbe = 48;
  RegionRequest probe = rq;
  probe.width = probe.height = kProbe;
  probe.view = ViewFit::probe_view(v0);
  ViewFit box;
  CpuRegionBackend cpu;
  for (int s = 0; s <= a.steps; ++s) {
    double value = 0;
    box.add_region(cpu.render(memo.make(step_spline(a, base, s, value), probe)), *probe.view);
  }
  if (box.empty()) return v0;
  box.add_moved_points(base, rq);  // the control points do not move with the knots
  return box.view(rq.width, rq.height);
}

std::vector<Step> prepare(const SweepArgs& a, const BSpline& base, RegionMemo& memo) {
  if (a.steps < 1 || a.steps > kMaxSweepSteps)
    throw InputError("--steps " + std::to_string(a.steps) + " is outside 1.." + std::to_string(kMaxSweepSteps));
  if (a.knot.has_value() == !a.to_knots.empty())
    throw InputError("give either --knot I --from U0 --to U1 or --to-knots K0,K1,...");
  if (a.knot) {
    if (!a.from || !a.to) throw InputError("--knot needs --from U0 and --to U1");
    if (*a.knot < 0 || *a.knot >= static_cast<int>(base.knots().size()))
      throw InputError("--knot " + std::to_string(*a.knot) + " is outside 0.." + std::to_string(base.knots().size() - 1));
  } else if (a.to_knots.size() != base.knots().size()) {
    throw InputError("--to-knots has " + std::to_string(a.to_knots.size()) + " knots; the spline has " +
                     std::to_string(base.knots().size()));
  }
  RegionRequest rq;
  const auto [w, h] = parse_size(a.size);
  check_total_pixels(a.steps + 1LL, w, h, "steps");
  check_sweep_memory(a.steps + 1LL, w, h);
  rq.width = w;
  rq.height = h;
  rq.point = a.point;
  rq.with = a.with;
  rq.mode = a.mode == "cmr" ? Mode::cmr : Mode::cmrwi;
  rq.split = a.split;
  rq.max_depth = a.depth;
  rq.depth = false;
  rq.view = a.view.empty() ? default_view(base, w, h) : parse_view(a.view);
  if (a.view.empty()) rq.view = fitted_view(a, base, rq, memo);
  std::vector<Step> steps;
  // A step moves one knot: only the spans whose window holds it are prepared
  // again (region/region_memo.hpp).
  for (int s = 0; s <= a.steps; ++s) {
    double value = 0;
    BSpline spline = step_spline(a, base, s, value);
    RegionProblem problem = memo.make(spline, rq);
    steps.push_back({value, std::move(spline), std::move(problem)});
  }
  return steps;
}

/// "In the region": a monotone label (increasing / decreasing; with a split
/// the four directions), not "not monotone" and not "undecided".
bool monotone(std::uint8_t label, bool split) {
  return split ? label >= 1 && label <= 4 : label == 1 || label == 2;
}

/// The progress bar, on a terminal only.
class Progress {
 public:
  explicit Progress(int total) : total_(total), on_(::isatty(STDERR_FILENO) == 1) {}
  void show(int done) const {
    if (!on_) return;
    const int width = 30, filled = width * done / total_;
    std::cerr << "\rsweep [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done << "/"
              << total_ << std::flush;
    if (done == total_) std::cerr << "\n";
  }

 private:
  int total_;
  bool on_;
};

/// The slider page over frames/step_NNN.png and kappa/step_NNN.png; the
/// current step is a red line over area.png (`area`: where the plot put its
/// data, draw::PlotArea, in percent of the picture so that a scaled picture
/// keeps it in place).
std::string sweep_html(const SweepArgs& a, const std::vector<nlohmann::ordered_json>& records,
                       const draw::PlotArea& area) {
  nlohmann::json data = nlohmann::json::array();
  for (const auto& r : records) data.push_back(nlohmann::json::parse(r.dump()));
  const nlohmann::json plot = {{"width", area.width}, {"height", area.height}, {"left", area.left},
                               {"right", area.right}, {"top", area.top},       {"bottom", area.bottom},
                               {"x0", area.x0},       {"x1", area.x1},         {"y0", area.y0},
                               {"y1", area.y1}};
  const std::string axis = a.knot ? "knot " + std::to_string(*a.knot) : std::string("t (to the target knots)");
  // JSON inside <script>: "</" must not end the element.
  std::string json = data.dump();
  for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 2)) json.replace(at, 2, "<\\/");
  return "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>cmr sweep: " + html_escape(a.file) +
         "</title>\n<style>body{font-family:sans-serif;margin:20px}img{image-rendering:pixelated;border:1px solid "
         "#888;max-width:90vw}#info{font-family:monospace;white-space:pre}#area{position:relative;display:inline-block}"
         "#area img{border:0;display:block}#mark{position:absolute;width:2px;margin-left:-1px;background:#d00}"
         "</style></head><body>\n"
         "<h1>Region of P" + std::to_string(a.point) + " while " + html_escape(axis) + " moves</h1>\n"
         "<p><input type=\"range\" id=\"s\" min=\"0\" max=\"" + std::to_string(records.size() - 1) +
         "\" value=\"0\" style=\"width:600px\"> <button id=\"play\">play</button></p>\n"
         "<div id=\"info\"></div>\n<p><img id=\"frame\" src=\"frames/step_000.png\" alt=\"region\"> "
         "<img id=\"kappa\" src=\"kappa/step_000.png\" alt=\"curvature of the step's curve\"></p>\n"
         "<p><span id=\"area\"><img src=\"area.png\" alt=\"area against the knot value\">"
         "<span id=\"mark\"></span></span></p>\n"
         "<p>Files: <a href=\"steps.jsonl\">steps.jsonl</a>, <a href=\"tube.obj\">tube.obj</a>, "
         "<a href=\"tube.ply\">tube.ply</a>, contours/step_NNN.svg.</p>\n<script>\nconst steps = " + json +
         ";\nconst plot = " + plot.dump() +
         ";\nconst s = document.getElementById('s'), img = document.getElementById('frame'), kappa = "
         "document.getElementById('kappa'), mark = document.getElementById('mark'), info = "
         "document.getElementById('info');\n"
         "mark.style.top = (100 * plot.top / plot.height) + '%'; mark.style.height = (100 * (plot.bottom - plot.top) / "
         "plot.height) + '%';\n"
         "function markAt(v){const x = plot.left + (v - plot.x0) / (plot.x1 - plot.x0) * (plot.right - plot.left); "
         "return 100 * x / plot.width;}\n"
         "function show(){const r = steps[s.value]; const n = String(s.value)."
         "padStart(3,'0');\n img.src = 'frames/step_' + n + '.png'; kappa.src = 'kappa/step_' + n + '.png';\n "
         "mark.style.left = markAt(r.value) + '%';\n info.textContent = 'step ' + r.step + '   "
         "value ' + r.value + '   knots ' + JSON.stringify(r.knots) + '\\nmonotone area ' + r.monotone_area + '   "
         "areas ' + JSON.stringify(r.areas) + '\\ncurve: cmrwi ' + r.verdict.cmrwi + ', cmr ' + r.verdict.cmr + "
         "(r.reason ? '\\nwhy: ' + r.reason : '');}\n"
         "s.oninput = show; let timer = null;\ndocument.getElementById('play').onclick = () => { if (timer) "
         "{clearInterval(timer); timer = null; return;}\n timer = setInterval(() => { s.value = (Number(s.value) + 1) "
         "% steps.length; show(); }, 150); };\nshow();\n</script>\n</body></html>\n";
}

/// Area per label against the knot value, and the monotone total.
std::string area_plot(const SweepArgs& a, const std::vector<Step>& steps,
                      const std::vector<RegionContours>& contours, draw::PlotArea& where) {
  draw::LinePlot plot;
  plot.title = "Region of P" + std::to_string(a.point) + ": area against the knot value";
  plot.x_label = a.knot ? "knot " + std::to_string(*a.knot) : std::string("t (to the target knots)");
  plot.y_label = "area";
  const bool split = a.split.has_value();
  const int labels = split ? kSplitLabelCodes : kRegionLabelCodes;
  draw::Series total{"monotone (all)", {0, 0, 0}, {}};
  for (int L = 1; L < labels; ++L) {
    if (!monotone(static_cast<std::uint8_t>(L), split)) continue;
    draw::Series s;
    s.name = split ? to_string(static_cast<Split>(L)) : to_string(static_cast<Direction>(L));
    // The legend's colour, made a little darker so thin lines show.
    const draw::Rgb c = draw::label_colour(static_cast<std::uint8_t>(L), split);
    s.colour = {c.r * 0.8, c.g * 0.8, c.b * 0.8};
    for (std::size_t k = 0; k < steps.size(); ++k) {
      double area = 0;
      for (const LabelContours& lc : contours[k].labels)
        if (lc.label == L) area = lc.area;
      s.points.emplace_back(steps[k].value, area);
    }
    plot.series.push_back(std::move(s));
  }
  for (std::size_t k = 0; k < steps.size(); ++k) {
    double area = 0;
    for (const LabelContours& lc : contours[k].labels)
      if (monotone(lc.label, split)) area += lc.area;
    total.points.emplace_back(steps[k].value, area);
  }
  plot.series.insert(plot.series.begin(), std::move(total));
  return draw::line_plot_png(plot, &where);
}

/// The curvature of step k's curve (the moved point where it is) with each
/// segment's certified class under it (draw::CurvaturePlot), titled with the
/// knot value; the caption says why the region is empty or full there
/// (region_reason, the record's "reason"), or how large it is.
std::string kappa_plot(const SweepArgs& a, const Step& step, const SplineAnalysis& analysis,
                       const nlohmann::ordered_json& record, std::size_t k, std::size_t steps) {
  std::ostringstream title;
  title.precision(6);
  title << "Step " << k << " of " << steps - 1 << ": " << (a.knot ? "knot " + std::to_string(*a.knot) + " = " : "t = ")
        << step.value;
  std::ostringstream caption;
  caption.precision(4);
  caption << "Curvature of the step's curve (red: increasing, blue: decreasing; the band: each segment's certified "
             "class). P"
          << a.point << "'s region: ";
  if (record.contains("reason")) caption << record["reason"].get<std::string>();
  else caption << "monotone area " << record["monotone_area"].get<double>() << ".";
  draw::Figure f;
  f.title = title.str();
  f.rows = {{draw::Panel{draw::CurvaturePlot{&step.spline, &analysis}, ""}}};
  f.caption = caption.str();
  f.panel_size = 360;
  return draw::figure_png(f);
}

void run_sweep(const SweepArgs& a) {
  const BSpline base = read_spline_file(a.file);
  std::filesystem::path dir;
  if (!a.out_dir.empty()) {  // created at the end if missing, as report --out and import --out
    dir = a.out_dir;
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
      throw InputError("--out-dir " + a.out_dir + ": not a folder");
  }
  RegionMemo memo;
  const std::vector<Step> steps = prepare(a, base, memo);
  const bool split = a.split.has_value();
  const std::shared_ptr<RegionBackend> backend = make_region_backend(a.backend, a.precision, a.device, static_cast<int>(steps.size()));
  const Progress progress(static_cast<int>(steps.size()));
  progress.show(0);

  std::vector<RegionResult> images;
  std::vector<RegionContours> contours;
  std::vector<SplineAnalysis> verdicts;  // the kappa plots' class bands
  std::vector<nlohmann::ordered_json> records;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const Step& st = steps[k];
    images.push_back(backend->render(st.problem));
    contours.push_back(region_contours(st.problem, images.back()));
    AnalyzeOptions ao;
    ao.classify.max_depth = a.depth;
    ao.split = a.split;
    ao.split_mode = a.mode == "cmr" ? Mode::cmr : Mode::cmrwi;
    verdicts.push_back(memo.analyze(st.spline, ao));
    const SplineAnalysis& verdict = verdicts.back();
    nlohmann::ordered_json curve = {{"cmrwi", to_string(verdict.cmrwi)}, {"cmr", to_string(verdict.cmr)}};
    if (verdict.split) curve["split"] = to_string(*verdict.split);
    nlohmann::ordered_json areas = nlohmann::ordered_json::object();
    double monotone_area = 0;
    for (const LabelContours& lc : contours.back().labels) {
      areas[images.back().label_name(lc.label)] = lc.area;
      if (monotone(lc.label, split)) monotone_area += lc.area;
    }
    std::vector<std::uint64_t> counts(split ? kSplitLabelCodes : kRegionLabelCodes, 0);
    for (std::size_t i = 0; i < images.back().size(); ++i) ++counts[images.back().code_at(i)];
    nlohmann::ordered_json c;
    for (std::size_t l = 0; l < counts.size(); ++l) c[images.back().label_name(static_cast<std::uint8_t>(l))] = counts[l];
    nlohmann::ordered_json r = {{"step", k},
                                {"value", st.value},
                                {"knots", st.spline.knots()},
                                {"areas", areas},
                                {"monotone_area", monotone_area},
                                {"counts", c},
                                {"verdict", curve},
                                {"exact_pixels", images.back().exact_pixels}};
    // Why the region is empty or full here (the segments responsible), when it is.
    if (const std::optional<std::string> why = region_reason(st.problem, images.back())) r["reason"] = *why;
    std::cout << r.dump() << "\n" << std::flush;
    records.push_back(std::move(r));
    progress.show(static_cast<int>(k + 1));
  }
  if (dir.empty()) return;

  // The tube: slices in increasing knot order.
  const RegionRequest& rq = steps.front().problem.request();
  mesh::VoxelStack stack;
  stack.width = rq.width;
  stack.height = rq.height;
  stack.view = *rq.view;
  std::vector<std::size_t> order(steps.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  if (steps.size() > 1 && steps.back().value < steps.front().value) std::reverse(order.begin(), order.end());
  for (std::size_t k : order) {
    stack.knots.push_back(steps[k].value);
    for (std::size_t i = 0; i < images[k].size(); ++i) stack.in.push_back(monotone(images[k].code_at(i), split));
  }
  const mesh::Mesh tube = mesh::tube_mesh(stack);

  // All or none (cmr::OutputSet): the sub-folders this run creates are
  // removed again when the set is not committed.
  // The folder holds this run's set only: the files an earlier sweep wrote
  // there and this one does not (the frames of a longer sweep) are removed.
  OutputSet out;
  out.create_folder(dir);
  out.own_folder(dir);
  for (const char* sub : {"contours", "frames", "kappa"}) out.create_folder(dir / sub), out.own_folder(dir / sub);
  std::string lines;
  for (const auto& r : records) lines += r.dump() + "\n";
  out.stage(dir / "steps.jsonl", lines);
  // One knot ruler for every frame: the knots' range over all steps, so that the mark moves.
  draw::KnotRuler ruler;
  ruler.from = steps.front().spline.knots().front(), ruler.to = steps.front().spline.knots().back();
  for (const Step& st : steps)
    ruler.from = std::min(ruler.from, st.spline.knots().front()), ruler.to = std::max(ruler.to, st.spline.knots().back());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    out.stage(dir / "contours" / (step_name(static_cast<int>(k)) + ".svg"), mesh::contours_svg(contours[k]));
    draw::RegionPicture pic;
    pic.spline = &steps[k].spline;
    pic.layers = {&images[k]};
    pic.split = split;
    pic.points = {a.point};
    // The legend (frames of 240 x 160 pixels or more) ends with the step's knot value.
    std::ostringstream note;
    note.precision(6);
    note << (a.knot ? "knot " + std::to_string(*a.knot) + " = " : std::string("t = ")) << steps[k].value << " (step "
         << k << " of " << steps.size() - 1;
    if (a.knot) note << ", from " << *a.from << " to " << *a.to;
    note << ")";
    pic.legend = true;
    pic.note = note.str();
    // The ruler: the step's knots, the moving one marked (with --to-knots every knot moves: none is).
    ruler.knots = steps[k].spline.knots();
    ruler.marked = a.knot ? *a.knot : -1;
    std::ostringstream value;
    value.precision(4);
    value << (a.knot ? "u" + std::to_string(*a.knot) + " = " : std::string("t = ")) << steps[k].value;
    ruler.label = value.str();
    pic.ruler = ruler;
    out.stage(dir / "frames" / (step_name(static_cast<int>(k)) + ".png"), draw::region_png(pic));
    out.stage(dir / "kappa" / (step_name(static_cast<int>(k)) + ".png"),
              kappa_plot(a, steps[k], verdicts[k], records[k], k, steps.size()));
  }
  draw::PlotArea area;
  out.stage(dir / "area.png", area_plot(a, steps, contours, area));
  out.stage(dir / "tube.obj", mesh::obj_text(tube));
  out.stage(dir / "tube.ply", mesh::ply_text(tube));
  out.stage(dir / "index.html", sweep_html(a, records, area));
  out.commit();
  nlohmann::ordered_json summary = {{"out_dir", a.out_dir},
                                    {"steps", steps.size()},
                                    {"view", {stack.view.x0, stack.view.y0, stack.view.x1, stack.view.y1}},
                                    {"tube", {{"vertices", tube.n_vertices()},
                                              {"faces", tube.n_faces()},
                                              {"area", mesh::mesh_area(tube)},
                                              {"volume", mesh::mesh_volume(tube)},
                                              {"closed", mesh::is_closed(tube)}}}};
  std::cout << summary.dump() << "\n";
}

}  // namespace

void add_sweep_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<SweepArgs>();
  auto* cmd = app.add_subcommand("sweep", "The region of a control point while a knot (or the knot vector) moves");
  cmd->add_option("FILE", a->file, "spline file (JSON)")->required();
  cmd->add_option("--knot", a->knot, "index I of the moving knot (polar form)");
  cmd->add_option("--from", a->from, "knot value at the first step");
  cmd->add_option("--to", a->to, "knot value at the last step");
  cmd->add_option("--to-knots", a->to_knots, "instead of --knot: move every knot linearly to these (comma separated)")
      ->delimiter(',');
  cmd->add_option("--steps", a->steps, "N: steps 0..N (N+1 regions)")->required();
  cmd->add_option("--point", a->point, "control point K whose region is swept")->capture_default_str();
  cmd->add_option("--with", a->with, "points moving rigidly with K (comma separated)")->delimiter(',');
  cmd->add_option("--mode", a->mode, "cmrwi: monotone; cmr: monotone without inflection")
      ->check(CLI::IsMember({"cmrwi", "cmr"}))
      ->capture_default_str();
  cmd->add_option("--split", a->split, "joint S: spans 0..S-1 against S..N-1");
  in_range(cmd->add_option("--depth", a->depth, "maximum subdivision depth D"), 0, kMaxDepth)->capture_default_str();
  cmd->add_option("--size", a->size, "image size WxH per step")->capture_default_str();
  cmd->add_option("--view", a->view,
                  "world rectangle X0,Y0,X1,Y1 (default: the regions of all steps and the moved point, with a margin)");
  add_backend_options(*cmd, a->backend, a->device, &a->precision);
  cmd->add_option("--out-dir", a->out_dir,
                  "folder for steps.jsonl, contours/, frames/, index.html, area.png, tube.obj, tube.ply");
  cmd->callback([a, &exit_code] {
    run_sweep(*a);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
