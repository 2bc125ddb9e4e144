// The piece rules of Algorithms 1 and 2 and the lazy sign scan of one piece:
// the mirror of bezierize/decide.hpp, shared by region_common.glsl and the
// rule test shader (piece_rules_test.frag, run by tests/vk/piece_rules_test.cpp
// against the C++ core). The includer defines REAL, REAL2 and
//   REAL2 coeff_at(uint e, bool eta, int p, int k)
// (coefficient k of piece p, value and bound), after including this file.

const int SIGN_UNKNOWN = 2;
const int P_INC = 0, P_DEC = 1, P_ZERO = 2, P_NONMONO = 3, P_INFL = 4, P_NOINFL = 5, P_SPLIT = 6, P_UNCERTAIN = 7;

// Certain sign of a value with its bound (cmr::certain_sign).
int b_sign(REAL2 a) {
  if (abs(a.x) > a.y) return a.x > REAL(0) ? 1 : -1;  // false for NaN: unknown
  if (a.y == REAL(0) && a.x == REAL(0)) return 0;     // an exact (structural) zero
  return SIGN_UNKNOWN;
}
REAL2 coeff_at(uint e, bool eta, int p, int k);

// The piece rules of bezierize/decide.hpp, line by line (ends_opposite,
// ends_touch, monotonicity_piece, inflection_piece): a certain zero end makes
// "c_0 c_n < 0" certainly false and "c_0 c_n <= 0" certainly true, whatever
// the other end.
const int T_NO = 0, T_YES = 1, T_UNKNOWN = 2;
int ends_opposite(int first, int last) {
  if (first == 0 || last == 0) return T_NO;
  if (first == SIGN_UNKNOWN || last == SIGN_UNKNOWN) return T_UNKNOWN;
  return first != last ? T_YES : T_NO;
}
int ends_touch(int first, int last) {
  if (first == 0 || last == 0) return T_YES;
  if (first == SIGN_UNKNOWN || last == SIGN_UNKNOWN) return T_UNKNOWN;
  return first != last ? T_YES : T_NO;
}
int monotonicity_rule(int first, int last, int pos, int neg, int zero, int unk) {
  int ends = ends_opposite(first, last);
  if (ends == T_YES) return P_NONMONO;
  bool ge = neg == 0 && unk == 0, le = pos == 0 && unk == 0;
  if (ge && le) return P_ZERO;
  if (ge) return P_INC;
  if (le) return P_DEC;
  if (pos > 0 && neg > 0 && ends == T_NO) return P_SPLIT;
  return P_UNCERTAIN;
}
int inflection_rule(int n1, int first, int last, int pos, int neg, int zero, int unk) {
  int ends = ends_touch(first, last);
  if (ends == T_YES) return P_INFL;
  if (ends == T_UNKNOWN) return P_UNCERTAIN;
  if (pos == n1 || neg == n1) return P_NOINFL;
  if (neg + zero > 0 && pos + zero > 0) return P_SPLIT;
  return P_UNCERTAIN;
}

// The lazy sign scan of one piece (bezierize/decide.hpp, scan_signs): both
// ends, then the inner coefficients until both signs appeared (or, with
// stop_at_unknown, an unknown one). The coefficients are read at one call
// site (ends first, then the inner ones in order): the driver inlines every
// call of coeff_at, so fewer sites mean a smaller pipeline that compiles
// sooner.
void scan_piece(uint e, bool eta, int p, int n1, bool stop_at_unknown, out int first, out int last, out int pos,
                out int neg, out int zero, out int unk) {
  first = SIGN_UNKNOWN;
  last = SIGN_UNKNOWN;
  pos = 0; neg = 0; zero = 0; unk = 0;
  for (int t = 0; t < n1 && !(t >= 2 && ((pos > 0 && neg > 0) || (stop_at_unknown && unk > 0))); ++t) {
    int g = b_sign(coeff_at(e, eta, p, t == 0 ? 0 : (t == 1 ? n1 - 1 : t - 1)));
    if (t == 0) first = g;
    if (t == 1 || n1 == 1) last = g;
    if (g == SIGN_UNKNOWN) ++unk; else if (g > 0) ++pos; else if (g < 0) ++neg; else ++zero;
  }
}

// A piece by Algorithm 1 (2) at one position; first_sign: the sign of
// coefficient 0 (read first, always).
int decide_piece(uint e, bool eta, int p, int n1, out int first_sign) {
  int first, last, pos, neg, zero, unk;
  scan_piece(e, eta, p, n1, false, first, last, pos, neg, zero, unk);
  first_sign = first;
  return eta ? inflection_rule(n1, first, last, pos, neg, zero, unk)
             : monotonicity_rule(first, last, pos, neg, zero, unk);
}
int decide_piece(uint e, bool eta, int p, int n1) {
  int first_sign;
  return decide_piece(e, eta, p, n1, first_sign);
}

// A piece over a box of positions (bezierize/decide.hpp, block_piece): a
// leaf only where every coefficient's sign is certain over the box; any
// other piece is split (P_UNCERTAIN: all exactly zero).
int decide_box_piece(uint e, bool eta, int p, int n1) {
  int first, last, pos, neg, zero, unk;
  scan_piece(e, eta, p, n1, true, first, last, pos, neg, zero, unk);
  if ((eta ? ends_touch(first, last) : ends_opposite(first, last)) == T_YES) return eta ? P_INFL : P_NONMONO;
  if (zero == n1) return P_UNCERTAIN;
  if (unk == 0 && neg == 0 && (!eta || zero == 0)) return P_INC;
  if (unk == 0 && pos == 0 && (!eta || zero == 0)) return P_DEC;
  return P_SPLIT;
}
