#pragma once
/// Space curves from STEP files (issue 25) through OpenCASCADE (OCCT, Debian's
/// libocct-*-dev packages): the B-spline and Bezier curves of a STEP model,
/// the edges of its B-rep shapes included, as cmr space spline files.
///
/// What is read: every root the STEP reader transfers (STEPControl_Reader:
/// solids, shells, faces, wires, edges, geometric curve sets), then every
/// distinct edge of the resulting shape (TopExp::MapShapes: an edge shared by
/// two faces counts once), in the order OCCT numbers them. An edge's 3D curve
/// (BRep_Tool::Curve, its location applied; a Geom_TrimmedCurve's basis
/// curve) is kept when it is a Geom_BSplineCurve or a Geom_BezierCurve (a
/// Bezier curve becomes a one-span B-spline); the part of it the edge uses
/// (its parameter range) is what is converted (Geom_BSplineCurve::Segment). Every other curve type (lines,
/// circles, ellipses, offset curves, ...) and degenerated edges (no 3D curve)
/// are skipped and counted by type (StepCurves::skipped), and so are
/// B-splines of degree 1 (polylines: cmr's splines have degree >= 2).
///
/// Conversion (OCCT knots + multiplicities -> cmr's polar-form knots):
///  - open curves: OCCT's flat knot sequence (KnotSequence, points + degree +
///    1 values) without its first and last value: m points, m + d - 1 knots;
///  - periodic curves: "closed": true with the m distinct poles (rotated so
///    that cmr's first span uses the poles OCCT's does) and the m + 1 knots of
///    one period, each knot as often as its multiplicity (docs/spline-files.md),
///    when that curve evaluates as OCCT's does; otherwise the curve is
///    unperiodised (SetNotPeriodic, the same curve as an open B-spline);
///  - rational curves: "weights" (one per point); a rational curve whose
///    weights are all equal is the polynomial curve and gets none.
/// Every converted curve is evaluated against OCCT's at sample parameters
/// (error <= 1e-9 of its bounding box), so a conversion slip cannot pass
/// silently (InputError naming the edge).
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace cmr::import {

/// Where an edge comes from in the STEP file (read_step_curves: through
/// OpenCASCADE's transfer process, XSControl_TransferReader's
/// TransientProcess, whose binders map each EDGE_CURVE (or a wireframe's
/// TRIMMED_CURVE), ADVANCED_FACE, CLOSED_SHELL/OPEN_SHELL and
/// PRODUCT_DEFINITION to its shape). Names are the entities' name
/// attributes ('' in the file: empty); the face and shell are the first that
/// hold the edge, the product the smallest one whose shape holds it.
struct StepOrigin {
  long long entity = 0;  ///< the edge's entity, #1234 (0: not traced, a shape built in memory)
  std::string edge_name, face_name, shell_name, product_name;
};

struct StepCurve {
  std::string name;          ///< step_curve_name: "edge #1234 (box (0, 0, 0)..(40, 30, 20))"
  int edge = 0;              ///< OCCT's 1-based edge index (TopExp::MapShapes)
  StepOrigin origin;
  glm::dvec3 box_min{0}, box_max{0};  ///< the edge's bounding box (BndLib_Add3dCurve::AddOptimal, its range only)
  std::string type;          ///< "Geom_BSplineCurve" or "Geom_BezierCurve"
  int degree = 0;
  std::vector<double> knots;  ///< cmr's polar-form knots (one period when closed)
  std::vector<glm::dvec3> points;
  std::vector<double> weights;  ///< empty: polynomial
  bool closed = false;
  bool unperiodised = false;  ///< OCCT's curve was periodic and is written open
  bool trimmed = false;       ///< the edge uses part of the curve's domain
  /// Its |kappa| by cmr's certified analysis (analyze_space, CMRWI rules), in
  /// the curve's own direction: "increasing", "decreasing", "none",
  /// "undecided", or "not judged (...)" (edges of chains only; "" otherwise).
  std::string curvature;
};

/// Chains of edges (issue 40 item 4): the runs of consecutive converted
/// edges of each wire of the model (BRepTools_WireExplorer: edges in wire
/// order, each with its orientation; a line or circle between two edges ends
/// a run), each run once (an edge shared by two faces' wires is in both),
/// cut at corners (tangents more than corner_deg apart: a face's corner is
/// meant, not a continuity defect) into chains of two edges or more.
/// At each shared vertex, with the orientations applied (a reversed edge is
/// walked from its end: the first and third derivatives change sign):
///   gap    |end of one - start of the next|; more than ChainTolerances::gap
///          is an InputError naming both edges (one line, exit 2);
///   G1     tangent angle <= angle_deg;
///   G2     G1 and |kappa_l N_l - kappa_r N_r| <= curvature_rel * max(kappa)
///          (curvature vectors: magnitude and osculating plane);
///   G3     G2 and |dkappa/ds_l - dkappa/ds_r| <= g3_rel * max(|dk_l|, |dk_r|,
///          kappa_max^2) and |tau_l - tau_r| <= g3_rel * max(|tau_l|, |tau_r|,
///          kappa_max), with a, b, c the first three derivatives:
///          kappa = |a x b| / |a|^3, tau = det(a, b, c) / |a x b|^2,
///          dkappa/ds = ((a x b).(a x c) / (|a x b| |a|^3) - 3 |a x b| (a.b) / |a|^5) / |a|.
/// Derivatives from OpenCASCADE's curve (Geom_BSplineCurve::D3, rational
/// curves exactly). Monotone: "each edge" when every edge's |kappa| is
/// monotone (increasing, decreasing or none: constant); "whole chain" when,
/// walked along the chain, all go one way and no junction's kappa jumps
/// against it (beyond curvature_rel).
struct ChainTolerances {
  double gap = 1e-6;            ///< model units
  double angle_deg = 1e-3;      ///< G1
  double curvature_rel = 1e-6;  ///< G2
  double g3_rel = 1e-3;         ///< G3
  double corner_deg = 10;       ///< a junction whose tangents differ more is a corner: it ends the chain
};

struct StepJunction {
  double gap = 0, angle_deg = 0;
  double kappa_left = 0, kappa_right = 0, dkds_left = 0, dkds_right = 0, tau_left = 0, tau_right = 0;
  int level = 0;  ///< 0 (not G1), 1, 2 or 3
  glm::dvec3 at{0};
};

struct StepChain {
  std::vector<std::size_t> curves;      ///< indices into StepCurves::curves, in chain order
  std::vector<bool> reversed;           ///< walked against the curve's parameter
  std::vector<StepJunction> junctions;  ///< junctions[i]: curves[i] -> curves[i + 1] (closed: and last -> first)
  bool closed = false;
};

struct StepCurves {
  std::vector<StepCurve> curves;
  int edges = 0;                         ///< distinct edges in the model
  std::map<std::string, int> skipped;    ///< curve type (or "degenerated edge") -> count
  std::map<long long, std::string> skipped_entities;  ///< traced edges skipped: #id -> curve type
  std::vector<StepChain> chains;
};

/// A chain's junctions computed again, by OpenCASCADE, from the converted
/// curves (StepCurve's points, knots and weights; open curves only): the
/// certificate of a chain fix (step/chain_fix.hpp), whose edges exist only
/// in cmr's form. InputError for a closed edge.
std::vector<StepJunction> step_chain_junctions(const StepCurves& curves, const StepChain& chain,
                                               const ChainTolerances& tolerances = {});

/// Walked along a chain: each edge's |kappa| direction (a reversed edge's
/// the other way round), the edges that are not monotone ("-#55
/// undecided", "#40 not monotone": analyze_space's "none"), and whether the
/// whole chain goes one way: every edge the same way and no junction's kappa
/// jumping against it (beyond curvature_rel); a closed chain never (its kappa
/// cannot grow all the way round). `way`: "increasing" or "decreasing" when
/// one way, else "". (An edge of constant kappa is "increasing" by
/// analyze_space's rules, as in `cmr analyze`.)
struct ChainVerdict {
  std::vector<std::string> directions;  ///< in chain order
  std::vector<std::string> not_monotone;
  bool one_way = false;
  std::string way;
};
ChainVerdict chain_verdict(const StepCurves& curves, const StepChain& chain, const ChainTolerances& tolerances = {});

/// "#12" or "-#55" (walked reversed): the i-th edge of a chain.
std::string chain_edge_label(const StepCurves& curves, const StepChain& chain, std::size_t i);

/// The chains' report, one line per chain then one per junction:
///   chain 1: #12 > #40 > -#55 (3 edges, open): each edge monotone; whole chain: kappa increasing
///     #12 > #40 at (1, 2, 3): G3 (gap 0, angle 0 deg, kappa 0.5 | 0.5, dkappa/ds 0.1 | 0.1, tau 0 | 0)
/// ("-#55": walked reversed; "not monotone: #40 undecided" and so on).
std::vector<std::string> step_chain_report(const StepCurves& curves, const ChainTolerances& tolerances = {});
/// One chain's lines (numbered `index`, 1-based).
std::vector<std::string> step_chain_report(const StepCurves& curves, const StepChain& chain, int index,
                                           const ChainTolerances& tolerances = {});

/// A curve's name: "edge #1234" (or "edge 57", OCCT's index, when the edge
/// was not traced to an entity), then its names where the file has them and
/// its bounding box: "edge #1234 'rim' (face 'top', shell 'body', product
/// 'Bracket'; box (0, -2.5, 0)..(40, 30, 20))". Numbers with 6 significant
/// digits.
std::string step_curve_name(const StepCurve& curve);

/// "edge #1234", or "edge 57" (OCCT's index) when not traced.
std::string step_edge_label(const StepCurve& curve);
/// "#1234", or "edge 57" when not traced (chains, lists).
std::string step_edge_id(const StepCurve& curve);

/// The file stem of a curve's spline file: "1234" (the entity), or "edge57".
std::string step_curve_stem(const StepCurve& curve);

/// `--edges '#1234,#1240'`: the entity ids, in order, without repeats.
/// InputError "edges: ..." (edges a field, spline/fields.hpp) for anything but comma-separated #N.
std::vector<long long> parse_step_edge_ids(const std::string& spec);

/// `curves` with only the curves whose entities are `ids`, in the order of
/// `ids`, and the chains all of whose edges are among them.
/// InputError "edges: #999 is not an edge of FILE" (or "... is a
/// Geom_Line edge, skipped: ...") for an id that names no converted curve.
StepCurves select_step_edges(const StepCurves& curves, const std::vector<long long>& ids,
                                         const std::string& where);

/// Whether this cmr was built with the STEP importer (OCCT found at configure time).
bool step_supported();

/// The curves of a STEP file. InputError "FILE: ..." (one line) when the file
/// cannot be read, is not STEP, or holds no B-spline or Bezier curve ("FILE:
/// no B-spline or Bezier curves (12 edges: 12 Geom_Line skipped)");
/// InputError "FILE: cmr was built without STEP support (OpenCASCADE was not
/// found when it was configured; tools/setup.sh installs it)" in a build
/// without OCCT.
StepCurves read_step_curves(const std::filesystem::path& path, const ChainTolerances& chains = {});

/// The pre-scan of a STEP file's text (ISO 10303-21), before OpenCASCADE
/// sees it, outside 'strings' (where '' is a quote), "binaries" and /*
/// comments */:
///  - how deep its parentheses nest, and the line where that depth is first
///    reached. read_step_curves refuses a file deeper than max_step_nesting:
///    OCCT's reader recurses per level and a file nesting 200,000
///    parentheses overflowed its stack (issue 42 E4). Real models nest a few
///    levels (lists of lists of points).
///  - the first number that is no geometry: a real whose magnitude exceeds
///    max_step_magnitude (or that overflows a double, 1.E400), or an integer
///    beyond a 32-bit int, with the entity (#id) whose parameters hold it.
///    OCCT treats 2e100 as infinite (Precision::Infinite) and its shape
///    healing squares coordinates: one point of the example model at
///    (1.E308, -1.7E308, 1.E308) kept it classifying points for more than
///    120 s (issue 42 E5). A model in millimetres (or metres, or inches)
///    has no coordinate, knot or weight near 1e100.
struct StepScan {
  int depth = 0;
  int line = 1;  ///< where `depth` is first reached
  /// The first number out of range ("" when none), its entity and line.
  std::string bad_number;
  long long bad_entity = 0;  ///< 0: outside any entity (the header)
  int bad_line = 0;
  /// The first break of an instance's parentheses ("" when none): a ')'
  /// without its '(', a ';' inside parentheses, or more than ';' after the
  /// parameter list closed; or an instance defined twice. OCCT's parser recovers from some of these with a
  /// null entity that its model loader then dereferences (SIGSEGV; fuzz_step).
  std::string syntax;
  int syntax_line = 0;
};
StepScan step_scan(std::string_view text);
inline constexpr int max_step_nesting = 256;
inline constexpr double max_step_magnitude = 1e100;

/// The time budget of reading a STEP file of `bytes` bytes, in seconds:
/// 5 s + 4 s per MB. `cmr import` reads the example model (200 KB) in 0.1 s
/// and its 100-copy benchmark model (21 MB; budget 89 s) in 4.6 s of CPU,
/// 18.5 s on the loaded 2-core VM (cmr_step_model OUT 100). `cmr import`
/// stops a read that outlives it (OCCT's algorithms cannot be interrupted)
/// with one line and exit 2, before anything is written (and reads the
/// environment variable CMR_STEP_TIME_BUDGET, seconds, which replaces it for
/// tests; the library reads no environment).
double step_time_budget(std::uintmax_t bytes);

/// The spline file of a curve: {"name", "degree", "knots", "points" ([x, y, z]),
/// "weights" (rational only), "closed" (closed only)}.
nlohmann::ordered_json step_curve_json(const StepCurve& curve);

/// "12 Geom_Line, 2 Geom_Circle" (empty when nothing was skipped).
std::string skipped_summary(const StepCurves& curves);

}  // namespace cmr::import
