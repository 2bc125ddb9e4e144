// Space curves on the command line (tools/cmd_space.hpp, docs/space.md).
#include "tools/cmd_space.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <cmath>
#include <iostream>

#include "region/space_region.hpp"
#include "draw/draw.hpp"
#include "draw/space_mesh.hpp"
#include "io/output.hpp"
#include "report/baseline.hpp"
#include "report/junit.hpp"
#include "report/markdown.hpp"
#include "report/sarif.hpp"
#include "report/space_report.hpp"
#include "spline/errors.hpp"
#include "step/step.hpp"
#include "tools/cli_common.hpp"

namespace cmr::cli {

namespace {

nlohmann::ordered_json vec3(const Vec3& p) { return {p.x, p.y, p.z}; }

}  // namespace

void run_space_analyze(const std::string& file, int depth, bool torsion, const ContinuityTolerances& continuity,
                       bool pretty, double torsion_tolerance) {
  const SpaceSpline spline = read_space_spline_file(file);
  SpaceAnalyzeOptions o;
  o.max_depth = depth;
  o.torsion = torsion;
  o.torsion_tolerance = torsion_tolerance;
  o.continuity = continuity;
  const SpaceAnalysis a = analyze_space(spline, o);
  // One segment and one joint at a time, as the planar analyze (docs/outputs.md, "Limits on work").
  JsonObjectStream out(std::cout, pretty);
  out.begin_array("segments");
  for (std::size_t i = 0; i < a.segments.size(); ++i) out.element(report::space_segment_json(spline, a, i));
  out.end_array();
  out.begin_array("joints");
  for (const SpaceJoint& j : a.joints) out.element(report::space_joint_json(a, j));
  if (a.seam) out.element(report::space_joint_json(a, *a.seam));
  out.end_array();
  out.member("spline", report::space_verdict_json(a));
  out.finish();
}

namespace {

std::string pgm(const RegionResult& img, const std::vector<std::uint8_t>& values, int maxval) {
  std::string out = "P5\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n" +
                    std::to_string(maxval) + "\n";
  out.append(reinterpret_cast<const char*>(values.data()), values.size());
  return out;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

void run_space_region(const SpaceRegionArgs& a) {
  if (a.point.empty()) throw InputError("--point is required (see cmr region --help)");
  const SpaceSpline spline = read_space_spline_file(a.file);
  SpaceRegionRequest r;
  try {
    std::size_t used = 0;
    r.point = std::stoi(a.point, &used);
    if (used != a.point.size()) throw std::invalid_argument(a.point);
  } catch (const std::exception&) {
    throw InputError("--point: expected an index (got '" + a.point + "'; 'all' is for planar splines)");
  }
  if (r.point < 0 || r.point >= spline.unique_point_count())
    throw InputError("--point " + a.point + " is outside 0.." + std::to_string(spline.unique_point_count() - 1));
  if (!a.plane.empty()) r.plane = parse_space_plane(a.plane, spline.points()[static_cast<std::size_t>(r.point)]);
  const auto [w, h] = parse_size(a.size);
  r.width = w;
  r.height = h;
  r.max_depth = a.depth;
  if (!a.png.empty()) check_output_path(a.png, "--png");
  if (!a.labels.empty()) check_output_path(a.labels, "--labels");
  if (!a.depth_map.empty()) check_output_path(a.depth_map, "--depth-map");
  if (!a.mesh.empty()) check_output_path(a.mesh, "--mesh"), mesh::check_mesh_file_name(a.mesh);
  mesh::TubeOptions tube;
  tube.radius = a.tube_radius == 0 ? mesh::default_tube_radius(spline) : a.tube_radius;
  if (!(tube.radius > 0) || !std::isfinite(tube.radius))
    throw InputError("--tube-radius: must be a positive number (got " + std::to_string(a.tube_radius) + ")");
  // Without --view: the region and the moved point with a margin
  // (report::fit_space_view; the report's thumbnails take the same view).
  std::optional<report::SpaceViewFit> fit;
  if (!a.view.empty()) {
    r.view = parse_view(a.view);
  } else {
    fit = report::fit_space_view(spline, r);
    r.view = fit->view;
  }
  const SpaceRegionProblem problem = SpaceRegionProblem::make(spline, r);
  // --backend vulkan: the device judges each pixel's parts and the CPU the
  // pixels it cannot certify (vk/space_region_vk.hpp); auto and cpu: the CPU.
  const std::shared_ptr<SpaceRegionBackend> backend = make_space_region_backend(a.backend);
  RegionResult img;
  try {
    img = backend->render(problem);
  } catch (const InputError&) {
    throw;
  } catch (const EnvironmentError& e) {  // the device's failure, named as the option chose it
    std::string message = "--backend ";
    message.append(backend->name()).append(": ").append(shown_message(e));
    throw EnvironmentError(message);
  }
  const SpacePlane& plane = *problem.request().plane;
  OutputSet out;
  if (!a.labels.empty()) out.stage(a.labels, pgm(img, img.codes(), 255));
  // The picture of the report's thumbnails (report/space_report.hpp).
  if (!a.png.empty()) out.stage(a.png, report::space_region_png(spline, plane, img, r.point, r.max_depth));
  if (ends_with(a.depth_map, ".png"))
    out.stage(a.depth_map, report::space_region_png(spline, plane, img, r.point, r.max_depth, true));
  if (!a.depth_map.empty() && !ends_with(a.depth_map, ".png"))
    out.stage(a.depth_map, pgm(img, img.depth, std::max(1, r.max_depth)));
  std::size_t mesh_faces = 0;
  if (!a.mesh.empty()) {  // the curve as a tube and the region as a patch in its plane
    mesh::Mesh m = mesh::plane_patch(img, plane);
    mesh::append(m, mesh::curve_tube(spline, tube));
    mesh_faces = m.n_faces();
    out.stage(a.mesh, mesh::mesh_file(a.mesh, m));
  }
  out.commit();
  std::uint64_t counts[kRegionLabelCodes] = {}, inside = 0;
  for (std::size_t i = 0; i < img.size(); ++i) ++counts[img.code_at(i)], inside += img.in_region(i) ? 1 : 0;
  if (fit && fit->empty)
    std::cerr << "cmr: note: P" << r.point << " has no region near the curve in this plane (the view is the curve's)\n";
  else if (fit && inside * 100 < img.size())  // under 1% of the picture though fitted: a speck beside the point
    std::cerr << "cmr: note: P" << r.point << "'s region is a speck: " << inside << " of " << img.size()
              << " pixels, far from the point or thin (--view zooms)\n";
  nlohmann::ordered_json c;
  for (std::uint8_t l = 0; l < kRegionLabelCodes; ++l) c[img.label_name(l)] = counts[l];
  nlohmann::ordered_json doc = {{"width", img.width},
                                {"height", img.height},
                                {"view", {img.view.x0, img.view.y0, img.view.x1, img.view.y1}},
                                {"plane", {{"origin", vec3(plane.origin)}, {"u", vec3(plane.u)}, {"v", vec3(plane.v)}}},
                                {"dimension", 3},
                                {"backend", backend->name()},
                                {"point", r.point},
                                {"view_fitted", fit.has_value()},
                                {"plane_name", report::space_plane_name(spline, plane, r.point)},
                                {"counts", c}};
  if (!a.mesh.empty()) doc["mesh"] = {{"faces", mesh_faces}, {"tube_radius", tube.radius}};
  if (a.stats) {
    doc["seconds"] = img.seconds;
    doc["exact_pixels"] = img.exact_pixels;
    if (const auto host = backend->host_pixels()) doc["host_pixels"] = *host;  // left to the CPU by the device
  }
  print_json(doc, a.pretty);
}

namespace {

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

}  // namespace

int run_space_report(const SpaceReportRun& run) {
  const report::SpaceReportOptions& o = run.options;
  validate(o.continuity);
  std::optional<report::BaselineComparison> baseline;
  if (run.baseline) baseline.emplace(report::read_baseline(*run.baseline));  // a bad baseline: before any work
  std::vector<report::SpaceReport> reports;
  std::vector<std::vector<report::Finding>> findings;
  std::vector<std::string> names;  // each file's name in findings
  const std::string root = run.source_root ? run.source_root->string() : std::string();
  for (const std::string& f : run.files) reports.push_back(report::space_report_analysis(f, o));
  report::space_report_extras(reports, o);  // fix searches and thumbnails, within the run's budget
  for (std::size_t i = 0; i < run.files.size(); ++i) {
    const std::string& f = run.files[i];
    const std::string base = run.source_root ? root : (i < run.bases.size() ? run.bases[i] : std::string());
    names.push_back(report::source_name(f, base));
    findings.push_back(report::space_findings(reports[i], names.back(), o));
  }
  const std::filesystem::path dir = run.out;
  OutputSet set;
  set.create_folder(dir);
  set.stage(dir / "index.html", report::space_report_html(reports, o));
  // The CI files: one suite per file (one case: its curve), one SARIF result per finding.
  std::string junit = report::junit_header(), sarif;
  if (run.sarif) sarif = report::sarif_header(run.parsed, report::source_uri_base(root));
  const std::string timestamp = utc_now();
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "localhost");
  int pass = 0, fail = 0, invalid = 0, new_findings = 0, unchanged = 0, results = 0;
  std::vector<const report::Finding*> new_list;
  std::optional<report::MarkdownSummary> markdown;
  if (run.markdown) markdown.emplace(run.parsed);
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const report::SpaceReport& r = reports[i];
    report::FileRecord rec;
    rec.path = rec.title = r.file;
    rec.items = 1;
    report::CaseRecord c;
    c.name = r.spline ? r.spline->name() : std::filesystem::path(r.file).filename().string();
    c.error = r.error;
    c.pass = r.error.empty() && r.pass;
    c.findings = findings[i];
    (!r.error.empty() ? rec.items_invalid : (r.pass ? rec.items_pass : rec.items_fail)) = 1;
    if (!r.error.empty()) {
      ++invalid;
      std::cerr << "cmr: " << r.error << '\n';
    } else {
      ++(r.pass ? pass : fail);
    }
    bool relative = false;
    const std::string uri = report::source_uri(r.file, root, &relative);
    if (run.sarif && !r.error.empty())
      sarif.append(results++ ? "," : "").append(report::sarif_invalid(uri, relative, c.name, r.error, run.parsed));
    for (const report::Finding& f : findings[i]) {
      const char* state = baseline ? baseline->judge(f) : nullptr;
      if (state && std::string(state) == "new") ++new_findings, new_list.push_back(&f);
      if (state && std::string(state) == "unchanged") ++unchanged;
      if (run.sarif) sarif.append(results++ ? "," : "").append(report::sarif_result(f, uri, relative, run.parsed, state));
    }
    rec.cases.push_back(std::move(c));
    junit += report::junit_suite(rec, static_cast<int>(i), timestamp, host);
    if (markdown) markdown->add(rec, names[i], "");
  }
  junit += report::junit_footer();
  if (run.sarif) sarif += report::sarif_footer();
  if (run.junit) set.stage(*run.junit, junit);
  if (run.sarif) set.stage(*run.sarif, sarif);
  const bool gated = o.require_monotone || !o.gates.empty();
  const int exit_code = invalid > 0 ? kInvalid
                        : baseline  ? (new_findings > 0 ? kFail : kOk)
                                    : (gated && fail > 0 ? kFail : kOk);
  int finding_count = 0;
  for (const auto& fs : findings) finding_count += static_cast<int>(fs.size());
  if (markdown) {  // the planar run's summary, from the same counts
    report::BatchSummary s;
    s.files = static_cast<int>(reports.size());
    s.items = s.files;
    s.pass = pass, s.fail = fail, s.invalid = invalid;
    s.findings = finding_count;
    s.baseline = baseline.has_value();
    s.new_findings = new_findings, s.unchanged = unchanged, s.fixed = baseline ? baseline->fixed() : 0;
    for (const report::Finding* f : new_list) s.new_list.push_back(*f);
    s.exit_code = exit_code;
    set.stage(*run.markdown, markdown->finish(s, run.baseline ? run.baseline->string() : std::string()));
  }
  nlohmann::ordered_json doc = report::space_report_json(reports, o, &findings);
  doc["summary"]["exit_code"] = exit_code;  // as a planar report's (report/merge.hpp reads it)
  if (baseline)
    doc["summary"]["baseline"] = {{"file", run.baseline->string()}, {"new", new_findings},
                                  {"fixed", baseline->fixed()}, {"unchanged", unchanged}};
  set.stage(dir / "report.json", json_text(doc, run.pretty));
  set.commit_last(dir / "report.json");  // renamed last: the commit marker
  set.commit();
  for (const report::Finding* f : new_list) std::cerr << "cmr: new: " << f->file << ": " << f->gate << ": " << f->message << '\n';
  if (run.quiet) return exit_code;
  const bool piped = (run.junit && is_stdout_path(*run.junit)) || (run.sarif && is_stdout_path(*run.sarif)) ||
                     (run.markdown && is_stdout_path(*run.markdown));
  std::ostream& line = piped ? std::cerr : std::cout;
  line << reports.size() << (reports.size() == 1 ? " space curve: " : " space curves: ") << pass << " pass, " << fail
       << " fail, " << invalid << " invalid";
  line << "; " << finding_count << (finding_count == 1 ? " finding" : " findings");
  if (baseline)
    line << " (baseline: " << new_findings << " new, " << baseline->fixed() << " fixed, " << unchanged << " unchanged)";
  line << "; wrote " << (dir / "index.html").string() << " and " << (dir / "report.json").string() << '\n';
  return exit_code;
}

StepEdge open_step_edge(const std::filesystem::path& model, const std::string& spec) {
  std::vector<long long> ids;
  try {
    ids = import::parse_step_edge_ids(spec);
  } catch (const InputError& e) {  // "--edges: ..." as cmr import says it
    throw InputError("--edge" + shown_message(e).substr(std::string("--edges").size()));
  }
  if (ids.size() != 1)
    throw InputError("--edge: one edge to edit (#1234), not " + std::to_string(ids.size()) + " (" + spec + ")");
  const import::StepCurves all = import::read_step_curves(model);
  import::StepCurves picked;
  try {
    picked = import::select_step_edges(all, ids, model.string());
  } catch (const InputError& e) {
    const std::string what = shown_message(e);
    throw InputError(what.rfind("--edges", 0) == 0 ? "--edge" + what.substr(7) : what);
  }
  const import::StepCurve& c = picked.curves.front();
  const nlohmann::json doc = nlohmann::json::parse(import::step_curve_json(c).dump());
  return {space_spline_from_json(doc),
          model.parent_path() / (model.stem().string() + "_" + import::step_curve_stem(c) + ".json")};
}

}  // namespace cmr::cli
