// De Casteljau halving at t = 1/2 of N doubles held in aligned pairs.
//
// bernstein_halve (bernstein.hpp) works row by row in one array: row r's
// value i is 0.5 * (w_i + w_{i+1}) of row r - 1, left_r = row r's first
// value, right_{N-1-r} its last. Vectorised as it stands, each row reads
// w_{i+1} as a pair that straddles two pairs the previous row has just
// stored, which the processor cannot forward from its store buffer: the
// halving of the degree-9 per-pixel traversal (N = 30) stalled on every pair.
// Here a row's value pairs are aligned vectors and w_{i+1}'s pair is a
// shuffle of two of them, so every load matches a store.
//
// Each value is the same operation on the same operands as bernstein_halve
// with HalfMean (0.5 * (a + b)), so the halves are bit-identical (test
// HalvePairs.BitIdenticalToBernsteinHalve) and FlatPiecesN's error bound,
// derived for that arithmetic, holds unchanged.
#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.

namespace cmr {

/// In: cur[0..N) the coefficients. Out: cur[0..N) the left half, right[0..N)
/// the right half.
template <int N>
inline void halve_in_pairs(double* cur, double* right) {
  static_assert(N >= 1);
  using Pair = double __attribute__((vector_size(16)));
  // Pairs enough for values 0..N and the shuffle's partner of the last one;
  // values past a row's end are never read for a value inside it.
  constexpr int kPairs = N / 2 + 1;
  Pair w[kPairs];
#pragma GCC unroll 32
  for (int k = 0; k < kPairs; ++k) w[k] = Pair{2 * k < N ? cur[2 * k] : 0.0, 2 * k + 1 < N ? cur[2 * k + 1] : 0.0};
  right[N - 1] = cur[N - 1];
  const Pair half{0.5, 0.5};
#pragma GCC unroll 32
  for (int r = 1; r < N; ++r) {
    const int m = N - r;  // this row's values: 0..m-1
#pragma GCC unroll 32
    for (int k = 0; 2 * k < m; ++k) w[k] = half * (w[k] + __builtin_shufflevector(w[k], w[k + 1], 1, 2));
    cur[r] = w[0][0];
    right[m - 1] = w[(m - 1) / 2][(m - 1) % 2];
  }
}

}  // namespace cmr
