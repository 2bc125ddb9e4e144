// cmr region FILE --point K|all ...: the curvature monotonicity region of a
// control point as label maps, depth maps and a picture.
#include <chrono>
#include <cstdlib>
#include <sstream>

#include <CLI/CLI.hpp>

#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/draw.hpp"
#include "tools/mesh.hpp"

namespace cmr::cli {
namespace {

struct RegionArgs {
  std::string file;
  std::string point = "0";
  std::vector<int> with;
  std::string mode = "cmrwi";
  std::optional<int> split;
  int depth = kDefaultDepth;
  std::string size = "512x512";
  std::string view;
  std::string backend = "vulkan";
  std::string precision = "fp64";
  std::string device;
  std::string png, labels, depth_map;
  std::string contours;  // --contours OUT.svg|OUT.obj|OUT.ply
  bool stats = false;
};

std::string pgm(const RegionResult& img, const std::vector<uint8_t>& values) {
  std::string out = "P5\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n255\n";
  out.append(reinterpret_cast<const char*>(values.data()), values.size());
  return out;
}

std::string with_point_suffix(const std::string& path, int k) {
  const auto dot = path.rfind('.');
  const std::string stem = dot == std::string::npos ? path : path.substr(0, dot);
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  return stem + ".P" + std::to_string(k) + ext;
}

/// The region request the arguments describe (point and validation come later).
RegionRequest region_options(const RegionArgs& a) {
  RegionRequest o;
  const auto [w, h] = parse_size(a.size);
  o.width = w;
  o.height = h;
  o.mode = a.mode == "cmr" ? Mode::cmr : Mode::cmrwi;
  o.split = a.split;
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
/// bad input leaves no files.
std::vector<RegionProblem> validated_problems(const RegionArgs& a, const BSpline& spline, const RegionRequest& o) {
  if (!a.png.empty()) check_output_path(a.png, "--png");
  if (!a.labels.empty()) check_output_path(a.labels, "--labels");
  if (!a.depth_map.empty()) check_output_path(a.depth_map, "--depth-map");
  if (!a.contours.empty()) check_output_path(a.contours, "--contours"), mesh::check_contour_file_name(a.contours);
  std::vector<RegionProblem> problems;
  for (int k : chosen_points(a, spline)) {
    RegionRequest ok = o;
    ok.point = k;
    problems.push_back(RegionProblem::make(spline, ok));
  }
  return problems;
}

/// The rendered images, one per point, with the JSON summary of each.
struct Rendered {
  std::vector<RegionResult> images;
  nlohmann::ordered_json per_point = nlohmann::ordered_json::array();
  double seconds = 0, setup_seconds = 0;
};

/// Label counts of one image (and with --stats its timing and exact share).
nlohmann::ordered_json point_summary(const RegionArgs& a, const RegionProblem& problem, const RegionResult& img,
                                     double sec) {
  std::vector<std::uint64_t> counts(kSplitLabelCodes, 0);
  for (std::size_t i = 0; i < img.size(); ++i) ++counts[img.code_at(i)];
  nlohmann::ordered_json c;
  const int labels = img.split ? kSplitLabelCodes : kRegionLabelCodes;
  for (int l = 0; l < labels; ++l) c[std::to_string(l)] = counts[l];
  nlohmann::ordered_json entry = {{"point", problem.request().point}, {"counts", c}};
  if (a.stats) {
    entry["seconds"] = sec;
    entry["exact_pixels"] = img.exact_pixels;
    entry["exact_share"] = static_cast<double>(img.exact_pixels) / static_cast<double>(img.size());
  }
  return entry;
}

Rendered render_all(const RegionArgs& a, const std::vector<RegionProblem>& problems) {
  Rendered r;
  const std::shared_ptr<RegionBackend> backend = make_region_backend(a.backend, a.precision, a.device);
  const auto t0 = std::chrono::steady_clock::now();
  for (const RegionProblem& problem : problems) {
    const auto t1 = std::chrono::steady_clock::now();
    r.images.push_back(backend->render(problem));
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    r.setup_seconds += r.images.back().setup_seconds;
    r.per_point.push_back(point_summary(a, problem, r.images.back(), sec));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

/// --contours: every image's refined outlines (bezierize/contour.hpp), and
/// each label's area in its summary ("areas": {"code": area}).
std::vector<RegionContours> contours_of(const RegionArgs& a, const std::vector<RegionProblem>& problems, Rendered& r) {
  std::vector<RegionContours> all;
  if (a.contours.empty()) return all;
  for (std::size_t i = 0; i < problems.size(); ++i) {
    all.push_back(region_contours(problems[i], r.images[i]));
    nlohmann::ordered_json areas = nlohmann::ordered_json::object();
    for (const LabelContours& lc : all.back().labels) areas[std::to_string(lc.label)] = lc.area;
    r.per_point[i]["areas"] = areas;
  }
  return all;
}

/// The PGMs, the PNG and the contour files, all or none (each through cmr::write_file_atomic).
void write_outputs(const RegionArgs& a, const BSpline& spline, const std::vector<RegionProblem>& problems,
                   const Rendered& r, const std::vector<RegionContours>& contours) {
  OutputFiles out;
  const bool several = problems.size() > 1;
  for (std::size_t i = 0; i < contours.size(); ++i)
    out.write(several ? with_point_suffix(a.contours, problems[i].request().point) : a.contours,
              mesh::contour_file(a.contours, contours[i]));
  for (std::size_t i = 0; i < r.images.size(); ++i) {
    const int k = problems[i].request().point;
    if (!a.labels.empty())
      out.write(several ? with_point_suffix(a.labels, k) : a.labels, pgm(r.images[i], r.images[i].codes()));
    if (!a.depth_map.empty())
      out.write(several ? with_point_suffix(a.depth_map, k) : a.depth_map, pgm(r.images[i], r.images[i].depth));
  }
  if (!a.png.empty()) {
    draw::RegionPicture pic;
    pic.spline = &spline;
    for (const RegionResult& img : r.images) pic.layers.push_back(&img);
    pic.split = problems.front().request().split.has_value();
    pic.max_depth = problems.front().request().max_depth;
    out.write(a.png, draw::region_png(pic));
  }
  out.keep();
}

/// The JSON printed on stdout.
nlohmann::ordered_json region_summary(const RegionArgs& a, const RegionRequest& o, const Rendered& r) {
  const View& v = r.images.front().view;
  nlohmann::ordered_json doc = {{"width", o.width},
                                {"height", o.height},
                                {"view", {v.x0, v.y0, v.x1, v.y1}},
                                {"mode", a.mode},
                                {"backend", a.backend},
                                {"points", r.per_point}};
  if (o.split) doc["split"] = *o.split;
  if (a.stats) {
    doc["seconds"] = r.seconds;
    doc["setup_seconds"] = r.setup_seconds;
    doc["mpixel_per_second"] = static_cast<double>(o.width) * o.height * r.images.size() / r.seconds / 1e6;
  }
  return doc;
}

void run_region(const RegionArgs& a) {
  const BSpline spline = read_spline_file(a.file);
  const RegionRequest o = region_options(a);
  const std::vector<RegionProblem> problems = validated_problems(a, spline, o);
  Rendered r = render_all(a, problems);
  const std::vector<RegionContours> contours = contours_of(a, problems, r);
  write_outputs(a, spline, problems, r, contours);
  print_json(region_summary(a, o, r));
}

}  // namespace

void add_region_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<RegionArgs>();
  auto* cmd = app.add_subcommand("region", "Where may a control point go so that curvature stays monotone?");
  cmd->add_option("FILE", a->file, "spline file (JSON)")->required();
  cmd->add_option("--point", a->point, "control point K placed at every pixel, or 'all' (one map per point)")
      ->capture_default_str();
  cmd->add_option("--with", a->with, "points moving rigidly with K (comma separated)")->delimiter(',');
  cmd->add_option("--mode", a->mode, "cmrwi: monotone; cmr: monotone without inflection")
      ->check(CLI::IsMember({"cmrwi", "cmr"}))
      ->capture_default_str();
  cmd->add_option("--split", a->split, "joint S: spans 0..S-1 against S..N-1 (extremum at the joint)");
  cmd->add_option("--depth", a->depth, "maximum subdivision depth D")->capture_default_str();
  cmd->add_option("--size", a->size, "image size WxH")->capture_default_str();
  cmd->add_option("--view", a->view, "world rectangle X0,Y0,X1,Y1 (default: control polygon with a margin)");
  cmd->add_option("--backend", a->backend, "vulkan (default; lavapipe without a GPU) or cpu")
      ->check(CLI::IsMember({"vulkan", "cpu"}))
      ->capture_default_str();
  cmd->add_option("--precision", a->precision, "shader arithmetic; labels are certified either way")
      ->check(CLI::IsMember({"fp64", "fp32"}))
      ->capture_default_str();
  cmd->add_option("--device", a->device, "Vulkan device name (substring, case-insensitive)");
  cmd->add_option("--png", a->png, "picture: regions, curve, control polygon");
  cmd->add_option("--labels", a->labels, "label map, 8-bit PGM (with --point all: OUT.P0.pgm, OUT.P1.pgm, ...)");
  cmd->add_option("--depth-map", a->depth_map, "decision level per pixel, 8-bit PGM");
  cmd->add_option("--contours", a->contours,
                  "region outlines refined on the exact boundary: .svg, or triangulated .obj/.ply (areas in the summary)");
  cmd->add_flag("--stats", a->stats, "report timings and the share of pixels that needed the exact path");
  cmd->callback([a, &exit_code] {
    run_region(*a);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
