// The one piece-rule table (bezierize/decide.hpp) against the paper's rules
// written out independently on exact signs, over every sign vector of
// lengths 1..6 with signs in {-, 0, +, unknown}:
//  - exact signs: the table gives Algorithm 1's and 2's outcome;
//  - with unknowns: a certain outcome holds for every completion of the
//    unknown signs (soundness), and `uncertain` only where completions
//    disagree (nothing certain is given away);
//  - a full (eager) count and the lazy scan that stops at both signs give
//    the same piece.
#include "bezierize/decide.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <vector>

namespace cmr {
namespace {

// Algorithm 1 / 2 on exact signs, straight from CAD&A 2024 §3.
Piece paper_monotonicity(const std::vector<int>& g) {
  if (g.front() * g.back() < 0) return Piece::non_monotone;
  bool ge = true, le = true;
  for (int s : g) {
    ge = ge && s >= 0;
    le = le && s <= 0;
  }
  if (ge && le) return Piece::zero;
  if (ge) return Piece::increasing;
  if (le) return Piece::decreasing;
  return Piece::split;
}
Piece paper_inflection(const std::vector<int>& g) {
  if (g.front() * g.back() <= 0) return Piece::inflection;
  bool pos = true, neg = true;
  for (int s : g) {
    pos = pos && s > 0;
    neg = neg && s < 0;
  }
  return pos || neg ? Piece::no_inflection : Piece::split;
}

struct Signs {
  const std::vector<int>& g;
  int size() const { return static_cast<int>(g.size()); }
  int sign(int k) const { return g[k]; }
};

SignSummary eager(const std::vector<int>& g) {
  SignSummary s;
  s.n1 = static_cast<int>(g.size());
  s.first = g.front();
  s.last = g.back();
  for (int x : g) s.add(x);
  return s;
}

// Every completion of the unknown signs; f(completed) for each.
template <class F>
void completions(std::vector<int> g, std::size_t i, F&& f) {
  if (i == g.size()) return f(g);
  if (g[i] != kSignUnknown) return completions(g, i + 1, f);
  for (int s : {-1, 0, 1}) {
    g[i] = s;
    completions(g, i + 1, f);
  }
}

std::string show(const std::vector<int>& g) {
  std::ostringstream s;
  for (int x : g) s << (x == kSignUnknown ? '?' : x > 0 ? '+' : x < 0 ? '-' : '0');
  return s.str();
}

TEST(Decide, TableIsThePapersRulesCertified) {
  const int alphabet[] = {-1, 0, 1, kSignUnknown};
  for (int n1 = 1; n1 <= 6; ++n1) {
    int total = 1;
    for (int i = 0; i < n1; ++i) total *= 4;
    for (int code = 0; code < total; ++code) {
      std::vector<int> g;
      for (int i = 0, r = code; i < n1; ++i, r /= 4) g.push_back(alphabet[r % 4]);
      for (bool eta : {false, true}) {
        const auto rule = [&](const SignSummary& s) { return eta ? inflection_piece(s) : monotonicity_piece(s); };
        const auto paper = [&](const std::vector<int>& e) { return eta ? paper_inflection(e) : paper_monotonicity(e); };
        Signs src{g};
        const Piece lazy = rule(scan_signs(src)), full = rule(eager(g));
        ASSERT_EQ(lazy, full) << show(g) << (eta ? " (Algorithm 2)" : " (Algorithm 1)");
        bool agree = true, first = true;
        Piece common = Piece::uncertain;
        completions(g, 0, [&](const std::vector<int>& e) {
          const Piece p = paper(e);
          if (!first && p != common) agree = false;
          common = p;
          first = false;
        });
        if (full == Piece::uncertain)
          EXPECT_FALSE(agree) << show(g) << ": every completion gives " << to_string(common) << ", the table says uncertain";
        else
          EXPECT_TRUE(agree && full == common) << show(g) << ": table " << to_string(full) << ", completions disagree or give "
                                               << to_string(common);
      }
    }
  }
}

TEST(Decide, ZeroEndWithUncertainOtherEnd) {
  // nu_0 nu_n <= 0 is certain when one end is exactly zero; xi_0 xi_n < 0 is certainly false.
  const std::vector<int> g{0, 1, kSignUnknown};
  Signs src{g};
  EXPECT_EQ(inflection_piece(scan_signs(src)), Piece::inflection);
  EXPECT_EQ(ends_opposite(0, kSignUnknown), Truth::no);
  EXPECT_EQ(ends_touch(kSignUnknown, 0), Truth::yes);
}

TEST(Decide, JumpSignMatchesCurvatureDifference) {
  // kappa = A / G^{3/2}: compare with the difference in double on cases far from a tie.
  const double cases[][4] = {{1, 1, 2, 1}, {2, 1, 1, 1}, {-1, 4, -1, 1}, {1, 4, -1, 1}, {3, 2, 3, 2.5}, {0, 1, 0, 2}};
  for (const auto& c : cases) {
    const double kl = c[0] / std::pow(c[1], 1.5), kr = c[2] / std::pow(c[3], 1.5);
    const int want = (kr > kl) - (kr < kl);
    EXPECT_EQ(jump_sign<double>(c[0], c[1], c[2], c[3]), want) << "AL " << c[0] << " GL " << c[1] << " AR " << c[2]
                                                               << " GR " << c[3];
  }
  EXPECT_EQ(jump_sign<double>(1, 0, 1, 1), 0);  // a degenerate leg
}

}  // namespace
}  // namespace cmr
