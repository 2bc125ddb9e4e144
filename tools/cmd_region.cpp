// cmr region FILE --point K|all ...: the curvature monotonicity region of a
// control point as label maps, depth maps and a picture.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <iostream>
#include <optional>
#include <cstdlib>
#include <sstream>

#include <CLI/CLI.hpp>

#include "bezierize/analyze.hpp"
#include "region/region_reason.hpp"
#include "region/view_fit.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"
#include "draw/draw.hpp"
#include "draw/mesh.hpp"
#include "draw/region_export.hpp"
#include "draw/weight_picture.hpp"

namespace cmr::cli {
namespace {

struct RegionArgs {
  std::string file;
  std::string point;
  std::vector<int> with;
  std::string mode = "cmrwi";
  std::vector<int> split;
  std::string segments;
  std::string each_piece;  // --each-piece [S1,S2,...]
  const CLI::Option* each_piece_option = nullptr;
  int depth = kDefaultDepth;
  std::string size = "512x512";
  std::string view;
  std::string backend = "auto";
  std::string precision = "fp64";
  std::string device;
  std::string png, labels, depth_map;
  std::string contours;  // --contours OUT.svg|OUT.obj|OUT.ply
  bool stats = false;
  bool pretty = false;
  // --weight K --from A --to B (region/weight_region.hpp): the region of a weight.
  std::optional<int> weight;
  std::optional<double> from, to;
  int samples = WeightRegionRequest{}.samples;
  std::string plot, json_out;
  std::string plane;  // space curves: --plane (tools/cmd_space.hpp)
  std::string mesh;   // space curves: --mesh OUT.obj|OUT.ply, the tube and the patch (draw/space_mesh.hpp)
  double tube_radius = 0;
  /// Options given on the command line, by name (to refuse those of the
  /// other mode with one line).
  std::vector<std::pair<std::string, const CLI::Option*>> given;
};

/// The region request the arguments describe (point and validation come later).
RegionRequest region_options(const RegionArgs& a) {
  RegionRequest o;
  const auto [w, h] = parse_size(a.size);
  o.width = w;
  o.height = h;
  o.mode = a.mode == "cmr" ? Mode::cmr : Mode::cmrwi;
  if (a.split.size() == 1) o.split = a.split[0];
  else o.splits = a.split;
  if (a.each_piece_option && a.each_piece_option->count() > 0) {
    if (!a.split.empty()) throw InputError("--each-piece takes the joints itself (--each-piece S1,S2,...): drop --split");
    o.each_piece = true;
    o.splits = parse_joint_list(a.each_piece);
  }
  if (!a.segments.empty()) o.segments = parse_segment_range(a.segments);
  o.max_depth = a.depth;
  o.with = a.with;
  if (!a.view.empty()) o.view = parse_view(a.view);
  o.depth = !a.depth_map.empty();
  return o;
}

/// --point K or --point all.
std::vector<int> chosen_points(const RegionArgs& a, const BSpline& spline) {
  std::vector<int> points;
  if (a.point == "all") {
    if (!a.with.empty()) throw InputError("--with cannot be combined with --point all");
    for (int k = 0; k < spline.point_count(); ++k) points.push_back(k);
    return points;
  }
  try {
    std::size_t used = 0;
    points.push_back(std::stoi(a.point, &used));
    if (used != a.point.size()) throw std::invalid_argument(a.point);
  } catch (const std::exception&) {
    throw InputError("--point: expected an index or 'all' (got '" + a.point + "')");
  }
  return points;
}

/// Every point and output path is validated before anything is rendered, so
/// bad input leaves no files. Without --view the view is fitted to the
/// points' regions (fit_region_view, issue 40 item 6), and `fit` says how.
std::vector<RegionProblem> validated_problems(const RegionArgs& a, const BSpline& spline, RegionRequest o,
                                             std::vector<std::string>& notes, std::optional<RegionViewFit>& fit) {
  // A closed curve is never monotone over its period: without --segments (and
  // without joints) one point's region judges the spans it acts on.
  const std::vector<int> points = chosen_points(a, spline);
  if (spline.closed() && !o.segments && !o.split && o.splits.empty() && !o.each_piece && points.size() == 1) {
    if (const auto r = closed_support_range(spline, points[0], o.with)) {
      o.segments = r;
      notes.push_back("note: closed curve: P" + std::to_string(points[0]) + "'s region judges the spans it acts on, " +
                      "segments " + std::to_string(r->first) + ".." + std::to_string(r->last) +
                      " (give --segments to choose others)");
    }
  }
  if (!a.png.empty()) check_output_path(a.png, "--png");
  if (!a.labels.empty()) check_output_path(a.labels, "--labels");
  if (!a.depth_map.empty()) check_output_path(a.depth_map, "--depth-map");
  if (!a.contours.empty()) check_output_path(a.contours, "--contours"), mesh::check_contour_file_name(a.contours);
  check_total_pixels(static_cast<long long>(points.size()), o.width, o.height, "points");
  if (!o.view) {
    std::vector<RegionRequest> each;
    for (const int k : points) each.push_back(o), each.back().point = k;
    fit = fit_region_view(spline, each);
    o.view = fit->view;
  }
  return RegionProblem::make_each(spline, o, points);
}

/// The rendered images, one per point, with the JSON summary of each.
struct Rendered {
  std::vector<RegionResult> images;
  nlohmann::ordered_json per_point = nlohmann::ordered_json::array();
  double seconds = 0, setup_seconds = 0;
  std::string backend;  ///< the backend that rendered ("auto" resolved)
  std::vector<std::string> notes;  ///< printed on stderr once the outputs are written
};

/// Label counts of one image (and with --stats its timing and exact share);
/// an empty region adds a note, and so does a speck in a fitted view (`fit`:
/// without --view).
nlohmann::ordered_json point_summary(const RegionArgs& a, const RegionProblem& problem, const RegionResult& img,
                                     double sec, const std::optional<RegionViewFit>& fit,
                                     std::vector<std::string>& notes) {
  std::vector<std::uint64_t> counts(kSplitLabelCodes, 0);
  for (std::size_t i = 0; i < img.size(); ++i) ++counts[img.code_at(i)];
  // Keyed by the labels' names, in code order.
  nlohmann::ordered_json c;
  for (int l = 0; l < img.label_codes(); ++l) c[img.label_name(static_cast<std::uint8_t>(l))] = counts[l];
  // Monotone positions: increasing or decreasing (with a split: both parts monotone).
  const std::uint64_t monotone = img.each_piece ? counts[1]
                                 : img.split    ? counts[1] + counts[2] + counts[3] + counts[4]
                                                : counts[1] + counts[2];
  const std::optional<std::string> why = region_reason(problem, img);  // empty or full: say why
  const std::string k = std::to_string(problem.request().point);
  if (monotone == 0)
    notes.push_back("note: P" + k + " has no " + (a.mode == "cmr" ? "CMR" : "CMRWI") +
                    (img.split ? " with both parts monotone" : img.each_piece ? " with each piece monotone" : "") +
                    " in this view (its region is empty here" +
                    (fit && fit->empty ? std::string(", and in three times the polygon's view") : std::string()) +
                    "): " + (why ? show_fields(*why) : "see --view"));
  else if (why)
    notes.push_back("note: " + *why);
  if (fit && monotone > 0 && monotone * 100 < img.size())  // under 1% of a fitted picture: thin, or small beside others
    notes.push_back("note: P" + k + "'s region is a speck: " + std::to_string(monotone) + " of " +
                    std::to_string(img.size()) + " pixels (" +
                    (fit->probe_pixels.size() > 1 ? "small beside the other points' regions, or thin"
                                                  : "thin, or smaller than the probe's pixels") +
                    "; --view zooms)");
  nlohmann::ordered_json entry = {{"point", problem.request().point}, {"counts", c}};
  if (a.stats) {
    entry["seconds"] = sec;
    entry["exact_pixels"] = img.exact_pixels;
    entry["exact_share"] = static_cast<double>(img.exact_pixels) / static_cast<double>(img.size());
  }
  return entry;
}

/// A judged span with a pole (W = 0) makes every position fail: say where.
void note_poles(const RegionProblem& problem, std::vector<std::string>& notes) {
  const BSpline& s = problem.spline();
  const std::optional<SegmentRange>& range = problem.request().segments;
  const int first = range ? range->first : 0, last = range ? range->last : s.segment_count() - 1;
  for (int i = first; i <= last; ++i)
    if (const std::vector<double> poles = segment_poles(s, s.segments()[i]); !poles.empty()) {
      std::ostringstream t;
      t.precision(6);
      t << poles.front();
      notes.push_back("note: segment " + std::to_string(i) + " has a pole (W = 0 at t = " + t.str() +
                      "): every position fails; the weights do not move with the point");
      return;
    }
}

Rendered render_all(const RegionArgs& a, const std::vector<RegionProblem>& problems, std::vector<std::string> notes,
                    const std::optional<RegionViewFit>& fit) {
  Rendered r;
  r.notes = std::move(notes);
  if (!problems.empty()) note_poles(problems.front(), r.notes);
  const std::shared_ptr<RegionBackend> backend = make_region_backend(a.backend, a.precision, a.device, static_cast<int>(problems.size()));
  const auto t0 = std::chrono::steady_clock::now();
  for (const RegionProblem& problem : problems) {
    const auto t1 = std::chrono::steady_clock::now();
    r.images.push_back(backend->render(problem));
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    r.setup_seconds += r.images.back().setup_seconds;
    r.per_point.push_back(point_summary(a, problem, r.images.back(), sec, fit, r.notes));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.backend = backend->name();
  return r;
}

/// --contours: every image's refined outlines (region/contour.hpp), and
/// each label's area in its summary ("areas": {"label name": area}).
std::vector<RegionContours> contours_of(const RegionArgs& a, const std::vector<RegionProblem>& problems, Rendered& r) {
  std::vector<RegionContours> all;
  if (a.contours.empty()) return all;
  for (std::size_t i = 0; i < problems.size(); ++i) {
    all.push_back(region_contours(problems[i], r.images[i]));
    nlohmann::ordered_json areas = nlohmann::ordered_json::object();
    for (const LabelContours& lc : all.back().labels) areas[r.images[i].label_name(lc.label)] = lc.area;
    areas[kUndecidedBandName] = all.back().band.area;  // undecided, narrower than a pixel (contour.hpp)
    r.per_point[i]["areas"] = areas;
  }
  return all;
}

/// Each problem's request, in order.
std::vector<RegionRequest> requests_of(const std::vector<RegionProblem>& problems) {
  std::vector<RegionRequest> out;
  for (const RegionProblem& p : problems) out.push_back(p.request());
  return out;
}

/// The picture settings of a problem: curve, legend, labels of its mode.
draw::RegionPicture picture(const BSpline& spline, const RegionProblem& problem) {
  draw::RegionPicture pic;
  pic.spline = &spline;
  pic.split = problem.request().split.has_value();
  pic.each_piece = problem.request().each_piece;
  pic.alternating = !problem.request().splits.empty() && !pic.each_piece;
  pic.max_depth = problem.request().max_depth;
  pic.legend = true;
  return pic;
}

/// A depth map: OUT.png is the Fig. 7 picture (red/blue/grey, darker with the
/// level, with its legend); any other name a PGM of the levels 0..D with
/// maxval D, so that viewers stretch it to black..white.
std::string depth_map(const RegionArgs& a, const BSpline& spline, const RegionProblem& problem,
                      const RegionResult& img) {
  const std::string& path = a.depth_map;
  const bool png = path.size() >= 4 && std::equal(path.end() - 4, path.end(), ".png", [](char x, char y) {
                     return std::tolower(static_cast<unsigned char>(x)) == y;
                   });
  if (!png) return draw::pgm(img.width, img.height, img.depth, std::max(1, problem.request().max_depth));
  draw::RegionPicture pic = picture(spline, problem);
  pic.layers = {&img};
  pic.points = {problem.request().point};
  pic.depth_shading = true;
  return draw::region_png(pic);
}

/// The PGMs, the PNG and the contour files, all or none: everything is staged first, then
/// committed as one cmr::OutputSet, so a failure (a full disk on the last
/// file) leaves every pre-existing output as it was.
void write_outputs(const RegionArgs& a, const BSpline& spline, const std::vector<RegionProblem>& problems,
                   const Rendered& r, const std::vector<RegionContours>& contours) {
  OutputSet out;
  const bool several = problems.size() > 1;
  for (std::size_t i = 0; i < contours.size(); ++i)
    out.stage(several ? draw::with_point_suffix(a.contours, problems[i].request().point) : std::filesystem::path(a.contours),
              mesh::contour_file(a.contours, contours[i]));
  for (std::size_t i = 0; i < r.images.size(); ++i) {
    const int k = problems[i].request().point;
    if (!a.labels.empty())
      out.stage(several ? draw::with_point_suffix(a.labels, k) : std::filesystem::path(a.labels), draw::label_pgm(r.images[i]));
    if (!a.depth_map.empty())
      out.stage(several ? draw::with_point_suffix(a.depth_map, k) : std::filesystem::path(a.depth_map),
                depth_map(a, spline, problems[i], r.images[i]));
  }
  if (!a.png.empty()) {
    draw::RegionPicture pic = draw::layers_picture(spline, r.images, requests_of(problems));
    if (!several) pic.note = show_fields(region_reason(problems.front(), r.images.front()).value_or(""));
    out.stage(a.png, draw::region_png(pic));
  }
  out.commit();
}

/// The JSON printed on stdout.
nlohmann::ordered_json region_summary(const RegionArgs& a, const RegionRequest& o,
                                      const std::vector<RegionProblem>& problems, const Rendered& r,
                                      const std::optional<RegionViewFit>& fit) {
  const View& v = r.images.front().view;
  nlohmann::ordered_json doc = {{"width", o.width}, {"height", o.height}, {"view", {v.x0, v.y0, v.x1, v.y1}}};
  if (fit) doc["view_fitted"] = fit->fitted();  // without --view only: a given view's output is as it was
  doc["mode"] = a.mode;
  doc["backend"] = r.backend;
  doc["points"] = r.per_point;
  if (o.split) doc["split"] = *o.split;
  if (!o.splits.empty() && !o.each_piece) doc["split"] = o.splits;
  if (o.each_piece)  // the cut joints (every joint of the judged range by default)
    doc["each_piece"] =
        each_piece_cuts(judged_range(o.segments, problems.front().spline().segment_count()), o.splits);
  if (o.segments) {
    // The judged segments, and the ignored ones by index (not silently dropped).
    nlohmann::ordered_json ignored = nlohmann::ordered_json::array();
    for (int seg = 0; seg < problems.front().spline().segment_count(); ++seg)
      if (seg < o.segments->first || seg > o.segments->last) ignored.push_back(seg);
    doc["segments"] = {o.segments->first, o.segments->last};
    doc["ignored_segments"] = ignored;
  }
  if (a.stats) {
    doc["seconds"] = r.seconds;
    doc["setup_seconds"] = r.setup_seconds;
    doc["mpixel_per_second"] = static_cast<double>(o.width) * o.height * r.images.size() / r.seconds / 1e6;
  }
  return doc;
}

/// Refuses an option of the other mode (--point's with --weight and back).
void refuse_options(const RegionArgs& a, const std::vector<std::string>& names, const std::string& why) {
  for (const auto& [name, option] : a.given)
    if (option->count() > 0 && std::find(names.begin(), names.end(), name) != names.end())
      throw InputError(name + " " + why);
}

/// cmr region FILE --weight K --from A --to B: the labels of the weights in [A, B].
void run_weight_region(const RegionArgs& a) {
  // The weights' labels come from analyze() on the host: no backend runs.
  refuse_options(a,
                 {"--with", "--size", "--view", "--png", "--labels", "--depth-map", "--contours", "--stats",
                  "--backend", "--device", "--precision"},
                 "is for --point (with --weight: --plot FILE.png|svg, -o FILE.json)");
  if (!a.from || !a.to) throw InputError("--weight needs --from A and --to B (the interval of weights)");
  const BSpline spline = read_spline_file(a.file);
  WeightRegionRequest r;
  r.point = *a.weight;
  r.from = *a.from;
  r.to = *a.to;
  r.samples = a.samples;
  r.labels = region_options(a);
  if (!a.plot.empty()) check_output_path(a.plot, "--plot");
  if (!a.json_out.empty()) check_output_path(a.json_out, "-o");
  const auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
  };
  const std::string plot = lower(a.plot);
  const bool svg = plot.size() >= 4 && plot.compare(plot.size() - 4, 4, ".svg") == 0;
  if (!plot.empty() && !svg && !(plot.size() >= 4 && plot.compare(plot.size() - 4, 4, ".png") == 0))
    throw InputError("--plot: the file name must end in .png or .svg (got '" + a.plot + "')");
  const WeightRegion region = weight_region(spline, r);

  nlohmann::ordered_json intervals = nlohmann::ordered_json::array();
  for (const WeightInterval& iv : region.intervals)
    intervals.push_back({{"from", iv.from}, {"to", iv.to}, {"label", region.label_name(iv.label)}, {"pole", iv.pole}});
  nlohmann::ordered_json doc = {{"weight", r.point},
                                {"from", r.from},
                                {"to", r.to},
                                {"current", spline.weight(r.point)},
                                {"mode", a.mode},
                                {"samples", r.samples},
                                {"tolerance", r.tolerance * (r.to - r.from)},
                                {"evaluations", region.evaluations},
                                {"intervals", intervals}};
  if (r.labels.split) doc["split"] = *r.labels.split;
  if (!r.labels.splits.empty()) doc["split"] = r.labels.splits;
  if (r.labels.segments) doc["segments"] = {r.labels.segments->first, r.labels.segments->last};
  OutputSet out;
  if (!a.plot.empty()) out.stage(a.plot, weight_region_picture(spline, r, region, svg));
  if (!a.json_out.empty()) out.stage(a.json_out, json_text(doc, a.pretty));
  out.commit();
  if (a.json_out.empty()) print_json(doc, a.pretty);
}

void run_region(const RegionArgs& a) {
  const BSpline spline = read_spline_file(a.file);
  std::vector<std::string> notes;
  std::optional<RegionViewFit> fit;
  const std::vector<RegionProblem> problems = validated_problems(a, spline, region_options(a), notes, fit);
  const RegionRequest& o = problems.front().request();
  Rendered r = render_all(a, problems, std::move(notes), fit);
  const std::vector<RegionContours> contours = contours_of(a, problems, r);
  write_outputs(a, spline, problems, r, contours);
  for (const std::string& note : r.notes) std::cerr << note << '\n';  // after the outputs: a failure prints one line
  print_json(region_summary(a, o, problems, r, fit), a.pretty);
}

}  // namespace

void add_region_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<RegionArgs>();
  auto* cmd = app.add_subcommand("region", "Where may a control point go so that curvature stays monotone?");
  cmd->add_option("FILE", a->file, "spline file (JSON)")->required();
  auto* point = cmd->add_option("--point", a->point,
                                "control point K placed at every pixel, or 'all' (one map per point)");
  auto* weight = cmd->add_option("--weight", a->weight,
                                 "the region of weight K: which weights in --from A .. --to B give which label");
  point->excludes(weight);
  weight->excludes(point);
  cmd->add_option("--from", a->from, "--weight: the smallest weight A");
  cmd->add_option("--to", a->to, "--weight: the largest weight B (A < B)");
  cmd->add_option("--samples", a->samples,
                  "--weight: equally spaced weights labelled before the changes are bisected")
      ->capture_default_str();
  cmd->add_option("--plot", a->plot, "--weight: the picture, FILE.png or FILE.svg");
  cmd->add_option("-o,--output", a->json_out, "--weight: the JSON to FILE instead of stdout");
  cmd->add_option("--with", a->with, "points moving rigidly with K (comma separated)")->delimiter(',');
  cmd->add_option("--mode", a->mode, "cmrwi: monotone; cmr: monotone without inflection")
      ->check(CLI::IsMember({"cmrwi", "cmr"}))
      ->capture_default_str();
  cmd->add_option("--split", a->split,
                  "joint S: spans 0..S-1 against S..N-1 (extremum at the joint); joints S1,S2,...: the groups "
                  "between them alternate direction")
      ->delimiter(',');
  a->each_piece_option =
      cmd->add_option("--each-piece", a->each_piece,
                      "each piece monotone on its own, in either direction (no alternation); with joints "
                      "S1,S2,... the groups between them (docs/semantics.md)")
          ->expected(0, 1);
  cmd->add_option("--segments", a->segments, "judge only spans A..B (inclusive); the others are ignored");
  in_range(cmd->add_option("--depth", a->depth, "maximum subdivision depth D"), 0, kMaxDepth)->capture_default_str();
  cmd->add_option("--size", a->size, "image size WxH")->capture_default_str();
  cmd->add_option("--view", a->view, "world rectangle X0,Y0,X1,Y1 (default: the points' regions and the moved points, with a margin; "
                                      "the control polygon's view where no region shows)");
  add_backend_options(*cmd, a->backend, a->device, &a->precision);
  cmd->add_option("--png", a->png,
                  "picture: regions, curve, control polygon, the moved point ringed, a legend (with --point all one "
                  "picture, each point's region in its own colour)");
  cmd->add_option("--labels", a->labels, "label map, 8-bit PGM (with --point all: OUT.P0.pgm, OUT.P1.pgm, ...)");
  cmd->add_option("--depth-map", a->depth_map,
                  "decision level per pixel: 8-bit PGM (maxval D), or a shaded picture when the name ends in .png");
  cmd->add_option("--contours", a->contours,
                  "region outlines refined on the exact boundary: .svg, or triangulated .obj/.ply (areas in the summary)");
  cmd->add_flag("--stats", a->stats, "report timings and the share of pixels that needed the exact path");
  cmd->add_option("--plane", a->plane, "space curves: the plane K moves in, xy|yz|zx through K or OX,OY,OZ,UX,UY,UZ,VX,VY,VZ "
                                       "(default: through K, spanned by its neighbours; docs/space.md)");
  cmd->add_option("--mesh", a->mesh, "space curves: the curve as a tube and the region as a patch in its plane, .obj or .ply");
  cmd->add_option("--tube-radius", a->tube_radius, "space curves: the --mesh tube's radius (default: 0.4% of the "
                                                   "control points' bounding box diagonal)");
  add_pretty_flag(*cmd, a->pretty);
  for (CLI::Option* o : cmd->get_options()) a->given.emplace_back(o->get_name(), o);
  cmd->callback([a, &exit_code] {
    if (spline_file_dimension(a->file) == 3) {  // [x, y, z] points: a space curve (docs/space.md)
      refuse_options(*a, {"--weight", "--with", "--split", "--segments", "--mode", "--contours", "--device", "--precision"},
                     "is for planar splines (" + a->file + " is a space curve)");
      run_space_region({a->file, a->point, a->plane, a->size, a->view, a->backend, a->depth, a->png, a->labels,
                        a->depth_map, a->stats, a->pretty, a->mesh, a->tube_radius});
      exit_code = kOk;
      return;
    }
    if (!a->plane.empty()) {
      (void)read_spline_file(a->file);  // an unreadable file says so first
      refuse_options(*a, {"--plane"}, "is for space curves (" + a->file + " is planar)");
    }
    refuse_options(*a, {"--mesh", "--tube-radius"}, "is for space curves (" + a->file + " is planar; --contours FILE.obj|ply "
                                                     "meshes a planar region)");
    if (a->weight) {
      run_weight_region(*a);
    } else {
      if (a->point.empty())
        throw InputError("--point is required (see cmr region --help), or --weight K for the region of a weight");
      refuse_options(*a, {"--from", "--to", "--samples", "--plot", "--output"}, "is for --weight K");
      run_region(*a);
    }
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
