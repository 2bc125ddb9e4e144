#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
/// The one decision core of Algorithms 1 and 2 (Yoshida et al., CAD&A 21(1)
/// 2024, §3): the piece rules as functions of a sign summary, and the one
/// depth-first traversal over a coefficient source. Every C++ path (the
/// generic exact/Bounded/double path and the allocation-free fast path in
/// classify.cpp, the region pixel and region block paths in region/region.cpp and region/block.cpp)
/// decides pieces here; the shader (shaders/piece_rules.glsl) mirrors these
/// rules line by line, and tests/vk/piece_rules_test.cpp compares the two on
/// a table of coefficient vectors.
///
/// Certain signs. A coefficient's sign is +1, -1, 0 or kSignUnknown. Exact
/// arithmetic always knows it; with an error bound e a value v has a certain
/// sign when |v| > e, and it is certainly 0 only when v == 0 and e == 0 (in
/// the region paths: a structural zero, the same for every position).
///
/// Algorithm 1 on xi_0..xi_n (one piece):
///   (3) xi_0 xi_n < 0       -> non_monotone   (checked first: it stops the segment)
///   (1) and (2) all xi = 0  -> zero           (lambda == 0: a straight segment)
///   (1) all xi >= 0         -> increasing
///   (2) all xi <= 0         -> decreasing
///   otherwise               -> split
/// Algorithm 2 on nu_0..nu_n:
///   (1) nu_0 nu_n <= 0      -> inflection
///   (2) all nu > 0 or < 0   -> no_inflection
///   otherwise               -> split
/// With uncertain signs a condition is yes, no or unknown; a rule fires when
/// its condition is certainly true and every earlier one certainly false, and
/// the answer is `uncertain` (go to exact arithmetic) when the first
/// condition that is not certainly false is unknown. In particular a product
/// with a factor that is certainly 0 is certainly 0 whatever the other
/// factor: "xi_0 xi_n < 0" is then certainly false, and "nu_0 nu_n <= 0"
/// certainly true (an inflection), even when the other end is uncertain.
/// Every path, the shader included, follows this one rule.
///
/// Summaries. A scanner reads the two ends, then the inner coefficients, and
/// may stop once both a certainly positive and a certainly negative
/// coefficient were seen (no outcome of either table then depends on the
/// rest; the lazy region paths save evaluations that way). The block rules
/// below may also stop at the first unknown sign.
#include <cstdint>
#include <vector>

#include "numeric/bernstein.hpp"
#include "bezierize/piece.hpp"
#include "numeric/bounded.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "spline/vec2.hpp"

namespace cmr {


/// Three-valued truth of a condition on coefficients whose signs may be unknown.
enum class Truth : std::uint8_t { no, yes, unknown };

/// The signs of one piece's coefficients, as far as a scanner read them.
struct SignSummary {
  int n1 = 0;               ///< number of coefficients (degree + 1)
  int first = 0, last = 0;  ///< signs of c_0 and c_n (kSignUnknown if not certain)
  int pos = 0, neg = 0, zero = 0, unknown = 0;  ///< counts among the coefficients read
  void add(int g) {
    if (g == kSignUnknown) ++unknown;
    else if (g > 0) ++pos;
    else if (g < 0) ++neg;
    else ++zero;
  }
};

/// c_0 c_n < 0 (Algorithm 1, rule 3).
constexpr Truth ends_opposite(int first, int last) {
  if (first == 0 || last == 0) return Truth::no;  // a certain zero factor: the product is 0
  if (first == kSignUnknown || last == kSignUnknown) return Truth::unknown;
  return first != last ? Truth::yes : Truth::no;
}

/// c_0 c_n <= 0 (Algorithm 2, rule 1).
constexpr Truth ends_touch(int first, int last) {
  if (first == 0 || last == 0) return Truth::yes;  // a certain zero factor: the product is 0
  if (first == kSignUnknown || last == kSignUnknown) return Truth::unknown;
  return first != last ? Truth::yes : Truth::no;
}

/// Algorithm 1's rules on one piece (see the table above).
constexpr Piece monotonicity_piece(const SignSummary& s) {
  const Truth ends = ends_opposite(s.first, s.last);
  if (ends == Truth::yes) return Piece::non_monotone;
  const bool ge = s.neg == 0 && s.unknown == 0, le = s.pos == 0 && s.unknown == 0;
  if (ge && le) return Piece::zero;
  if (ge) return Piece::increasing;
  if (le) return Piece::decreasing;
  // Rules (1) and (2) are certainly false only when both signs were seen.
  if (s.pos > 0 && s.neg > 0 && ends == Truth::no) return Piece::split;
  return Piece::uncertain;
}

/// Algorithm 2's rules on one piece.
constexpr Piece inflection_piece(const SignSummary& s) {
  const Truth ends = ends_touch(s.first, s.last);
  if (ends == Truth::yes) return Piece::inflection;
  if (ends == Truth::unknown) return Piece::uncertain;
  if (s.pos == s.n1 || s.neg == s.n1) return Piece::no_inflection;
  // Rule (2) is certainly false when some coefficient is certainly <= 0 and
  // some certainly >= 0 (the ends are certainly non-zero and alike here).
  if (s.neg + s.zero > 0 && s.pos + s.zero > 0) return Piece::split;
  return Piece::uncertain;
}

/// The rules of the region block proof (region/block.cpp, classify_box_labels),
/// where a piece's signs must hold for every position of a block of pixels.
/// They differ from Algorithms 1 and 2 by design: the block search does not
/// reproduce each pixel's traversal (levels may differ between pixels), it
/// proves the pixels' common answer. A piece is a leaf `increasing`
/// (`decreasing`) when every coefficient is certainly >= 0 (<= 0), for
/// eta strictly > 0 (< 0): the sub-pieces of a piece monotone for a pixel are
/// monotone the same way, so every pixel's Algorithm 1 gives that direction
/// or "not monotone". Certain end rules prove non_monotone (for eta:
/// inflection) for every pixel, as in the tables above. An identically zero
/// piece is left to the pixels (`uncertain`); anything else is split, even
/// where some pixels would decide it. Scanners may stop at the first unknown.
constexpr Piece block_piece(const SignSummary& s, bool eta) {
  if (eta ? ends_touch(s.first, s.last) == Truth::yes : ends_opposite(s.first, s.last) == Truth::yes)
    return eta ? Piece::inflection : Piece::non_monotone;
  if (s.zero == s.n1) return Piece::uncertain;
  const bool up = s.unknown == 0 && s.neg == 0 && (!eta || s.zero == 0);
  const bool down = s.unknown == 0 && s.pos == 0 && (!eta || s.zero == 0);
  if (up) return Piece::increasing;
  if (down) return Piece::decreasing;
  return Piece::split;
}

/// Reads the current piece of `src` into a summary: both ends, then the
/// inner coefficients until both signs appeared (or, with stop_at_unknown,
/// an unknown one).
template <class Source>
SignSummary scan_signs(Source& src, bool stop_at_unknown = false) {
  SignSummary s;
  s.n1 = src.size();
  s.first = src.sign(0);
  s.add(s.first);
  s.last = s.first;
  if (s.n1 > 1) {
    s.last = src.sign(s.n1 - 1);
    s.add(s.last);
  }
  for (int k = 1; k + 1 < s.n1 && !(s.pos > 0 && s.neg > 0) && !(stop_at_unknown && s.unknown > 0); ++k)
    s.add(src.sign(k));
  return s;
}

/// The one depth-first traversal of Algorithms 1 and 2. Level 0 is the whole
/// segment; a piece the rule splits below max_depth is replaced by its two
/// halves at t = 1/2, left first (pieces are visited in parameter order).
/// Every other outcome goes to visit(piece, level), which folds it and
/// returns true to stop; `split` reaching visit means "split at level D".
///
/// Source concept (the current piece is (0, 0) at construction):
///   int size()                   coefficients per piece
///   int sign(int k)              certain sign of coefficient k of the current piece
///   void split(int level, int j) the current piece becomes its left half,
///                                piece (level, j); the right half is pending
///   void next(int level, int j)  the current piece becomes piece (level, j),
///                                the most recently pending one
/// rule(const SignSummary&) -> Piece is one of the tables above.
/// Returns false when a piece was uncertain.
template <class Source, class Decide, class Visit, class Done>
bool traverse_nodes(Source& src, int max_depth, Decide decide, Visit visit, Done done);

template <class Source, class Rule, class Visit>
bool traverse(Source& src, int max_depth, Rule rule, Visit visit, bool stop_at_unknown = false) {
  return traverse_nodes(
      src, max_depth, [&](int, int) { return rule(scan_signs(src, stop_at_unknown)); }, visit, [](int) {});
}

/// The one traversal itself, with the decision of each node (level, j) left
/// to decide(level, j) (traverse: the rule on the current piece's signs; a
/// block's reuse, region/box_reuse.hpp: a recorded fact where there is
/// one) and done(level) called for each node whose subtree it has finished.
template <class Source, class Decide, class Visit, class Done>
bool traverse_nodes(Source& src, int max_depth, Decide decide, Visit visit, Done done) {
  int level = 0, j = 0;
  for (;;) {
    const Piece p = decide(level, j);
    if (p == Piece::uncertain) return false;
    if (p == Piece::split && level < max_depth) {
      ++level;
      j *= 2;
      src.split(level, j);
      continue;
    }
    if (visit(p, level)) return true;
    done(level);
    // Climb while on a right child, then go to the right sibling.
    while (level > 0 && (j & 1) == 1) {
      --level;
      j >>= 1;
      done(level);
    }
    if (level == 0) return true;
    ++j;
    src.next(level, j);
  }
}

/// A Bernstein polynomial in memory as a source: halves are computed with
/// bernstein_halve and pending right halves kept on a stack.
template <class T>
class BernsteinSource {
 public:
  BernsteinSource(const Bernstein<T>& c, int max_depth)
      : n1_(static_cast<int>(c.size())), cur_(c), work_(c.size()),
        pending_(static_cast<std::size_t>(max_depth + 1) * c.size()) {}
  int size() const { return n1_; }
  int sign(int k) const { return Scalar<T>::sign(cur_[k]); }
  void split(int, int) {
    bernstein_halve(cur_.data(), n1_, cur_.data(), slot(sp_++), work_.data());
  }
  void next(int, int) {
    const T* p = slot(--sp_);
    std::copy(p, p + n1_, cur_.begin());
  }

 private:
  T* slot(int i) { return pending_.data() + static_cast<std::size_t>(i) * n1_; }
  int n1_;
  std::vector<T> cur_, work_, pending_;
  int sp_ = 0;
};

/// Sign of kappa_right - kappa_left at a joint, from the numerator A and the
/// squared first-leg length G of each side's end curvature,
/// kappa = c A / G^{3/2} with the same c > 0 on both sides (for Bezier points:
/// A = det(a, b), G = a.a with a, b the first two legs read from the joint;
/// the left side's A changes sign, being read backwards).
///   sign(A_R / G_R^{3/2} - A_L / G_L^{3/2}) = sign(X - Y),
///   X = A_R G_L^{3/2}, Y = A_L G_R^{3/2}: when A_R and A_L differ in sign
///   the larger sign wins; otherwise compare X^2 = A_R^2 G_L^3 with
///   Y^2 = A_L^2 G_R^3 and flip for negative A.
/// 0 when a leg is degenerate (G = 0: curvature undefined) or both are
/// straight; kSignUnknown when T carries bounds and a sign is not certain.
template <class T>
int jump_sign(const T& AL, const T& GL, const T& AR, const T& GR) {
  const int gl = Scalar<T>::sign(GL), gr = Scalar<T>::sign(GR);
  if (gl == kSignUnknown || gr == kSignUnknown) return kSignUnknown;
  if (gl == 0 || gr == 0) return 0;
  const int sx = Scalar<T>::sign(AR), sy = Scalar<T>::sign(AL);
  if (sx == kSignUnknown || sy == kSignUnknown) return kSignUnknown;
  if (sx != sy) return sx > sy ? 1 : -1;
  if (sx == 0) return 0;
  const int c = Scalar<T>::sign(AR * AR * GL * GL * GL - AL * AL * GR * GR * GR);
  if (c == kSignUnknown) return kSignUnknown;
  return sx > 0 ? c : -c;
}

/// The terms of a segment end's curvature kappa = (d-1)/d A / G^{3/2} (d the
/// degree; the span length cancels), from the first three Bezier points read
/// from that end inwards, and the end tangent's direction `a` (read inwards).
/// Exact for exact T; no division, so any T and any weights are safe.
///  * Polynomial, points q0 (the end), q1, q2: a = q1 - q0, b = q2 - q1,
///    A = det(a, b), G = a.a.
///  * Rational, homogeneous points H_k = (X_k, w_k) (X_k = w_k q_k), any
///    signs of w: with kappa = W^3 D / |h|^3 (rational_lambda.hpp) at t = 0,
///    h(0) = n (w0 X1 - w1 X0) and D(0) = n^2 (n-1) det3(H0, H1, H2), so
///    a = g = w0 X1 - w1 X0, A = w0^3 det3(H0, H1, H2), G = g.g. With
///    w0, w1, w2 certainly > 0 this is g = w0 w1 (q1 - q0) and A / G^{3/2} =
///    (w0 w2 / w1^2) det(a, b) / |a|^3 with a = q1 - q0, b = q2 - q1, the
///    classical formula: that case computes it (A = (w0 w2 / w1^2) det(a, b),
///    G = a.a, a = q1 - q0), so positive weights keep their values bit for
///    bit; other weights take the division-free form. At a pole (w0 = 0)
///    the curvature is undefined: callers exclude poles (analyze.hpp:
///    segment_poles).
/// Read backwards (the end of a segment), the turning sense flips: the caller
/// negates A.
template <class T>
struct EndTerms {
  T A, G;
  Point<T> a;
};
template <class T>
EndTerms<T> end_terms(const Point<T>& q0, const Point<T>& q1, const Point<T>& q2) {
  const Point<T> a = q1 - q0, b = q2 - q1;
  return {det(a, b), dot(a, a), a};
}
template <class T>
EndTerms<T> end_terms(const HPoint<T>& h0, const HPoint<T>& h1, const HPoint<T>& h2) {
  if (Scalar<T>::sign(h0.z) == 1 && Scalar<T>::sign(h1.z) == 1 && Scalar<T>::sign(h2.z) == 1) {
    const auto proj = [](const HPoint<T>& h) { return Point<T>{h.x / h.z, h.y / h.z}; };
    EndTerms<T> e = end_terms<T>(proj(h0), proj(h1), proj(h2));
    e.A = h0.z * h2.z / (h1.z * h1.z) * e.A;
    return e;
  }
  const Point<T> x0{h0.x, h0.y}, x1{h1.x, h1.y}, x2{h2.x, h2.y};
  const Point<T> g = h0.z * x1 - h1.z * x0;
  // det3 of the rows (X_k, w_k), expanded along the weight column.
  const T d3 = h0.z * det(x1, x2) - h1.z * det(x0, x2) + h2.z * det(x0, x1);
  return {h0.z * h0.z * h0.z * d3, dot(g, g), g};
}

/// jump_sign at the joint between two Bezier segments of degree >= 2 (L ends
/// where R starts), from their end legs (end_terms).
template <class T>
int jump_sign(const std::vector<Point<T>>& L, const std::vector<Point<T>>& R) {
  const int d = static_cast<int>(L.size()) - 1;
  CMR_CHECK(d >= 2 && R.size() == L.size());
  const EndTerms<T> l = end_terms<T>(L[d], L[d - 1], L[d - 2]), r = end_terms<T>(R[0], R[1], R[2]);
  return jump_sign<T>(T(0) - l.A, l.G, r.A, r.G);
}

/// jump_sign at the joint between two rational Bezier segments given by
/// homogeneous points (W x, W y, W), W != 0 at the joint (no pole there):
/// end_terms of the homogeneous points, any signs of the weights.
template <class T>
int jump_sign_homogeneous(const std::vector<HPoint<T>>& L, const std::vector<HPoint<T>>& R) {
  const int d = static_cast<int>(L.size()) - 1;
  CMR_CHECK(d >= 2 && R.size() == L.size());
  const EndTerms<T> l = end_terms<T>(L[d], L[d - 1], L[d - 2]), r = end_terms<T>(R[0], R[1], R[2]);
  return jump_sign<T>(T(0) - l.A, l.G, r.A, r.G);
}

}  // namespace cmr
