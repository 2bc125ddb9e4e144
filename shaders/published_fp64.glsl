// The region benchmark's baseline as its authors run it: the published
// method (Yoshida et al., CAD&A 2024; tools/bench/published_method.hpp) per
// pixel in a fragment shader, fp64, plain double, no error bounds, no
// culling. Per pixel: the moved segments' points B = base + w (p - P_k),
// the level-0 test (3) on xi's ends, then xi from the fixed-degree formulas
// (every loop bound a specialization constant, so the driver unrolls them
// into straight-line code) and Algorithm 1 depth first on a fixed stack.
// Included by published_fp64.frag (one fragment per pixel, as published) and
// published_fp64.comp (one compute invocation per pixel, row-major): the
// benchmark times both and takes the faster as the baseline.
// Labels as published_region's: 0 not monotone, 1 increasing, 2
// decreasing, 3 undecided. Untouched segments are judged on the host and
// arrive as direction flags. Written by tools/bench/published_method_vk.cpp.
layout(constant_id = 0) const int N = 3;      // degree
layout(constant_id = 1) const int MAXD = 12;  // D of Algorithm 1
const int M = N - 1, DN = 2 * N - 4, DG = 2 * N - 2, DL = 4 * N - 7, K = 4 * N - 6;

// Per moved segment, 3 (N + 1) doubles: base x, base y, w of each point.
layout(std430, set = 0, binding = 0) readonly buffer Data { double d[]; };
layout(push_constant) uniform Push {
  dvec4 view;    // x0, y0, x1, y1
  dvec2 anchor;  // P_k before the move
  int width, height;
  int segments;  // moved segments
  uint fixed_dirs;  // untouched segments' directions: 1 inc, 2 dec, 4 undecided
} pc;

double binom(int n, int k) {  // as binomials<n>() in published_method.cpp
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * double(n - i + 1) / double(i);
  return r;
}

double Px[N + 1], Py[N + 1], xi[K];
double stack_[(MAXD + 2) * K];
int levels[MAXD + 2];

void points(int s, dvec2 dd) {
  for (int i = 0; i <= N; ++i) {
    const int at = 3 * ((N + 1) * s + i);
    Px[i] = d[at] + d[at + 2] * dd.x;
    Py[i] = d[at + 1] + d[at + 2] * dd.y;
  }
}

double lambda_start(int a, int b, int c, int e) {  // lambda_start<N> of published_method.cpp
  const double q0x = double(N) * (Px[b] - Px[a]), q0y = double(N) * (Py[b] - Py[a]);
  const double q1x = double(N) * (Px[c] - Px[b]), q1y = double(N) * (Py[c] - Py[b]);
  const double q2x = double(N) * (Px[e] - Px[c]), q2y = double(N) * (Py[e] - Py[c]);
  const double nu0 = double(M) * (q0x * q1y - q0y * q1x);
  const double nu1 = (double(M * (M - 1)) / double(DN)) * (q0x * q2y - q0y * q2x);
  const double g0 = q0x * q0x + q0y * q0y, g1 = (2.0LF * double(M) / double(DG)) * (q0x * q1x + q0y * q1y);
  return double(DN) * (nu1 - nu0) * g0 - (1.5LF * double(DG)) * nu0 * (g1 - g0);
}

bool ends_differ(double a, double b) { return (a < 0 && b > 0) || (a > 0 && b < 0); }

void lambda_fixed() {
  double qx[M + 1], qy[M + 1], nu_s[DN + 1], g_s[DG + 1], d_s[DN], e_s[DG], a[DL + 1], b[DL + 1];
  for (int i = 0; i <= M; ++i) {
    qx[i] = double(N) * (Px[i + 1] - Px[i]);
    qy[i] = double(N) * (Py[i + 1] - Py[i]);
  }
  for (int k = 0; k <= DN; ++k) nu_s[k] = 0;
  for (int k = 0; k <= DG; ++k) g_s[k] = 0;
  for (int i = 0; i <= M; ++i) {
    g_s[2 * i] += (binom(M, i) * binom(M, i)) * (qx[i] * qx[i] + qy[i] * qy[i]);
    for (int j = i + 1; j <= M; ++j) {
      const double w = binom(M, i) * binom(M, j);
      nu_s[i + j - 1] += (double(j - i) * w) * (qx[i] * qy[j] - qy[i] * qx[j]);
      g_s[i + j] += (2.0LF * w) * (qx[i] * qx[j] + qy[i] * qy[j]);
    }
  }
  for (int k = 0; k < DN; ++k)
    d_s[k] = (binom(DN - 1, k) * double(DN)) * (nu_s[k + 1] * (1.0LF / binom(DN, k + 1)) - nu_s[k] * (1.0LF / binom(DN, k)));
  for (int k = 0; k < DG; ++k)
    e_s[k] = (binom(DG - 1, k) * double(DG)) * (g_s[k + 1] * (1.0LF / binom(DG, k + 1)) - g_s[k] * (1.0LF / binom(DG, k)));
  for (int k = 0; k <= DL; ++k) {
    a[k] = 0;
    b[k] = 0;
  }
  for (int i = 0; i < DN; ++i)
    for (int j = 0; j <= DG; ++j) a[i + j] += d_s[i] * g_s[j];
  for (int i = 0; i <= DN; ++i)
    for (int j = 0; j < DG; ++j) b[i + j] += nu_s[i] * e_s[j];
  for (int k = 0; k <= DL; ++k) xi[k] = (a[k] - 1.5LF * b[k]) * (1.0LF / binom(DL, k));
}

// Algorithm 1 as algorithm1_fixed: 0 increasing, 1 decreasing, 2 none, 3 undecided, 4 constant.
int algorithm1() {
  for (int i = 0; i < K; ++i) stack_[i] = xi[i];
  levels[0] = 0;
  int sp = 1;
  bool inc = false, dec = false, undecided = false;
  while (sp > 0) {
    --sp;
    const int c = sp * K;
    const int level = levels[sp];
    if (ends_differ(stack_[c], stack_[c + K - 1])) return 2;
    double lo = stack_[c], hi = stack_[c];
    for (int i = 1; i < K; ++i) {
      lo = min(lo, stack_[c + i]);
      hi = max(hi, stack_[c + i]);
    }
    if (lo >= 0 && hi <= 0) return 4;
    if (lo >= 0) {
      inc = true;
    } else if (hi <= 0) {
      dec = true;
    } else if (level < MAXD) {
      const int left = c + K;
      stack_[left] = stack_[c];
      for (int r = 1; r < K; ++r) {
        for (int i = 0; i < K - r; ++i) stack_[c + i] = 0.5LF * (stack_[c + i] + stack_[c + i + 1]);
        stack_[left + r] = stack_[c];
      }
      levels[sp] = level + 1;
      levels[sp + 1] = level + 1;
      sp += 2;
      continue;
    } else {
      undecided = true;
    }
    if (inc && dec) return 2;
  }
  if (undecided) return 3;
  return inc || !dec ? 0 : 1;
}

uint published_label(int i, int j) {
  const double x = pc.view.x + ((pc.view.z - pc.view.x) * (double(i) + 0.5LF)) / double(pc.width);
  const double y = pc.view.w - ((pc.view.w - pc.view.y) * (double(j) + 0.5LF)) / double(pc.height);
  const dvec2 dd = dvec2(x - pc.anchor.x, y - pc.anchor.y);
  for (int s = 0; s < pc.segments; ++s) {
    points(s, dd);
    if (ends_differ(lambda_start(0, 1, 2, 3), lambda_start(N, N - 1, N - 2, N - 3))) {
      return 0u;
    }
  }
  bool inc = (pc.fixed_dirs & 1u) != 0u, dec = (pc.fixed_dirs & 2u) != 0u, undecided = (pc.fixed_dirs & 4u) != 0u;
  for (int s = 0; s < pc.segments; ++s) {
    points(s, dd);
    lambda_fixed();
    const int v = algorithm1();
    inc = inc || v == 0;
    dec = dec || v == 1;
    undecided = undecided || v == 3;
    if (v == 2 || (inc && dec)) {
      return 0u;
    }
  }
  return undecided ? 3u : (dec ? 2u : 1u);
}
