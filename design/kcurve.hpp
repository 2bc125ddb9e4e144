#pragma once
// κ-curves (Yan, Schiller, Wilensky, Carr, Schaefer, "κ-Curves: Interpolation
// at Local Maximum Curvature", ACM TOG 36(4), 2017) and their subdivided,
// degree-elevated cubic chain (CAD&A 2024 §5.2, Eq. 7), written from the
// published method and derived here.
//
// Setting. Points p_0..p_{n-1}. Closed: N = n quadratics, one per point,
// indices mod N. Open: the ends p_0, p_{n-1} are the curve's ends and the
// N = n-2 interior points get one quadratic each. Quadratic i is
//     c_i(t) = (1-t)^2 c_{i,0} + 2t(1-t) c_{i,1} + t^2 c_{i,2},
// its joints are shared with the neighbours on the line of the middle points,
//     c_{i,2} = c_{i+1,0} = (1-λ_i) c_{i,1} + λ_i c_{i+1,1},          (J)
// and it must interpolate its point at its curvature maximum:
// p_i = c_i(t_i) with |κ_i| largest at t_i. Open ends: c_{0,0} = p_first and
// c_{N-1,2} = p_last, i.e. λ_{-1} = 0 with c_{-1,1} := p_first and
// λ_{N-1} = 1 with c_{N,1} := p_last in (J).
//
// 1. t_i (the cubic). With A = c_{i,0} - p_i, B = c_{i,2} - p_i, s = 1-t and
//    M = c_{i,1} - p_i, interpolation gives 2ts M = -(s^2 A + t^2 B). A
//    quadratic's κ = det(c', c'')/|c'|^3 has a constant numerator, so |κ| is
//    largest where |c'| is smallest: c'(t)·c'' = 0. Substituting M,
//        2ts c'(t)/2 = t^2 B - s^2 A,   2ts c''/2 = 2(s A + t B),
//    so t_i is a root of f(t) = (t^2 B - s^2 A)·(s A + t B)
//        = t^3 |B|^2 - s^3 |A|^2 + ts(t - s) A·B,
//    in Bernstein form on [0,1]: (-|A|^2, -A·B/3, A·B/3, |B|^2). Its monomial
//    leading coefficient is |B - A|^2 = |c_{i,2} - c_{i,0}|^2, which vanishes
//    when the quadratic's ends coincide; the Bernstein form does not care.
//    f(0) = -|A|^2 <= 0 <= |B|^2 = f(1), so [0, 1] holds a root; Yan et al.
//    prove it is the only one (the tests check that on random A, B with
//    certified root isolation). It is found by bisection on the sign of f,
//    which needs no leading coefficient.
// 2. λ_i (G2). At the end of a quadratic (a, m, b), |κ(1)| = area(a,m,b)/|b-m|^3.
//    With b on segment m n at λ (n = c_{i+1,1}), area(a,m,b) = λ area(a,m,n)
//    and |b-m| = λ|n-m|; on the right side the same with 1-λ. Equal curvature
//    magnitudes give λ^2/(1-λ)^2 = area(a,m,n)/area(m,n,e), so
//        λ_i = sqrt(A1) / (sqrt(A1) + sqrt(A2)),
//        A1 = area(c_{i,0}, c_{i,1}, c_{i+1,1}), A2 = area(c_{i,1}, c_{i+1,1}, c_{i+1,2}),
//    with the areas of the current iterate; λ_i = 1/2 when both vanish
//    (collinear points). Where the two triangles turn opposite ways (an
//    inflection) only |κ| is matched: the joint is G1 with a curvature sign change.
// 3. The middle points. Substituting (J) into p_i = c_i(t_i):
//        (1-t)^2 (1-λ_{i-1}) c_{i-1,1}
//      + [(1-t)^2 λ_{i-1} + 2t(1-t) + t^2 (1-λ_i)] c_{i,1}
//      + t^2 λ_i c_{i+1,1} = p_i          (t = t_i),
//    a tridiagonal system (cyclic when closed), solved with partial pivoting
//    (Sherman-Morrison for the corners); its residual is checked.
// Iteration (as Yan et al.): start from c_{i,1} = p_i, λ_i = 1/2; repeat
// steps 2, (J), 1, 3. Written as a fixed point x = G(x) of the middle points
// and λ, the plain iteration converges slowly or cycles where the polygon
// turns sharply, so after a few plain steps each iteration tries a Newton
// step on F(x) = G(x) - x (forward-difference Jacobian, dense, up to 64
// points; a backtracking line search on |F|) and falls back to the damped
// plain step (relaxation halved when the residual grows, doubled when it
// falls) where Newton does not lower |F|, retrying Newton a few iterations
// later. A point whose t_i is within 1e-2 of an end is pinned there for the
// Newton step: step 1's t_i has a kink where the point reaches a joint, where
// Newton would stall. Two residuals: the κ-curve proper (each point at its
// quadratic's Eq. 7 maximum) is sought first, for 300 iterations, with pins
// that prove wrong (Eq. 7's maximum not at the pinned end) released for good;
// if it does not converge, the published fixed point is sought, where a
// point may sit on a joint while its quadratic peaks elsewhere (step 1's
// cubic then has its root at that end whatever the quadratic does).
// Polish. Such a fixed point is then polished on the κ-curve equations as
// one smooth system: unknowns c_{i,1}, the free λ_i and t_i; equations
// c_i(t_i) = p_i, λ_i = step 2's λ, and the vertex condition
// c_i'(t_i)·c_i'' = 0 (Eq. 7 at t_i). It has no kink at the joints, so
// Newton (line search) and Levenberg-Marquardt steps reach the κ-curve
// proper where step 1's kink stalled the fixed point; a solution counts only
// with every t_i in [0, 1] and λ_i in (0, 1). Starts: the fixed point, where
// the strict iteration stopped, and the initial state. Where that still is
// no κ-curve proper, the whole run is repeated from up to 14 other starts
// (λ from 0.1 to 0.9, c_{i,1} pushed out or in from p_i) and the best
// answer kept: a κ-curve proper, else one whose maxima of |κ| are all at
// points (KCurve::stray_maxima empty), else the first. Quadratics whose
// maximum is not at their point are listed in KCurve::off_point_maxima and
// the CLI says so, one line per point. On 400 seeded designer-like sets
// (tests/design/kcurve_designer_test.cpp prints the counts) all converge;
// 396 are κ-curves proper, 1 more has every maximum of |κ| at a point with
// a point on a joint where |κ| is smallest, and 3 have a maximum at no point.
// The residual is the larger of max_i |c_i(t_i) - p_i| / extent (t_i from
// Eq. 7, or from step 1 for the published fixed point) and
// max_i |λ_i(new) - λ_i(used)|.
// Eq. 7 (CAD&A 2024): the maximum of a quadratic (P0, P1, P2) lies at
//     t* = (P0 - P1)·(P0 - 2P1 + P2) / |P0 - 2P1 + P2|^2,
// the minimum of |c'(t)|^2 (c'/2 = (P1-P0) + t (P0 - 2P1 + P2)).
#include <atomic>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "spline/bspline.hpp"
#include "spline/vec2.hpp"

namespace cmr {

struct KCurveOptions {
  bool closed = false;        ///< one quadratic per point, the last joined back to the first
  double tolerance = 1e-10;   ///< converged when the residual (see above) is at most this; must be in (0, 1)
  int max_iterations = 10000;  ///< iterations before giving up (the result then has residual > tolerance)
  /// Other starts tried, in turn, where the first answer is no κ-curve
  /// proper (0: the published start only; at most kKCurveRestarts). Each
  /// costs up to a whole run, so an interactive caller may want fewer.
  int restarts = 14;
  /// The work budget, by the input's size: iterations × interpolated
  /// points, over every start (0: none). The default gives a curve of 100
  /// points or fewer at least its max_iterations (one start's worth), and
  /// 1,000 points 1,000 iterations in all (about 3 s on the 2-core VM); a
  /// run that spends it stops there (KCurve::budget_spent), with what it has
  /// (not converged, or the best answer before the restarts that did not run).
  long long max_point_iterations = 1'000'000;
  /// Wall-clock limit in seconds over the whole solve (0: none), checked
  /// between iterations, polish steps and restarts.
  double time_limit = 0;
  /// The caller's cancel flag (may be null; the Python module's
  /// KeyboardInterrupt), read where time_limit is: once set, the solve stops
  /// as when its budget is spent, and its result is to be dropped.
  const std::atomic<bool>* cancel = nullptr;
};

/// The number of other starts kcurve() knows (KCurveOptions::restarts).
inline constexpr int kKCurveRestarts = 14;

struct KCurve {
  std::vector<std::array<Vec2, 3>> quadratics;  ///< c_{i,0}, c_{i,1}, c_{i,2}; joints shared exactly
  std::vector<double> t_max;  ///< Eq. 7 parameter of each quadratic's curvature maximum, in [0, 1]
  bool closed = false;
  int iterations = 0;         ///< iterations run
  double residual = 0;        ///< at the last iteration (see the header comment)
  double tolerance = 0;       ///< the options' tolerance
  /// Quadratics whose curvature maximum (Eq. 7) is not at their point: the
  /// published fixed point can leave a point on a joint while its quadratic
  /// peaks elsewhere (the cubic of step 1 then has its root at that end
  /// whatever the quadratic does). Empty for a κ-curve proper.
  std::vector<int> off_point_maxima;
  /// Of off_point_maxima, the quadratics that give the curve a local
  /// maximum of |κ| at none of the points (inside the quadratic, or on a
  /// joint where |κ| rises on both sides). Where this is empty but
  /// off_point_maxima is not, every maximum of |κ| is still at a point
  /// (Yan et al.'s guarantee) and each listed point lies on a joint where
  /// |κ| has a minimum: the flattest place between its sharper neighbours.
  std::vector<int> stray_maxima;
  /// Where off_point_maxima is not empty: the parameters t_i at which the
  /// κ-curve equations (each point at its quadratic's maximum, λ from step 2)
  /// put the points when solved from this answer without holding t_i to
  /// [0, 1] (Newton / Levenberg-Marquardt on the smooth system, "Polish"
  /// above), one per quadratic; a t_i outside [0, 1] says that this nearby
  /// solution needs point i beyond its quadratic's joint. Empty where that
  /// solve found no solution (and for a κ-curve proper).
  std::vector<double> unconstrained_t;
  bool converged() const { return residual <= tolerance; }
  /// The run stopped on KCurveOptions::max_point_iterations or time_limit.
  bool budget_spent = false;
};

/// Fewest points a κ-curve accepts, open or closed (an open curve of three
/// points is one quadratic through the middle point at its curvature maximum).
inline constexpr int kKCurveMinPoints = 3;

/// The κ-curve through `points`. Throws InputError (one line) for fewer than
/// kKCurveMinPoints points, a non-finite coordinate, consecutive points closer
/// than 1e-9 of the points' extent (for closed curves the last and first count
/// as consecutive), bad options, a singular linear system, and collinear
/// points (within 1e-9 of the extent of one line) that are closed or turn
/// back along their line (the curve would double back on itself); collinear
/// points in order give the straight curve. A curve that has not converged
/// after options.max_iterations is returned with converged() false.
KCurve kcurve(std::span<const Vec2> points, const KCurveOptions& options = {});

/// Step 1 of the iteration: the unique t in [0, 1] at which a quadratic from
/// c0 to c2 through p at t has its curvature maximum (root of the cubic f).
double kcurve_parameter(Vec2 c0, Vec2 p, Vec2 c2);

/// Eq. 7: the parameter of the curvature maximum of the quadratic (P0, P1, P2),
/// clamped to [0, 1]; 1/2 for a uniformly parametrised straight quadratic
/// (P0 - 2P1 + P2 = 0, where κ is zero throughout).
double quadratic_max_curvature_parameter(const std::array<Vec2, 3>& q);

/// The κ-curve as a degree-2 spline: the quadratics as a Bézier chain in polar
/// form, knots 0,0,1,1,...,N,N (multiplicity 2 at the joints). Closed curves
/// end where they start.
BSpline kcurve_quadratic_spline(const KCurve& curve);

/// §5.2: each quadratic subdivided at its curvature maximum t_max (de
/// Casteljau) and both halves degree-elevated to cubics, as a cubic Bézier
/// chain in polar form, knots 0,0,0,1,1,1,...,M,M,M. Pieces start at c_{0,0}
/// and alternate left half, right half; a half of zero length (t_max at 0
/// or 1) is left out. Each maximum is a joint P_k with P_{k-1}, P_k, P_{k+1}
/// collinear.
BSpline kcurve_cubic_chain(const KCurve& curve);

/// The pieces of kcurve_cubic_chain(curve) that are not certified monotone.
/// Each piece is checked with the exact classifier (what `cmr analyze`
/// reports at its default depth); where rounding the split point and the
/// degree elevation to doubles leaves the maximum a hair inside a piece
/// rather than on its end, the handle at the piece's other end is scaled by
/// 1 +- 2^-48 ... 2^-20 along its own direction until the piece is
/// certified monotone (docs/kcurve.md). Empty when every piece is; the CLI
/// refuses to write a chain otherwise.
std::vector<int> kcurve_cubic_uncertified(const KCurve& curve);

/// One line per quadratic of curve.off_point_maxima, for the CLI and the
/// editor, naming the point (its index in `points`, the input of kcurve())
/// and the joint it lies on: either "points[K] is not a curvature maximum:
/// it lies on the joint of quadratics I and J, where |kappa| has a minimum;
/// every maximum of |kappa| is at a point (WHY)" or, for stray_maxima,
/// "quadratic I peaks at t = T, at none of the points, and points[K] lies on
/// the joint ..., D% of the points' extent from that peak (WHY)"; WHY names the point unconstrained_t puts farthest
/// outside its quadratic, or says that no κ-curve was found.
std::vector<std::string> kcurve_off_point_notes(const KCurve& curve, std::span<const Vec2> points);

/// For each quadratic i, the index k of its maximum P_k among the control
/// points of kcurve_cubic_chain(curve); -1 where t_max is 0 or 1 (then the
/// maximum is a quadratic joint, not a handle pair).
std::vector<int> kcurve_cubic_maxima(const KCurve& curve);

/// The quadratics of `curve` whose two joints coincide (to
/// kCoincidentRelative of the curve's extent): a zero-length piece, where
/// |κ| is undefined. Empty for a usable curve.
std::vector<int> kcurve_degenerate_pieces(const KCurve& curve);

}  // namespace cmr
