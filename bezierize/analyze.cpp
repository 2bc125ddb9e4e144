#include "bezierize/analyze.hpp"

#include "bezierize/decide.hpp"
#include "bezierize/exact.hpp"
#include "bezierize/extract.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"

namespace cmr {

const char* to_string(Direction d) {
  switch (d) {
    case Direction::increasing: return "increasing";
    case Direction::decreasing: return "decreasing";
    case Direction::none: return "none";
    case Direction::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(Split s) {
  switch (s) {
    case Split::inc_inc: return "inc-inc";
    case Split::inc_dec: return "inc-dec";
    case Split::dec_inc: return "dec-inc";
    case Split::dec_dec: return "dec-dec";
    case Split::none: return "none";
    case Split::undecided: return "undecided";
  }
  return "?";
}

namespace {

// Numerator and squared first-leg length of the curvature at one end of a
// segment, exactly: kappa = (d-1)/d * A / G^{3/2} (the factor is common to all
// segments and dropped).
struct EndCurvature {
  Rational A, G;
};

EndCurvature end_curvature_exact(const BSpline& spline, const Segment& s, int side) {
  const int d = spline.degree();
  const int first = s.span - d + 1;
  const std::vector<Rational> knots(spline.knots().begin() + first, spline.knots().begin() + s.span + d + 1);
  const std::vector<HPoint<Rational>> H = homogeneous_window_points<Rational>(spline, s);
  const Rational e = side == 0 ? Rational(s.a) : Rational(s.b);
  const Rational o = side == 0 ? Rational(s.b) : Rational(s.a);
  std::vector<Rational> args(d, e);
  Point<Rational> q[3];
  Rational w[3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < d; ++i) args[i] = i < d - k ? e : o;
    const HPoint<Rational> h = blossom_span(knots, H, d, d - 1, args.data());
    q[k] = {h.x / h.z, h.y / h.z};
    w[k] = h.z;
  }
  const Point<Rational> a = q[1] - q[0], b = q[2] - q[1];
  // A rational Bezier end's curvature has the extra factor w0 w2 / w1^2 > 0
  // (1 for a polynomial curve).
  Rational A = w[0] * w[2] / (w[1] * w[1]) * det(a, b);
  if (side == 1) A = -A;  // read backwards from the end: turning sense flips
  return {A, dot(a, a)};
}

}  // namespace

int curvature_jump_sign(const BSpline& spline, const Segment& left, const Segment& right) {
  const EndCurvature L = end_curvature_exact(spline, left, 1);
  const EndCurvature R = end_curvature_exact(spline, right, 0);
  return jump_sign<Rational>(L.A, L.G, R.A, R.G);
}

Direction part_verdict(const std::vector<SegmentClass>& segments, const std::vector<Joint>& joints, int first,
                       int last, Mode mode, std::vector<int>* conflicts) {
  bool inc = false, dec = false, undecided = false, none = false;
  int kappa_sign = 0;
  for (int i = first; i < last; ++i) {
    const SegmentClass& c = segments[i];
    switch (c.monotonicity.curvature) {
      case Curvature::increasing: inc = true; break;
      case Curvature::decreasing: dec = true; break;
      case Curvature::non_monotone: none = true; break;
      case Curvature::undecided: undecided = true; break;
      case Curvature::constant: break;
    }
    if (mode == Mode::cmr) {
      switch (c.inflection.inflection) {
        case Inflection::present: none = true; break;
        case Inflection::undecided: undecided = true; break;
        case Inflection::none:
          if (kappa_sign != 0 && c.inflection.kappa_sign != kappa_sign) none = true;  // inflection at a joint
          kappa_sign = c.inflection.kappa_sign;
          break;
      }
    }
  }
  if (none || (inc && dec)) return Direction::none;
  // Jumps at non-C^2 joints inside the part must follow the direction.
  bool jump_up = false, jump_down = false;
  for (int i = first + 1; i < last; ++i) {
    const Joint& j = joints[i - 1];
    jump_up = jump_up || j.jump > 0;
    jump_down = jump_down || j.jump < 0;
    if ((j.jump > 0 && dec) || (j.jump < 0 && inc)) {
      if (conflicts) conflicts->push_back(j.index);
      none = true;
    }
  }
  if (none || (jump_up && jump_down)) return Direction::none;
  if (undecided) return Direction::undecided;
  if (dec || jump_down) return Direction::decreasing;
  return Direction::increasing;  // inc, or all constant (Algorithm 1 checks (1) first)
}

Split combine_split(Direction before, Direction after) {
  if (before == Direction::none || after == Direction::none) return Split::none;
  if (before == Direction::undecided || after == Direction::undecided) return Split::undecided;
  const bool a = before == Direction::increasing, b = after == Direction::increasing;
  return a ? (b ? Split::inc_inc : Split::inc_dec) : (b ? Split::dec_inc : Split::dec_dec);
}

SplineAnalysis analyze(const BSpline& spline, const AnalyzeOptions& options) {
  const int N = spline.segment_count();
  if (options.split && (*options.split < 1 || *options.split > N - 1))
    throw InputError(N == 1 ? "split " + std::to_string(*options.split) + ": the curve has one segment, so no joint to split at"
                            : "split " + std::to_string(*options.split) + " is outside 1.." + std::to_string(N - 1));
  if (options.classify.max_depth < 0 || options.classify.max_depth > kMaxDepth)
    throw InputError("depth " + std::to_string(options.classify.max_depth) + " is outside 0.." +
                     std::to_string(kMaxDepth));
  SplineAnalysis out;
  ClassifyOptions co = options.classify;
  co.inflection = true;  // CMR verdicts always need Algorithm 2
  for (const Segment& s : spline.segments()) {
    out.segments.push_back(classify_segment(spline, s, co));
    out.exact_segments += out.segments.back().exact_used ? 1 : 0;
  }
  const int d = spline.degree();
  for (int i = 1; i < N; ++i) {
    const Segment& L = spline.segments()[i - 1];
    const Segment& R = spline.segments()[i];
    Joint j;
    j.index = i;
    j.knot = R.a;
    j.multiplicity = spline.multiplicity(R.a);
    j.continuity = d - j.multiplicity;
    j.kappa_left = segment_end_curvature(spline, L, 1);
    j.kappa_right = segment_end_curvature(spline, R, 0);
    j.jump = j.continuity >= 2 ? 0 : curvature_jump_sign(spline, L, R);
    out.joints.push_back(j);
  }
  out.cmrwi = part_verdict(out.segments, out.joints, 0, N, Mode::cmrwi, &out.joint_conflicts);
  out.cmr = part_verdict(out.segments, out.joints, 0, N, Mode::cmr);
  if (options.split) {
    const int s = *options.split;
    out.split = combine_split(part_verdict(out.segments, out.joints, 0, s, options.split_mode),
                              part_verdict(out.segments, out.joints, s, N, options.split_mode));
  }
  return out;
}

}  // namespace cmr
