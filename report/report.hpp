#pragma once
/// Spline QA reports (`cmr report`): per spline, every span's classification
/// (Algorithms 1 and 2, CAD&A 2024 §3), the certified parameters of its
/// curvature extrema and inflections (numeric/roots.hpp), the joints, the
/// monotone pieces of the whole curve, and for a spline that fails the check,
/// which single control points have a region that fixes it (§4). Rendered as a
/// versioned JSON document (docs/report-schema.md) and one self-contained HTML
/// page; the exit code gates a batch. Library target cmr::report: it links no
/// command-line code and writes no files (the command writes what these
/// functions return, with cmr::write_file_atomic).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "bezierize/analyze.hpp"
#include "numeric/roots.hpp"

#include "region/region.hpp"
#include "spline/fields.hpp"
#include "spline/limits.hpp"
#include "report/certified_fix.hpp"
#include "report/gates.hpp"

namespace cmr::import {
struct ContourMotion;  // io/masters.hpp
}

namespace cmr::report {

/// The version of report_json's document (docs/report-schema.md).
inline constexpr const char* kSchema = "cmr-report/2";
/// The earlier version a baseline may still be (its findings are the same):
/// cmr-report/2 removed `tangent_fixes` (issue 22: certified fixes instead).
inline constexpr const char* kSchemaPrevious = "cmr-report/1";

/// exit_code's values; the cmr command exits with them.
inline constexpr int kExitPass = 0, kExitFail = 1, kExitInvalid = 2;
/// Default ReportOptions::constant_tolerance: well above the certification
/// error of kappa (kKappaRelError, 1e-11, times the piece's total curvature)
/// and far below any designed change.
inline constexpr double kDefaultConstantTolerance = 1e-9;

/// --constant-tol's rule, one for planar and space curves (docs/analyze.md,
/// docs/space.md): a piece of arc length at most L whose curvature lies in
/// [lo, hi] differs from the arc of constant curvature k0 = (lo + hi) / 2 by
/// |k - k0| <= (hi - lo) / 2 everywhere, so over any of its sub-arcs its total
/// curvature (the integral of k ds, its turning in radians) differs from
/// that arc's by at most
///   turning_deviation = (hi - lo) / 2 * L,
/// and, in the plane, its tangent by at most that angle and its points by at
/// most turning_deviation * L / 2 (model units) from the arc with the same
/// start and tangent. Dimensionless, unchanged by scaling the curve. A piece
/// is an arc of constant curvature within tol when turning_deviation <= tol.
/// L: the Bezier control polygon's length (polygon_length), which bounds the
/// arc length from above (corner cutting; positive weights for a rational
/// piece), so the bound holds.
inline double turning_deviation(double lo, double hi, double length) { return (hi - lo) / 2 * length; }

/// The length of a control polygon (Vec2 or Vec3 points).
template <class P>
double polygon_length(const std::vector<P>& points) {
  double l = 0;
  for (std::size_t i = 1; i < points.size(); ++i) l += glm::distance(points[i - 1], points[i]);
  return l;
}

/// Which curvature extremum a split requirement asks for at its joint, by
/// |kappa| (bezierize/extremum_terms.hpp): the sharpest or the flattest point.
enum class Extremum : std::uint8_t { any, sharpest, flattest };

/// What a spline must satisfy to pass: its CMRWI or CMR verdict is increasing
/// or decreasing, or (split:S) a curvature extremum at joint S and nowhere
/// else: segments 0..S-1 and S..N-1 each monotone in CMRWI mode, in opposite
/// directions (split verdict inc-dec or dec-inc). split:S:sharpest asks for
/// a maximum of |kappa| there, split:S:flattest for a minimum (the same
/// answer whichever way the curve runs or is mirrored); split:S:max and
/// split:S:min (signed kappa, which flips with the direction) are refused
/// with a one-line hint. With
/// ReportOptions::segments, "0..S-1" and "S..N-1" are the judged range's.
struct Requirement {
  Mode mode = Mode::cmr;
  std::optional<int> split;
  Extremum extremum = Extremum::any;  ///< with split
};
/// Parses "cmrwi", "cmr", "split:S", "split:S:sharpest" or "split:S:flattest"
/// (InputError otherwise).
Requirement parse_requirement(const std::string& text);
/// The text parse_requirement reads.
std::string to_string(const Requirement& r);
/// Whether a split verdict at `joint` (its certified curvatures give the
/// |kappa| reading) satisfies a split requirement's extremum.
bool split_passes(Split verdict, Extremum extremum, const Joint& joint);

/// How a batch is reported; the defaults are the command's.
struct ReportOptions {
  std::optional<Requirement> require;  ///< the gate; when empty splines are judged by CMR but cannot fail the run
  int max_depth = kDefaultDepth;       ///< D of Algorithms 1 and 2
  bool regions = true;                 ///< search single-point fixes (region images) and draw their thumbnails
  int region_size = 96;                ///< fix-search images are region_size x region_size over the default view
  std::shared_ptr<RegionBackend> backend;  ///< where region images are rendered (required with regions)
  int threads = 0;                     ///< threads for the per-spline analysis; 0: all cores
  RootOptions roots;                   ///< enclosure width of extrema and inflections
  ContinuityTolerances continuity;     ///< G1/G2 tests at joints (the same as cmr analyze's)
  /// Judge only these segments (verdicts, gate, fixes); the others are
  /// reported as ignored (their roots and the curve's events are still listed).
  std::optional<SegmentRange> segments;
  std::vector<Gate> gates;             ///< type-design gates (report/gates.hpp); a spline must pass all
  bool certified_fixes = true;         ///< with regions: the smallest certified fix of each failing check (report/certified_fix.hpp)
  /// A segment whose turning_deviation (its total curvature against an arc
  /// of constant curvature, radians) is at most this is read as an arc of
  /// constant curvature by the extremum gates (SpanReport::near_constant);
  /// 0: only exact constants.
  double constant_tolerance = kDefaultConstantTolerance;
  /// Severity (report/severity.hpp): when >= 0, each violation of a gate
  /// that has a fix gets the smallest certified move that removes it, and
  /// one whose move is below this (in the spline's units: font units) is
  /// `info`: reported, but it does not fail the gate (unless `strict`).
  /// < 0: not computed, every violation fails.
  double min_severity = -1;
  /// Fonts: with min_severity < 0, a font's glyphs get severity at
  /// report/severity.hpp's kDefaultMinSeverity (half a font unit): `cmr
  /// report`'s default; --no-severity turns it off.
  bool font_severity = false;
  bool strict = false;  ///< info findings fail too
  /// How the report's documents name the option fields (spline/fields.hpp)
  /// in the library messages they quote (a file's error, a fix's reason):
  /// by their names, or a program's own (the cmr command: its flags).
  std::function<std::string(const std::string&)> show_fields = plain_fields;
};

/// The check a spline is judged by: the requirement, or CMR without one.
Requirement check_of(const ReportOptions& options);

/// A root of lambda (a stationary point of the curvature) or of eta (a zero of
/// the curvature) in one segment, mapped to the spline's parameter.
struct SpanRoot {
  double t = 0;               ///< nearest double to the root (to its enclosure's midpoint if not exact)
  double t_lo = 0, t_hi = 0;  ///< enclosure, rounded outwards
  bool exact = false;         ///< the root is t exactly (before rounding to double)
  int multiplicity = 1;
  int sign_before = 0, sign_after = 0;  ///< of lambda (or eta) as this segment's polynomial
  enum class At : std::uint8_t { interior, start, end } at = At::interior;
  double kappa = 0;  ///< curvature at t (certified to kKappaRelError; NaN at a zero tangent)
};

/// One segment of a spline: its class and the roots of lambda and eta.
struct SpanReport {
  Segment segment;          ///< the span and its index
  std::vector<Vec2> bezier;  ///< the segment's Bezier points (to double precision)
  /// A rational segment's homogeneous Bezier points (w x, w y, w), to double
  /// precision (bezier holds their projections, NaN where w = 0); empty when
  /// polynomial.
  std::vector<glm::dvec3> homogeneous;
  SegmentClass classification;  ///< Algorithms 1 and 2
  SegmentShape shape;           ///< exact straight / cusp / inflection facts (analyze)
  bool lambda_zero = false;           ///< lambda == 0: constant curvature (a straight segment)
  bool eta_zero = false;              ///< eta == 0: zero curvature
  std::vector<SpanRoot> extrema;      ///< roots of lambda
  std::vector<SpanRoot> inflections;  ///< roots of eta
  /// (max kappa - min kappa) / max |kappa| over the segment, from the
  /// certified curvature at its ends and stationary points (each within
  /// kKappaRelError); 0 for a straight, NaN with a cusp or a pole.
  double kappa_spread = 0;
  /// turning_deviation(min kappa, max kappa, polygon_length of the Bezier
  /// points) from the same values: radians; NaN with a cusp or a pole.
  double turning_deviation = 0;
  /// turning_deviation <= ReportOptions::constant_tolerance: an arc of
  /// constant curvature up to the rounding of its data (an SVG or CAD circle
  /// arc, whose double weights and points make it an ellipse arc within
  /// 1e-16; OpenCASCADE's high-degree approximation of a circle).
  /// The verdicts stay exact; only the extremum gates exempt its extrema.
  bool near_constant = false;
};

/// "segment 3 has a pole at t≈0.5" (more parameters comma separated) for a
/// span whose shape has a pole (the gates' violation, the HTML's cells).
std::string pole_message(const SpanReport& span);

/// One joint: its analysis and its geometric continuity.
/// G1 and G2 (with ReportOptions::continuity) are in `joint`, computed by
/// analyze as for cmr analyze.
struct JointReport {
  Joint joint;  ///< knot, multiplicity, curvature on both sides, g1, g2
  std::string continuity;  ///< "C<k>" from the knots alone (k = degree - multiplicity)
  bool corner = false;     ///< not G1 (directions differ, or a zero tangent)
};

/// A curvature extremum or inflection of the whole curve: a change in the sign
/// of dkappa/ds (or of kappa) along the parameter, jumps at joints included.
struct CurveEvent {
  double t = 0;      ///< the spline parameter
  int kind = 0;      ///< extremum: +1 maximum, -1 minimum; inflection: sign of kappa after it
  double kappa = 0;  ///< extremum: the extreme value (the larger / smaller side of a jump)
  int segment = -1;  ///< inside this segment, or
  int joint = -1;    ///< on this joint (index i: between segments i-1 and i)
};

/// What moving one control point alone can do for a failing spline (§4).
struct Fix {
  int point = 0;                ///< the control point's index
  std::uint64_t pixels = 0;     ///< pixels of the region that pass the check
  std::optional<Vec2> example;  ///< the passing pixel centre nearest the current point
  bool verified = false;        ///< analyze on the spline with the point moved there passes
  std::string thumbnail_png;    ///< region picture (PNG bytes); empty when not drawn
};

/// Everything reported about one spline (or why it could not be read).
struct SplineReport {
  std::string file;   ///< as given on the command line (or a label)
  std::string name;   ///< the spline's name, else the file's stem
  std::string error;  ///< invalid input: the message; nothing below is filled
  std::optional<BSpline> spline;
  SplineAnalysis analysis;  ///< analyze() with the report's depth and split
  bool pass = false;        ///< it satisfies check_of(options) (unless only gates are asked for) and every gate
  bool requirement_pass = false;     ///< it satisfies check_of(options)
  std::vector<GateResult> gates;     ///< one per ReportOptions::gates
  std::vector<SpanReport> spans;    ///< one per segment
  std::vector<JointReport> joints;  ///< one per joint (segment i-1 | i); a closed spline's seam last (index N)
  std::vector<CurveEvent> extrema;      ///< in parameter order
  std::vector<CurveEvent> inflections;  ///< in parameter order
  int monotone_pieces = 1;              ///< extrema.size() + 1
  double kappa_min = 0, t_min = 0, kappa_max = 0, t_max = 0;  ///< curvature range and where it is reached
  bool cusp = false;  ///< some segment has a zero tangent: the range is unbounded (kappa_min/max are NaN)
  std::optional<std::vector<Fix>> fixes;  ///< one per control point; only for failing splines with regions on
  /// The smallest certified fix of each failing check (report/certified_fix.hpp); with regions and certified_fixes on.
  std::vector<CertifiedFix> certified_fixes;
  /// A master's contour (a designspace, a variable font): how it moves along
  /// each piece of the design space (io/masters.hpp), for the interpolation
  /// gates (report/interpolation.hpp); null otherwise.
  std::shared_ptr<const std::vector<import::ContourMotion>> motions{};
};

/// Every judged segment is straight (eta == 0: zero curvature throughout; a
/// glyph's l, I, H, -): its curvature is constant, so the pages and
/// report.json label it "straight" rather than by a direction (analyze's
/// Algorithm 1 says "increasing" there, docs/semantics.md).
bool straight_only(const SplineReport& r);
/// The label of a verdict of `r`: "straight" when straight_only(r), else
/// to_string(d).
std::string verdict_label(const SplineReport& r, Direction d);

/// One item of a batch: a spline, or why it could not be read.
struct ReportInput {
  std::string file;               ///< path or label
  std::optional<BSpline> spline;  ///< the spline, when it could be read
  std::string error;              ///< else the InputError's message (its fields marked; process_file shows them)
  std::shared_ptr<const std::vector<import::ContourMotion>> motions{};  ///< SplineReport::motions
};
/// Reads a spline file; an invalid one becomes an item with its error.
ReportInput read_input(const std::string& file);

/// The report model of one spline: everything but the gates and the fixes
/// (thread-safe). `pass` is the requirement's verdict only; the gates are
/// judged on the model by report/batch.hpp (judge_gates, judged_report,
/// report_batch: report -> gates -> fixes). Throws InputError when the
/// options do not fit the spline (a split joint it does not have).
/// With `classify` false, Algorithm 1 and 2 are not run, so every segment's
/// class is empty (SegmentClass{}: undecided), as are the verdicts and
/// requirement_pass made of them; everything else (shapes, joints, spans,
/// extrema, inflections, curvature range) is the same. For judges of gates
/// that do not read the classes (report/batch.hpp: gate_report), never for
/// a written report.
SplineReport report_spline(const BSpline& spline, const ReportOptions& options, bool classify = true);
/// The curvature extrema that curvature-extrema-at-nodes finds on a spline
/// of one segment (open, polynomial): as many as the gate's violations on
/// judged_report(spline, judge_only(options, that gate)), computed from the
/// parts of the model the gate reads (lambda's certified roots, and the
/// segment's curvature range when it has an extremum), without Algorithm 1
/// and 2 or the inflections. The severity search's judge of an extremum
/// (report/severity.cpp). nullopt for any other spline.
std::optional<int> segment_extrema_count(const BSpline& spline, const ReportOptions& options);
/// Fills report.fixes for a failing spline (renders one region per control point).
void find_fixes(SplineReport& report, const ReportOptions& options);

/// 0 when every spline passes (or there is no requirement), 1 when one fails,
/// 2 when an input is invalid (kExitPass, kExitFail, kExitInvalid).
int exit_code(const std::vector<SplineReport>& reports, const ReportOptions& options);

/// The words report.json writes: a spline's status ("pass", "fail",
/// "invalid"), a root of λ's kind ("maximum", "minimum", "touch", from the
/// signs of λ around it) and where in its span it lies ("interior", "start",
/// "end"). One definition for the tree writer (report_json) and the
/// streamed one (report/json_stream.hpp), which must write the same bytes.
const char* status_word(const SplineReport& r);
const char* root_kind_word(int sign_before, int sign_after);
const char* root_at_word(SpanRoot::At at);

/// A spline's "gates" in report.json: [{"gate", "pass", "violations": [{"t",
/// "message", "segment", "local_t"} or {"t", "message", "joint"}]}], one per
/// judged gate (report_json and the Python module's cmr.judge_many).
nlohmann::ordered_json gates_json(const SplineReport& r);
/// The report as a cmr-report/2 document (docs/report-schema.md).
nlohmann::ordered_json report_json(const std::vector<SplineReport>& reports, const ReportOptions& options);
/// One self-contained page: no network, pictures inline (SVG, data: URIs).
std::string report_html(const std::vector<SplineReport>& reports, const ReportOptions& options);
/// report_html's pieces, for a page written in pieces (report/corpus.hpp):
/// its style sheet, and the sections of `reports` anchored s<first + i>.
std::string report_style();
std::string report_sections_html(const std::vector<SplineReport>& reports, int first, const ReportOptions& options);

}  // namespace cmr::report
