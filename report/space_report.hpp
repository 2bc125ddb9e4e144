#pragma once
/// QA reports of space curves (issue 25, docs/space.md): `cmr report` when
/// every input is a space curve. The model, its JSON and a self-contained
/// HTML page (three orthographic projections with the curvature comb, the
/// curvature and torsion plots, the segments and joints), in memory.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/space_analyze.hpp"
#include "design/space_fix.hpp"
#include "region/space_region.hpp"
#include "report/corpus.hpp"
#include "report/gates.hpp"
#include "spline/fields.hpp"

namespace cmr::report {

struct SpaceReportOptions {
  int max_depth = kDefaultDepth;
  bool torsion = true;  ///< judge torsion monotonicity too (reported; the gate is curvature's)
  double torsion_tolerance = 0;  ///< SpaceAnalyzeOptions::torsion_tolerance (`--torsion-tol`)
  ContinuityTolerances continuity;
  bool require_monotone = false;  ///< the gate: |kappa| monotone over the whole spline
  /// --require cmr: monotone and kappa never 0 (zero curvature is the space
  /// analogue of an inflection); implies require_monotone.
  bool require_no_zero_curvature = false;
  /// The gates of the planar report that have a meaning in 3D
  /// (space_requirements): curvature-extrema-at-nodes,
  /// max-extrema-per-segment:N, g2-at-smooth-nodes[:tol], no-inflection
  /// (no zero curvature) and each-piece.
  std::vector<Gate> gates;
  /// The planar report's rule (ReportOptions::constant_tolerance,
  /// turning_deviation in report.hpp): a segment whose |kappa|, at its ends
  /// and stationary points, lies in [lo, hi] with (hi - lo) / 2 times its
  /// control polygon's length at most this (radians) is an arc of constant
  /// curvature up to the rounding of its data (a CAD circle, an
  /// OpenCASCADE approximation of one): the extremum gates skip it, and a
  /// curve whose every segment and whole length is such an arc (the whole
  /// curve's lo, hi and length) passes cmrwi and cmr (its exact verdict is
  /// still reported).
  double constant_tolerance = kDefaultConstantTolerance;
  /// Search the smallest certified fix of each failing curve (space_fix,
  /// cmrwi, each point in its default plane, kReportSpaceFixSeconds).
  bool fixes = true;
  bool regions = true;            ///< a region thumbnail per control point (`cmr report --no-thumbnails`: off)
  int region_size = 96;           ///< thumbnails are region_size x region_size (`--region-size`)
  /// Seconds of wall time for every fix search and thumbnail of a run
  /// (space_report_extras; `cmr report --fix-budget`, default
  /// kDefaultSpaceBudgetSeconds for space curves); 0: no limit.
  double budget = 0;
  /// How the documents name the option fields quoted in library messages
  /// (ReportOptions::show_fields).
  std::function<std::string(const std::string&)> show_fields = plain_fields;
};

/// The region of one control point in its default plane
/// (default_space_plane, the plane `cmr region FILE --point K` takes without
/// --plane), over the default view, at the report's depth: the labels of
/// `cmr region FILE --point K --size NxN --depth D` and its --png picture.
struct SpaceThumbnail {
  int point = 0;
  std::string error;  ///< why there is no region (e.g. a degenerate default plane); then nothing else is filled
  SpacePlane plane;
  RegionResult image;
  std::string png;
  std::string plane_name;  ///< "the plane through P3 spanned by P4 − P3 and P2 − P3"
};

/// Time limit of a failing space curve's fix search in a report (seconds);
/// the nearest fix found by then is still certified.
inline constexpr double kReportSpaceFixSeconds = 2;

/// `cmr report`'s default budget for a run of space curves' fix searches
/// and thumbnails (SpaceReportOptions::budget): a thumbnail of a degree-14
/// CAD edge takes 5-60 s (lambda3 of degree 73 a pixel, exact arithmetic on
/// the region's boundary), and such an edge can have 183 points.
inline constexpr double kDefaultSpaceBudgetSeconds = 5;

struct SpaceReport {
  std::string file;
  std::string error;  ///< the input's one-line error (then nothing else is filled)
  std::optional<SpaceSpline> spline;
  SpaceAnalysis analysis;
  std::vector<std::vector<SpaceExtremum>> extrema;  ///< per segment, certified locations
  double kappa_min = 0, kappa_max = 0;              ///< sampled (the plot's range)
  /// The check (cmrwi, or cmr with require_no_zero_curvature) holds: the
  /// curvature verdict is increasing or decreasing, or the curve is
  /// near_constant; and every gate passes.
  bool pass = false;
  bool check_pass = false;  ///< the check alone
  /// Per segment: (max - min) / max of |kappa| at its ends and stationary
  /// points (0 for a straight segment), reported.
  std::vector<double> kappa_spread;
  double spread = 0;  ///< the same over the whole curve
  /// Per segment: turning_deviation(min, max, polygon length) of the same
  /// values (radians); near_constant when every segment's and the whole
  /// curve's (`deviation`) are at most options.constant_tolerance.
  std::vector<double> turning_deviation;
  double deviation = 0;  ///< the same over the whole curve
  bool near_constant = false;
  std::vector<GateResult> gates;  ///< options.gates, in order
  std::vector<SpaceThumbnail> thumbnails;  ///< the points' drawn (or refused) regions, by point, when options.regions
  /// Points whose thumbnail the run's budget left out (space_report_extras), ascending.
  std::vector<int> regions_not_drawn;
  std::optional<SpaceFixResult> fix;  ///< failing curves, with options.fixes
  bool fix_not_searched = false;      ///< failing, options.fixes, and the run's budget was spent before its search
};

/// The picture of a space region (`cmr region --png` and the report's
/// thumbnails): the labels, with the curve and its control polygon projected
/// onto the plane and point `point` marked.
std::string space_region_png(const SpaceSpline& spline, const SpacePlane& plane, const RegionResult& image, int point,
                             int max_depth, bool depth_shading = false);
/// The default view of a space region (`cmr region FILE --point K` without
/// --view, the report's thumbnails; issue 40 item 6): the union of the
/// region and the moved point, with a margin. A 64 x 64 probe over the
/// polygon's default view (default_view of the curve projected onto the
/// plane) widened 3 times about its centre, at the request's depth, finds
/// the region's pixels (RegionResult::in_region); their rectangles' box and
/// the moved point's plane coordinates, widened by 15% of the larger side
/// each way and then in one direction so that pixels are square, is the
/// view. No region in the probe: the polygon's view, `empty`. The request's
/// plane must be set (or is the default plane); its view is ignored.
struct SpaceViewFit {
  View view;
  bool empty = false;     ///< no region pixel in the probe
  int probe_pixels = 0;   ///< the probe's region pixels (of 64 x 64)
};
SpaceViewFit fit_space_view(const SpaceSpline& spline, const SpaceRegionRequest& request);

/// "plane through P3: a (right) along P4 - P3, b (up) along P2 - P3" (a
/// direction that leads to a control point is named by it, others by their
/// coordinates): the last line of a space region picture's legend and the
/// `plane_name` of `cmr region`'s summary.
std::string space_plane_name(const SpaceSpline& spline, const SpacePlane& plane, int point);

/// The thumbnail of control point k (its region in its default plane);
/// `time_limit`: seconds for its renders (SpaceRegionRequest::time_limit).
SpaceThumbnail space_thumbnail(const SpaceSpline& spline, int k, int size, int max_depth,
                               double time_limit = kDefaultSpaceRegionSeconds);

/// The planar report's --require (parse_require_list into `parsed`) for a
/// run of space curves: cmrwi and cmr and the gates above go into `o`; a
/// check or gate that has no meaning for a space curve (split:S, the
/// quadratic-run and x/y-extremum gates of fonts) is an InputError naming
/// `file`, the run's first space curve.
void space_requirements(const ReportOptions& parsed, SpaceReportOptions& o, const std::string& file);

/// The findings of one report (Finding::key as the planar report's: file,
/// the spline's name, contour 0, "segment i" / "joint i", the gate or the
/// check), `name` being the file's name in findings (source_name).
std::vector<Finding> space_findings(const SpaceReport& r, const std::string& name, const SpaceReportOptions& options);

/// Reads and analyses one file (the verdict, extrema, gates, pass), without
/// its fix search and thumbnails; an InputError becomes `error`.
SpaceReport space_report_analysis(const std::string& file, const SpaceReportOptions& options);

/// The costly parts of a run's reports within options.budget seconds of
/// wall time for the whole run (0: no limit), curve by curve: the failing
/// curves first, then the passing ones, each group cheapest first (by
/// (6d - 11)^2 times the segments: lambda3's degree is 6d - 11) so that the
/// budget covers as many curves as it can. For each: its fix search when it
/// fails (options.fixes; kReportSpaceFixSeconds, or what is left), then its
/// thumbnails (options.regions): the fix's point first, then the points that
/// act on its failing segments, then its other points. Each render gets what is left of
/// the budget (at most kDefaultSpaceRegionSeconds); what the budget leaves
/// out is listed (SpaceReport::regions_not_drawn, fix_not_searched), never
/// half drawn. Thumbnails are kept by point.
void space_report_extras(std::vector<SpaceReport>& reports, const SpaceReportOptions& options);

/// Reads and analyses one file, then its fix search and thumbnails
/// (space_report_analysis, space_report_extras).
SpaceReport space_report(const std::string& file, const SpaceReportOptions& options);

/// The JSON of `cmr analyze` for a space curve: {"segments": [segment i ...],
/// "joints": [joint ..., the seam], "spline": verdict}, built from the three
/// parts below (the CLI prints them one at a time).
nlohmann::ordered_json space_analysis_json(const SpaceSpline& spline, const SpaceAnalysis& analysis);
nlohmann::ordered_json space_segment_json(const SpaceSpline& spline, const SpaceAnalysis& analysis, std::size_t i);
nlohmann::ordered_json space_joint_json(const SpaceAnalysis& analysis, const SpaceJoint& joint);
nlohmann::ordered_json space_verdict_json(const SpaceAnalysis& analysis);
/// report.json: {"schema": kSchema, "dimension": 3, "splines": [...],
/// "summary": {...}}; each spline with its "status" (pass, fail, invalid)
/// and, with `findings` (one list per report), its "findings" as the planar
/// report writes them ({"gate", "node", "message", "key"}: a baseline of
/// either reads both).
nlohmann::ordered_json space_report_json(const std::vector<SpaceReport>& reports, const SpaceReportOptions& options,
                                         const std::vector<std::vector<Finding>>* findings = nullptr);
/// A fix's entry of report.json's "certified_fixes" (the planar report's
/// fields, 3D points): {"check": "cmrwi", "found", "moves": [{"point", "name",
/// "from", "to", "displacement", "distance", "relative"}], "max_relative",
/// "seconds", "failing_segments", "certificate": {"curvature"}} with
/// "reason" when none was found.
nlohmann::ordered_json space_fix_json(const SpaceFixResult& fix);
/// index.html, self-contained (inline SVG).
std::string space_report_html(const std::vector<SpaceReport>& reports, const SpaceReportOptions& options);

}  // namespace cmr::report
