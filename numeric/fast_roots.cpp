#include "numeric/fast_roots.hpp"

#include <tuple>

#include "numeric/root_signs.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace cmr {

namespace {
std::atomic<bool> g_fast_paths{true};
}  // namespace

bool fast_paths_enabled() { return g_fast_paths.load(std::memory_order_relaxed); }
void set_fast_paths_enabled(bool on) { g_fast_paths.store(on, std::memory_order_relaxed); }

namespace {

// The constants of isolate_roots (roots.cpp): halving deeper than this gives
// the polynomial to the square-free split, which this path does not do.
constexpr int kIsolationDepth = 48;

struct Found {
  std::uint64_t k = 0;
  int level = 0;
  bool exact = false;
  int sign_lo = 0;
  int multiplicity = 1;
  double lower() const { return std::ldexp(static_cast<double>(k), -level); }
  double upper() const { return exact ? lower() : std::ldexp(static_cast<double>(k + 1), -level); }
};

// p(t) by de Casteljau in Bounded arithmetic (t exact).
Bounded eval(const Bounded* c, std::size_t n1, double t) {
  Bounded local[64];
  std::vector<Bounded> heap;
  Bounded* w = local;
  if (n1 > 64) {
    heap.assign(c, c + n1);
    w = heap.data();
  } else {
    std::copy(c, c + n1, local);
  }
  const Bounded bt(t), s = Bounded(1.0) - bt;
  for (std::size_t r = 1; r < n1; ++r)
    for (std::size_t i = 0; i + r < n1; ++i) w[i] = s * w[i] + bt * w[i + 1];
  return w[0];
}

// Sign variations with zero coefficients skipped (Descartes); -1 when a sign
// is uncertain.
int variations(const Bounded* c, std::size_t n1, int* first_nonzero) {
  int v = 0, last = 0;
  *first_nonzero = 0;
  for (std::size_t i = 0; i < n1; ++i) {
    const int s = certain_sign(c[i]);
    if (s == kSignUnknown) return -1;
    if (s == 0) continue;
    if (*first_nonzero == 0) *first_nonzero = s;
    if (last != 0 && s != last) ++v;
    last = s;
  }
  return v;
}

bool isolate(const Bernstein<Bounded>& q, std::vector<Found>& out) {
  const std::size_t n1 = q.size();
  const int s0 = certain_sign(q.front()), sn = certain_sign(q.back());
  if (s0 == kSignUnknown || sn == kSignUnknown) return false;
  if (s0 == 0) out.push_back({0, 0, true, 0, 1});
  if (sn == 0) out.push_back({1, 0, true, 0, 1});
  struct Piece {
    std::uint64_t k;
    int level;
  };
  std::vector<Piece> stack;
  std::vector<Bounded> coeffs;  // the pending pieces' coefficients, n1 per piece
  stack.push_back({0, 0});
  coeffs.assign(q.begin(), q.end());
  std::vector<Bounded> cur(n1), left(n1), right(n1), work(n1);
  while (!stack.empty()) {
    const Piece piece = stack.back();
    stack.pop_back();
    std::copy(coeffs.end() - static_cast<std::ptrdiff_t>(n1), coeffs.end(), cur.begin());
    coeffs.resize(coeffs.size() - n1);
    int first = 0;
    const int v = variations(cur.data(), n1, &first);
    if (v < 0) return false;
    if (v == 0) continue;
    if (v == 1) {
      out.push_back({piece.k, piece.level, false, first, 1});
      continue;
    }
    if (piece.level >= kIsolationDepth) return false;  // the exact path splits square-free here
    bernstein_halve(cur.data(), n1, left.data(), right.data(), work.data());
    const int sm = certain_sign(left.back());
    if (sm == kSignUnknown) return false;
    if (sm == 0) out.push_back({2 * piece.k + 1, piece.level + 1, true, 0, 1});
    stack.push_back({2 * piece.k + 1, piece.level + 1});
    coeffs.insert(coeffs.end(), right.begin(), right.end());
    stack.push_back({2 * piece.k, piece.level + 1});
    coeffs.insert(coeffs.end(), left.begin(), left.end());
  }
  return true;
}

// One bisection step; false when the sign at the midpoint is uncertain.
bool bisect(Found& f, const Bernstein<Bounded>& p) {
  const std::uint64_t mk = 2 * f.k + 1;
  const int ml = f.level + 1;
  const int s = certain_sign(eval(p.data(), p.size(), std::ldexp(static_cast<double>(mk), -ml)));
  if (s == kSignUnknown) return false;
  if (s == 0) {
    f.k = mk, f.level = ml, f.exact = true;
  } else {
    f.k = s == f.sign_lo ? mk : 2 * f.k;
    f.level = ml;
  }
  return true;
}

// multiplicity_at: the order of the first derivative not vanishing at t.
int multiplicity(const Bernstein<Bounded>& p, double t) {
  int m = 1;
  Bernstein<Bounded> d = bernstein_derivative(p);
  for (;;) {
    if (d.empty()) return -1;  // the exact path would read the zero polynomial's value; not certain here
    const int s = certain_sign(eval(d.data(), d.size(), t));
    if (s == kSignUnknown) return -1;
    if (s != 0) return m;
    ++m;
    d = bernstein_derivative(d);
  }
}

}  // namespace

int sign_at_start_bounded(const Bernstein<Bounded>& p) {
  for (const Bounded& c : p) {
    const int s = certain_sign(c);
    if (s != 0) return s;  // +1, -1 or unknown
  }
  return 0;
}

std::optional<std::vector<FastRoot>> isolate_roots_bounded(const Bernstein<Bounded>& p, const RootOptions& options) {
  CMR_CHECK(options.tolerance > 0 && options.tolerance <= 1);
  if (p.empty()) return std::vector<FastRoot>{};
  bool zero = true;
  for (const Bounded& c : p) {
    const int s = certain_sign(c);
    if (s == kSignUnknown) zero = false;  // not certainly zero; isolation decides the rest
    else if (s != 0) zero = false;
  }
  if (zero) return std::vector<FastRoot>{};  // certainly the zero polynomial: no isolated roots
  const int bits = static_cast<int>(std::ceil(-std::log2(options.tolerance)));
  if (bits > 60) return std::nullopt;  // dyadic ends as 64-bit numerators and exact doubles only
  std::vector<Found> found;
  if (!isolate(p, found)) return std::nullopt;
  for (Found& f : found)
    if (f.exact) {
      f.multiplicity = multiplicity(p, f.lower());
      if (f.multiplicity < 0) return std::nullopt;
    }
  for (Found& f : found)
    while (!f.exact && f.level < bits)
      if (!bisect(f, p)) return std::nullopt;
  // separate() of roots.cpp: one polynomial's enclosures overlap only where
  // an exact root sits at a piece's left end; the same sort and bisection.
  for (;;) {
    std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.lower() < b.lower(); });
    bool overlap = false;
    for (std::size_t i = 0; i + 1 < found.size() && !overlap; ++i) {
      Found& a = found[i];
      Found& b = found[i + 1];
      if (a.upper() <= b.lower()) continue;
      overlap = true;
      Found& wider = a.exact ? b : (b.exact ? a : (a.level <= b.level ? a : b));
      if (!bisect(wider, p)) return std::nullopt;
    }
    if (!overlap) break;
  }
  int s = sign_at_start_bounded(p);
  if (s == kSignUnknown) return std::nullopt;
  std::vector<FastRoot> out;
  for (const Found& f : found) {
    FastRoot r{f.k, f.level, f.exact, f.multiplicity, 0, 0};
    std::tie(r.sign_before, r.sign_after) = signs_around_root(s, f.multiplicity, f.exact && f.k == 0);
    out.push_back(r);
  }
  return out;
}

}  // namespace cmr
