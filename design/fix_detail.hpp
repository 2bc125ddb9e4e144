#pragma once
// Internal to cmr::design: what fix() (fix.cpp) and the parts of its search
// (fix_search.cpp) share.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <set>
#include <span>
#include <vector>

#include "bezierize/classify.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "design/fix.hpp"
#include "numeric/bernstein.hpp"
#include "numeric/bounded.hpp"
#include "spline/cpu_clock.hpp"

namespace cmr::fix_detail {

struct Unit;
struct Ties;
struct LocalJudge;
struct Search;
struct Nearest;
struct NearestN;

// Defined in fix.cpp:
double norm(Vec2 v);
bool monotone_class(const SegmentClass& c);

// Defined in fix_search.cpp:
bool segment_alone_bad(const SplineAnalysis& a, int i, const FixRequirement& r);
std::vector<Joint> all_joints(const SplineAnalysis& a);
Ties build_units(const BSpline& s, const SplineAnalysis& a, const std::vector<int>& allowed, Keep keep,
                 const std::set<int>& acting);
bool local_kind(FixRequirement::Kind k);
std::vector<int> check_points(const BSpline& s, FixRequirement::Kind kind, int i);
double end_curvature(const BSpline& s, const Segment& seg, int side);
LocalJudge make_judge(const BSpline& s, const SplineAnalysis& a, const FixRequirement& r, int max_depth);
Nearest nearest(const std::function<bool(Vec2)>& pass, int dims, Vec2 dir, double size, double max_move, double tol,
                int grid, int threads, std::size_t max_seeds = 6, bool refine = false,
                const std::function<bool(Vec2)>& certify = {});
NearestN nearest_rays(const std::function<bool(const std::vector<double>&)>& pass, int dims, double size,
                      double max_move, double tol, int threads);

/// A unit of motion: every point translates by the same 2-D vector, or (slide)
/// the one point moves along `dir`.
struct Unit {
  std::vector<int> points;  // leader first
  bool slide = false;
  Vec2 dir{0.0};
  int dims() const { return slide ? 1 : 2; }
};

struct Ties {
  std::vector<int> joints;            // joint indices (N: a closed spline's seam) kept
  std::vector<Unit> units;
  std::vector<bool> moves;            // per unique point: some unit moves it
  /// Each handle of a G1 tie: (handle, node, unit direction from the node to
  /// the handle). A handle that reaches or passes its node would turn the
  /// tangent round: G1 broken (Search::flips).
  struct Handle {
    int handle, node;
    Vec2 dir;
  };
  std::vector<Handle> handles;
};

/// Whether check i fails on a spline (exact or certified, as the final
/// analysis decides it).
struct LocalJudge {
  FixRequirement requirement;
  int max_depth = kDefaultDepth;
  int sign = 0;                    ///< no-inflection: the curvature sign every segment must keep (the input's majority)
  std::vector<char> judged_joint;  ///< g2: the joint starting segment i is judged (smooth in the input)

  bool bad(const BSpline& s, int i) const {
    const Segment& seg = s.segments()[i];
    switch (requirement.kind) {
      case FixRequirement::Kind::no_inflection: {
        if (!s.is_rational()) {
          // Most positions: eta's Bernstein coefficients certainly of one
          // sign (error-bounded doubles) mean no inflection and no cusp
          // (eta != 0 needs P' != 0), kappa of that sign throughout.
          Bernstein<Bounded> eta = eta_bernstein<Bounded>(segment_bezier_points<Bounded>(s, seg));
          const int e = strict_sign(eta);
          if (e != 0) return sign != 0 && e != sign;
          // Certainly bad: eta certainly against the sign at an end or at
          // the middle (de Casteljau in error-bounded doubles), or certainly
          // of opposite signs at the two ends.
          if (!eta.empty()) {
            const int e0 = certain_sign(eta.front()), e1 = certain_sign(eta.back());
            if (e0 * e1 < 0 || (sign != 0 && (e0 == -sign || e1 == -sign))) return true;
            for (std::size_t r = eta.size(); r-- > 1;)
              for (std::size_t k = 0; k < r; ++k) eta[k] = (eta[k] + eta[k + 1]).half();
            if (sign != 0 && certain_sign(eta.front()) == -sign) return true;
          }
        }
        const SegmentShape sh = segment_shape(s, seg);
        if (sh.pole || sh.cusp || sh.inflection != Inflection::none) return true;
        return !sh.straight && sh.kappa_sign != 0 && sign != 0 && sh.kappa_sign != sign;
      }
      case FixRequirement::Kind::g2: {
        if (!judged_joint[i]) return false;
        const int N = s.segment_count();
        const Segment& left = s.segments()[(i - 1 + N) % N];
        // The end curvatures from the Bezier points in doubles, judged with a
        // margin of 2% of the tolerance (the certificate's analyze decides
        // with the certified curvatures, kKappaRelError); a rational or
        // degenerate end: the certified values.
        double kl = end_curvature(s, left, 1), kr = end_curvature(s, seg, 0), tol = 0.98 * requirement.g2_tolerance;
        if (!std::isfinite(kl) || !std::isfinite(kr)) {
          kl = certified_end_curvature(s, left, 1), kr = certified_end_curvature(s, seg, 0);
          tol = requirement.g2_tolerance;
        }
        if (!std::isfinite(kl) || !std::isfinite(kr)) return true;
        return std::abs(kl - kr) > tol * std::max(std::abs(kl), std::abs(kr));
      }
      default: {
        // A Bezier window (every piece of a font contour): its control points
        // are its Bezier points exactly, and classify_bezier decides them
        // (a-priori bounded doubles, then error-bounded, then exact) without
        // blossoming them in error-bounded arithmetic first. Both certify
        // Algorithm 1's exact verdict, so the answer is the same.
        if (!s.is_rational() && bezier_window(s, seg)) {
          const std::size_t first = static_cast<std::size_t>(seg.span - s.degree() + 1);
          const std::span<const Vec2> points(s.points().data() + first, static_cast<std::size_t>(s.degree()) + 1);
          return !monotone_class(classify_bezier(points, {max_depth, false}));
        }
        return !segment_poles(s, seg).empty() || !monotone_class(classify_segment(s, seg, {max_depth, false}));
      }
    }
  }
};

using Clock = std::chrono::steady_clock;

/// A state of the search: one displacement per unique point.
struct Search {
  const BSpline& base;
  const FixRequest& request;
  const SplineAnalysis& base_analysis;
  double size = 1, tol = 0, max_move = 0;
  std::atomic<long> evaluations{0};

  LocalJudge judge;
  std::vector<char> base_bad;  ///< local kinds: check i fails on the input
  std::vector<Ties::Handle> handles;  ///< of the G1 ties (set by fix())

  /// Some tied handle reaches or passes its node (a slide of the handle, or
  /// of the node's group against it): the tangent would turn round.
  bool flips(const std::vector<Vec2>& delta) const {
    for (const Ties::Handle& h : handles) {
      const Vec2 off = base.points()[h.handle] + delta[h.handle] - base.points()[h.node] - delta[h.node];
      if (!(dot(off, h.dir) > 0)) return true;
    }
    return false;
  }

  Search(const BSpline& b, const FixRequest& r, const SplineAnalysis& a)
      : base(b), request(r), base_analysis(a), judge(make_judge(b, a, r.requirement, r.max_depth)) {
    if (!local_kind(r.requirement.kind)) return;
    base_bad.assign(b.segment_count(), 0);
    for (int i = a.range.first; i <= a.range.last; ++i) base_bad[i] = judge.bad(b, i);
  }

  BSpline moved(const std::vector<Vec2>& delta) const {
    // One copy of the spline per moved point (with_point), none more.
    std::optional<BSpline> s;
    for (std::size_t k = 0; k < delta.size(); ++k)
      if (delta[k] != Vec2(0.0)) s = (s ? *s : base).with_point(static_cast<int>(k), base.points()[k] + delta[k]);
    return s ? std::move(*s) : base;
  }

  /// The requirement on a moved spline: extrema-at-nodes re-classifies only
  /// the segments a moved point acts on; the others analyze the whole spline.
  bool holds(const std::vector<Vec2>& delta) {
    if (!count_evaluation()) return false;
    for (const Vec2& d : delta)
      if (norm(d) > max_move) return false;
    if (flips(delta)) return false;
    if (request.judge) return request.judge(moved(delta)) == 0;
    if (local_kind(request.requirement.kind)) return bad_segments(delta, true) == 0;
    return requirement_holds(moved(delta), request.requirement, request.max_depth);
  }

  /// extrema-at-nodes: how many judged segments are not certified monotone
  /// after the move (only the segments a moved point acts on are classified
  /// again); with `first`, stops at the first.
  int bad_segments(const std::vector<Vec2>& delta, bool first) {
    const BSpline s = moved(delta);
    int bad = 0;
    for (int i = base_analysis.range.first; i <= base_analysis.range.last && !(first && bad); ++i) {
      bool touched = false;
      for (int k : check_points(s, request.requirement.kind, i)) touched = touched || delta[k] != Vec2(0.0);
      bad += touched ? judge.bad(s, i) : base_bad[i];
    }
    return bad;
  }

  /// extrema-at-nodes: how many of the judged segments `segments` are not
  /// certified monotone after the move (each classified again).
  int bad_in(const std::vector<Vec2>& delta, const std::vector<int>& segments) {
    if (flips(delta)) return std::numeric_limits<int>::max() / 2;
    const BSpline s = moved(delta);
    int bad = 0;
    for (int i : segments) bad += judge.bad(s, i);
    return bad;
  }

  /// One evaluation, counted unless the search's time was already up (then
  /// the predicate answers "fails" at once, which is no work: so
  /// FixResult::evaluations, which the glyph fix charges as its work, counts
  /// the evaluations made); false where the time is up (expired).
  bool count_evaluation() {
    if (timed_out) return false;
    ++evaluations;
    return !expired();
  }

  /// The search's time is up (FixRequest::max_seconds or ::max_evaluations,
  /// or the caller's cancel flag): every predicate answers "fails" from now
  /// on, so every loop ends.
  bool expired() {
    if (!timed_out && request.max_evaluations > 0 && evaluations >= request.max_evaluations) timed_out = true;
    if (!timed_out && request.max_seconds > 0 &&
        (request.thread_cpu_clock ? cpu_deadline.passed() : Clock::now() > deadline))
      timed_out = true;
    if (!timed_out && request.cancel != nullptr && request.cancel->load(std::memory_order_relaxed)) timed_out = true;
    return timed_out;
  }
  Clock::time_point deadline;
  ThreadCpuDeadline cpu_deadline;  // FixRequest::thread_cpu_clock (threads 1: this thread's only)
  std::atomic<bool> timed_out{false};

  /// How far a moved spline is from the requirement (0: it holds): 4 per
  /// segment that fails alone, 1 per segment against the majority direction
  /// (of its part, with a split) and per joint whose jump goes against the
  /// verdict; at least 1 while the requirement fails. Each greedy step must
  /// lower it.
  int badness(const std::vector<Vec2>& delta) {
    if (!count_evaluation()) return std::numeric_limits<int>::max();
    for (const Vec2& d : delta)
      if (norm(d) > max_move) return std::numeric_limits<int>::max();
    if (flips(delta)) return std::numeric_limits<int>::max();
    if (request.judge) return request.judge(moved(delta));
    if (local_kind(request.requirement.kind)) return bad_segments(delta, false);
    const SplineAnalysis a = analyze(moved(delta), fix_analyze_options(request.requirement, request.max_depth));
    if (requirement_holds(a, request.requirement)) return 0;
    int score = 0;
    for (int i = a.range.first; i <= a.range.last; ++i) score += 4 * segment_alone_bad(a, i, request.requirement);
    if (request.requirement.kind != FixRequirement::Kind::extrema_at_nodes) {
      const bool split = request.requirement.kind == FixRequirement::Kind::split;
      std::vector<std::pair<int, int>> parts;
      if (split)
        parts = {{a.range.first, request.requirement.split}, {request.requirement.split, a.range.last + 1}};
      else
        parts = {{a.range.first, a.range.last + 1}};
      for (const auto& [first, end] : parts) {
        int inc = 0, dec = 0;
        for (int i = first; i < end; ++i) {
          inc += a.segments[i].monotonicity.curvature == Curvature::increasing;
          dec += a.segments[i].monotonicity.curvature == Curvature::decreasing;
        }
        score += std::min(inc, dec);
      }
      score += static_cast<int>(a.joint_conflicts.size());
    }
    return std::max(score, 1);
  }
};

/// The passing position nearest to 0 of pass(x), x = t * dir (dims 1) or x in
/// the plane (dims 2): see the header comment, step 1.
struct Nearest {
  bool found = false;
  Vec2 x{0.0};
  double dist = std::numeric_limits<double>::infinity();
};

/// The passing position nearest to 0 of pass(c) for c in R^dims (dims 3 or 4:
/// several units moved at once): rays from 0 in fixed directions (the axes,
/// the diagonals and seeded random ones), each scanned outwards by factors
/// of 1.5 from size/512 to max_move; the first passing radius of each ray is
/// bisected to `tol` against the radius before it. Coarse: the compass search
/// that follows polishes the total squared displacement.
struct NearestN {
  bool found = false;
  std::vector<double> c;
  double dist = std::numeric_limits<double>::infinity();
};

}  // namespace cmr::fix_detail
