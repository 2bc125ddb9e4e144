#include "region/region_pieces.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "numeric/scalar.hpp"
#include "spline/errors.hpp"

namespace cmr::backend {

namespace {

using Limb = mp_limb_t;
constexpr int kLimbBits = GMP_NUMB_BITS;
static_assert(GMP_NAIL_BITS == 0 && sizeof(Limb) * 8 == GMP_NUMB_BITS, "plain limbs");

// Integers of W limbs in two's complement (mod 2^(W kLimbBits)): addition and
// left shifts are the unsigned ones, and the widths below are chosen so that
// no value overflows, which makes every result exact.

// r = a << s (r may be a).
void shift_left(Limb* r, const Limb* a, int W, unsigned s) {
  const int q = static_cast<int>(s / kLimbBits);
  const unsigned b = s % kLimbBits;
  for (int i = W - 1; i >= 0; --i) {
    Limb v = i >= q ? a[i - q] << b : 0;
    if (b != 0 && i >= q + 1) v |= a[i - q - 1] >> (kLimbBits - b);
    r[i] = v;
  }
}

// The scratch integers of one conversion, allocated once per call of rounded_pieces.
struct Scratch {
  mpz_t scaled, quotient;
  std::vector<Limb> magnitude;
  explicit Scratch(int W) : magnitude(static_cast<std::size_t>(W)) {
    mpz_init(scaled);
    mpz_init(quotient);
  }
  ~Scratch() {
    mpz_clear(scaled);
    mpz_clear(quotient);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
};

// The exact value n / (odd 2^shift) as Rational::get_d gives it: canonical
// mpq, then mpq_get_d (truncation toward zero). The reference for the rare
// values the fast conversion leaves to it.
double rounded_by_mpq(mpz_srcptr magnitude, bool negative, mpz_srcptr odd, unsigned long shift) {
  mpq_t q;
  mpq_init(q);
  mpz_set(mpq_numref(q), magnitude);
  if (negative) mpz_neg(mpq_numref(q), mpq_numref(q));
  mpz_mul_2exp(mpq_denref(q), odd, shift);
  mpq_canonicalize(q);
  const double d = mpq_get_d(q);
  mpq_clear(q);
  return d;
}

// The value n / (odd 2^shift) (n: W limbs, two's complement; odd > 0 and
// odd) truncated toward zero to a double, as mpq_get_d truncates the exact
// value. floor(floor(y) / 2^s) = floor(y / 2^s), so the quotient floor(|n|
// 2^t / odd), taken with at least 54 bits, truncated to 53 bits by
// mpz_get_d, is the value's own truncation; scaling by a power of two is
// exact for a normal result. Values that would be subnormal or overflow, or
// whose quotient is too wide for mpz_get_d, go to rounded_by_mpq.
double rounded_value(const Limb* n, int W, mpz_srcptr odd, bool odd_is_one, unsigned long shift, Scratch& s) {
  const bool negative = (n[W - 1] >> (kLimbBits - 1)) != 0;
  Limb* mag = s.magnitude.data();
  if (negative) mpn_neg(mag, n, W);
  else std::copy(n, n + W, mag);
  int size = W;
  while (size > 0 && mag[size - 1] == 0) --size;
  if (size == 0) return 0.0;
  mpz_t m_view;
  mpz_srcptr m = mpz_roinit_n(m_view, mag, size);
  long exponent = -static_cast<long>(shift);  // value = q 2^exponent / ...
  mpz_srcptr q = m;
  if (!odd_is_one) {
    const long nb = static_cast<long>(mpz_sizeinbase(m, 2)), db = static_cast<long>(mpz_sizeinbase(odd, 2));
    const long t = std::max(0L, db - nb + 55);  // floor(|n| 2^t / odd) >= 2^54
    mpz_mul_2exp(s.scaled, m, static_cast<mp_bitcnt_t>(t));
    mpz_tdiv_q(s.quotient, s.scaled, odd);
    q = s.quotient;
    exponent -= t;
  }
  if (mpz_sizeinbase(q, 2) > 1000) return rounded_by_mpq(m, negative, odd, shift);
  const double d = mpz_get_d(q);  // truncated to 53 bits
  int e = 0;
  (void)std::frexp(d, &e);
  const long top = e + exponent;  // the result lies in [2^(top-1), 2^top)
  if (top - 1 < std::numeric_limits<double>::min_exponent - 1 || top > std::numeric_limits<double>::max_exponent)
    return rounded_by_mpq(m, negative, odd, shift);
  const double r = std::ldexp(d, static_cast<int>(exponent));
  return negative ? -r : r;
}

// The pieces of the polynomial whose root coefficient k has monomial m
// A[k][m] / D[m] (integers; D[m] > 0): rounded_pieces' result.
template <std::size_t K>
std::vector<std::array<double, K>> round_pieces(const std::vector<std::array<mpz_class, K>>& A,
                                                const std::array<mpz_class, K>& D, int levels) {
  CMR_CHECK(levels >= 0 && levels < 16 && !A.empty());
  const int n1 = static_cast<int>(A.size());
  const unsigned E = static_cast<unsigned>(n1 - 1);  // bits a halving adds to the denominator
  const int pieces = (2 << levels) - 1;
  std::vector<std::array<double, K>> out(static_cast<std::size_t>(pieces) * n1);
  std::vector<char> nonzero(out.size(), 0);  // some monomial of the coefficient is not exactly 0

  mpz_class odd;
  std::vector<Limb> limbs, work;
  for (std::size_t m = 0; m < K; ++m) {
    CMR_CHECK(sgn(D[m]) > 0);
    std::size_t bits = 0;
    for (int k = 0; k < n1; ++k) bits = std::max(bits, mpz_sizeinbase(A[k][m].get_mpz_t(), 2));
    const unsigned long a = mpz_scan1(D[m].get_mpz_t(), 0);
    mpz_tdiv_q_2exp(odd.get_mpz_t(), D[m].get_mpz_t(), a);
    const bool odd_is_one = odd == 1;
    // Level L is over D 2^(L E): |numerators| < 2^(bits + L E) (a halving's
    // sums of r neighbours stay below 2^r times the parent's bound, then shift by E - r).
    const int W = static_cast<int>((bits + static_cast<std::size_t>(levels) * E + 1) / kLimbBits + 1);
    const auto at = [&](int piece, int k) { return limbs.data() + (static_cast<std::size_t>(piece) * n1 + k) * W; };
    limbs.assign(static_cast<std::size_t>(pieces) * n1 * W, 0);
    work.assign(static_cast<std::size_t>(n1) * W, 0);
    for (int k = 0; k < n1; ++k) {
      Limb* r = at(0, k);
      const mpz_srcptr v = A[k][m].get_mpz_t();
      std::copy(mpz_limbs_read(v), mpz_limbs_read(v) + mpz_size(v), r);
      if (mpz_sgn(v) < 0) mpn_neg(r, r, W);
    }
    // de Casteljau at 1/2 of piece p into its children 2p+1 (left) and 2p+2
    // (right), as bernstein_halve orders the mid-points, without the halving.
    for (int p = 0; 2 * p + 2 < pieces; ++p) {
      std::copy(at(p, 0), at(p, 0) + static_cast<std::size_t>(n1) * W, work.data());
      Limb* left = at(2 * p + 1, 0);
      Limb* right = at(2 * p + 2, 0);
      const auto w = [&](int i) { return work.data() + static_cast<std::size_t>(i) * W; };
      shift_left(left, w(0), W, E);
      shift_left(right + static_cast<std::size_t>(n1 - 1) * W, w(n1 - 1), W, E);
      for (int r = 1; r < n1; ++r) {
        for (int i = 0; i + r < n1; ++i) mpn_add_n(w(i), w(i), w(i + 1), W);
        shift_left(left + static_cast<std::size_t>(r) * W, w(0), W, E - r);
        shift_left(right + static_cast<std::size_t>(n1 - 1 - r) * W, w(n1 - 1 - r), W, E - r);
      }
    }
    Scratch scratch(W);
    for (int p = 0; p < pieces; ++p) {
      int level = 0;
      while ((2 << level) - 1 <= p) ++level;
      for (int k = 0; k < n1; ++k) {
        const Limb* n = at(p, k);
        const std::size_t o = static_cast<std::size_t>(p) * n1 + k;
        out[o][m] = rounded_value(n, W, odd.get_mpz_t(), odd_is_one, a + static_cast<unsigned long>(level) * E, scratch);
        nonzero[o] = nonzero[o] || std::any_of(n, n + W, [](Limb l) { return l != 0; });
      }
    }
  }
  for (std::size_t o = 0; o < out.size(); ++o)
    if (nonzero[o] && std::all_of(out[o].begin(), out[o].end(), [](double v) { return v == 0; }))
      out[o][0] = std::numeric_limits<double>::quiet_NaN();
  return out;
}

}  // namespace

template <std::size_t K>
std::vector<std::array<double, K>> rounded_pieces(const Bernstein<Poly3>& root, int levels) {
  CMR_CHECK(!root.empty());
  for (const Poly3& c : root)
    for (std::size_t m = K; m < kPoly3Terms; ++m) CMR_CHECK(sgn(c.c[m]) == 0);  // nu is affine in (dx, dy)
  // One denominator D[m] for monomial m of every coefficient; A[k][m] = c_k D[m].
  std::array<mpz_class, K> D;
  std::vector<std::array<mpz_class, K>> A(root.size());
  mpz_class scale;
  for (std::size_t m = 0; m < K; ++m) {
    D[m] = 1;
    for (const Poly3& c : root) mpz_lcm(D[m].get_mpz_t(), D[m].get_mpz_t(), c.c[m].get_den_mpz_t());
    for (std::size_t k = 0; k < root.size(); ++k) {
      const mpq_class& c = root[k].c[m];
      mpz_divexact(scale.get_mpz_t(), D[m].get_mpz_t(), c.get_den_mpz_t());
      mpz_mul(A[k][m].get_mpz_t(), scale.get_mpz_t(), c.get_num_mpz_t());
    }
  }
  return round_pieces<K>(A, D, levels);
}

template std::vector<std::array<double, 10>> rounded_pieces<10>(const Bernstein<Poly3>&, int);
template std::vector<std::array<double, 3>> rounded_pieces<3>(const Bernstein<Poly3>&, int);

namespace {

using Cubic = std::array<mpz_class, kPoly3Terms>;  // monomials in poly3.hpp order
using Affine = std::array<mpz_class, 3>;           // 1, dx, dy
using Quadratic = std::array<mpz_class, 6>;        // 1, dx, dy, dx^2, dx dy, dy^2

// r += f h.
void add_product(Cubic& r, const Affine& f, const Quadratic& h) {
  for (int i = 0; i < 3; ++i) {
    if (sgn(f[i]) == 0) continue;
    for (int j = 0; j < 6; ++j) {
      if (sgn(h[j]) == 0) continue;
      const int at = poly3_index(kPoly3ExpX[i] + kPoly3ExpX[j], kPoly3ExpY[i] + kPoly3ExpY[j]);
      mpz_addmul(r[at].get_mpz_t(), f[i].get_mpz_t(), h[j].get_mpz_t());
    }
  }
}

// The scaled derivative of scaled coefficients F at degree p: (k+1) F_{k+1} - (p-k) F_k.
template <class Poly>
std::vector<Poly> scaled_derivative(const std::vector<Poly>& F) {
  const int p = static_cast<int>(F.size()) - 1;
  std::vector<Poly> d(static_cast<std::size_t>(std::max(p, 0)));
  mpz_class t;
  for (int k = 0; k < p; ++k)
    for (std::size_t m = 0; m < d[k].size(); ++m) {
      d[k][m] = F[k + 1][m] * (k + 1);
      mpz_submul_ui(d[k][m].get_mpz_t(), F[k][m].get_mpz_t(), static_cast<unsigned long>(p - k));
    }
  return d;
}

// lcm_k C(p, k), and M_k = that / C(p, k).
mpz_class binomial_lcm(int p, std::vector<mpz_class>& M) {
  mpz_class L = 1;
  M.assign(static_cast<std::size_t>(p) + 1, mpz_class());
  for (int k = 0; k <= p; ++k) {
    M[k] = to_mpz(binomial(p, k));
    mpz_lcm(L.get_mpz_t(), L.get_mpz_t(), M[k].get_mpz_t());
  }
  for (int k = 0; k <= p; ++k) mpz_divexact(M[k].get_mpz_t(), L.get_mpz_t(), M[k].get_mpz_t());
  return L;
}

}  // namespace

MovedPieces moved_pieces(const std::vector<Point<Rational>>& base, const std::vector<Rational>& weight, int levels) {
  const int n = static_cast<int>(base.size()) - 1, m = n - 1;
  CMR_CHECK(n >= 2 && weight.size() == base.size());
  // Integers over one denominator D0.
  mpz_class D0 = 1, t;
  for (int i = 0; i <= n; ++i)
    for (const Rational* v : {&base[i].x, &base[i].y, &weight[i]})
      mpz_lcm(D0.get_mpz_t(), D0.get_mpz_t(), v->get_den_mpz_t());
  const auto integer = [&](const Rational& v) {
    mpz_divexact(t.get_mpz_t(), D0.get_mpz_t(), v.get_den_mpz_t());
    return mpz_class(t * v.get_num());
  };
  std::vector<mpz_class> X, Y, W;
  for (int i = 0; i <= n; ++i) {
    X.push_back(integer(base[i].x));
    Y.push_back(integer(base[i].y));
    W.push_back(integer(weight[i]));
  }
  std::vector<mpz_class> a, b, w;  // the hodograph, over n / D0
  for (int i = 0; i < n; ++i) {
    a.push_back(X[i + 1] - X[i]);
    b.push_back(Y[i + 1] - Y[i]);
    w.push_back(W[i + 1] - W[i]);
  }
  // Nu_k = C(2m-2, k) nu_k and G_k = C(2m, k) g_k (lambda.hpp), over the hodograph's scale.
  std::vector<Affine> Nu(static_cast<std::size_t>(2 * m - 1));
  std::vector<Quadratic> G(static_cast<std::size_t>(2 * m + 1));
  mpz_class c, term;
  for (int i = 0; i <= m; ++i)
    for (int j = i; j <= m; ++j) {
      const mpz_class cij = to_mpz(binomial(m, i) * binomial(m, j));
      if (j > i) {  // det(q_i, q_j) = (a_i b_j - b_i a_j) + (w_i b_j - w_j b_i) dx + (a_i w_j - a_j w_i) dy
        Affine& r = Nu[i + j - 1];
        c = cij * (j - i);
        term = a[i] * b[j] - b[i] * a[j];
        mpz_addmul(r[0].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
        term = w[i] * b[j] - w[j] * b[i];
        mpz_addmul(r[1].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
        term = a[i] * w[j] - a[j] * w[i];
        mpz_addmul(r[2].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
      }
      // q_i . q_j = (a_i a_j + b_i b_j) + (a_i w_j + a_j w_i) dx + (b_i w_j + b_j w_i) dy + w_i w_j (dx^2 + dy^2)
      Quadratic& r = G[i + j];
      c = i == j ? cij : mpz_class(2 * cij);
      term = a[i] * a[j] + b[i] * b[j];
      mpz_addmul(r[0].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
      term = a[i] * w[j] + a[j] * w[i];
      mpz_addmul(r[1].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
      term = b[i] * w[j] + b[j] * w[i];
      mpz_addmul(r[2].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
      term = w[i] * w[j];
      mpz_addmul(r[3].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
      mpz_addmul(r[5].get_mpz_t(), c.get_mpz_t(), term.get_mpz_t());
    }
  // 2 (eta' g)~ - 3 (eta g')~ at degree 4m-3 = 4n-7 (eta' is empty for n = 2).
  std::vector<Affine> dNu = scaled_derivative(Nu), nNu = Nu;
  for (Affine& f : dNu)
    for (mpz_class& v : f) v *= 2;
  for (Affine& f : nNu)
    for (mpz_class& v : f) v *= -3;
  const std::vector<Quadratic> dG = scaled_derivative(G);
  const int p = 4 * m - 3;
  std::vector<Cubic> Xi(static_cast<std::size_t>(p) + 1);
  for (std::size_t i = 0; i < dNu.size(); ++i)
    for (std::size_t j = 0; j < G.size(); ++j) add_product(Xi[i + j], dNu[i], G[j]);
  for (std::size_t i = 0; i < nNu.size(); ++i)
    for (std::size_t j = 0; j < dG.size(); ++j) add_product(Xi[i + j], nNu[i], dG[j]);
  // Common denominators: xi_k = n^4 M_k Xi_k / (2 L D0^4), nu_k = n^2 M'_k Nu_k / (L' D0^2).
  MovedPieces out;
  {
    std::vector<mpz_class> M;
    const mpz_class L = binomial_lcm(p, M);
    const mpz_class n4 = mpz_class(n) * n * n * n;
    std::array<mpz_class, kPoly3Terms> D;
    D.fill(2 * L * D0 * D0 * D0 * D0);
    for (int k = 0; k <= p; ++k) {
      const mpz_class s = n4 * M[k];
      for (mpz_class& v : Xi[k]) v *= s;
    }
    out.xi = round_pieces<kPoly3Terms>(Xi, D, levels);
  }
  {
    std::vector<mpz_class> M;
    const mpz_class L = binomial_lcm(2 * m - 2, M);
    std::array<mpz_class, 3> D;
    D.fill(L * D0 * D0);
    for (int k = 0; k <= 2 * m - 2; ++k) {
      const mpz_class s = mpz_class(n) * n * M[k];
      for (mpz_class& v : Nu[k]) v *= s;
    }
    out.nu = round_pieces<3>(Nu, D, levels);
  }
  return out;
}

}  // namespace cmr::backend
