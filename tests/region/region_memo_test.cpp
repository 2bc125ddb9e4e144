// RegionMemo (region/region_memo.hpp): problems whose per-span setup is
// remembered between moves give the label maps of problems made from
// scratch (RegionProblem::make), pixel by pixel, over seeded sequences of
// moves; and a move re-prepares only the spans it acts on.
#include "region/region_memo.hpp"

#include <gtest/gtest.h>

#include "bezierize/extract.hpp"
#include "region/region_setup.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <set>
#include <sstream>

namespace cmr {
namespace {

// A spiral's control polygon (curvature monotone along it, so regions are
// not empty), n points, degree d, uniform knots; `double_knot` repeats an
// interior knot (a C^{d-2} joint whose curvature jump varies with a move).
BSpline spiral(int n, int d, bool closed = false, bool rational = false, bool double_knot = false) {
  std::vector<Vec2> pts;
  std::vector<double> weights;
  for (int i = 0; i < n; ++i) {
    const double a = 0.55 * i, r = closed ? 3.0 + 0.4 * std::sin(1.3 * i) : std::pow(1.2, i);
    pts.push_back({r * std::cos(a), r * std::sin(a)});
    if (rational) weights.push_back(1.0 + 0.25 * (i % 3));
  }
  std::vector<double> knots;
  if (closed) {
    for (int i = 0; i <= n; ++i) knots.push_back(i);
    return BSpline::make_closed(d, knots, pts, "closed", weights);
  }
  const int count = n + d - 1;
  for (int i = 0; i < count; ++i) knots.push_back(i);
  if (double_knot) {  // knots[d] repeated: the spline keeps its knot count with one knot fewer distinct
    for (int i = d + 1; i < count; ++i) knots[i] = i - 1;
  }
  return BSpline::make(d, knots, pts, "spiral", weights);
}

std::string describe(const RegionRequest& r) {
  std::ostringstream o;
  o << "P" << r.point << (r.mode == Mode::cmr ? " cmr" : " cmrwi");
  if (r.split) o << " split " << *r.split;
  if (r.segments) o << " segments " << r.segments->first << ".." << r.segments->last;
  if (r.each_piece) o << " each-piece";
  for (int w : r.with) o << " with " << w;
  return o.str();
}

// Pixel by pixel: codes and depths. Returns 1 when the map is not uniform
// (the comparison saw a boundary), else 0.
long expect_same_maps(const RegionProblem& memo, const RegionProblem& fresh, const std::string& where) {
  CpuRegionBackend cpu(1);
  const RegionResult a = cpu.render(memo), b = cpu.render(fresh);
  EXPECT_EQ(a.size(), b.size()) << where;
  long differ = 0;
  bool mixed = false;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (a.code_at(i) != b.code_at(i) || a.depth[i] != b.depth[i]) {
      if (++differ <= 3)
        ADD_FAILURE() << where << ": pixel " << i % a.width << "," << i / a.width << ": memo code "
                      << int(a.code_at(i)) << " depth " << int(a.depth[i]) << ", from scratch code "
                      << int(b.code_at(i)) << " depth " << int(b.depth[i]);
    }
    mixed = mixed || b.code_at(i) != b.code_at(0);
  }
  return mixed ? 1 : 0;
}

struct Family {
  std::string name;
  BSpline spline;
};

// Seeded moves of random points; after each, the region of a random point
// (the moved one, a neighbour, one at a span boundary of the moved one's
// support) in a random mode, through one memo and from scratch.
void check_family(const Family& f, unsigned seed, int steps) {
  std::mt19937 rng(seed);
  RegionMemo memo;
  BSpline s = f.spline;
  const int n = s.unique_point_count(), d = s.degree(), N = s.segment_count();
  std::uniform_real_distribution<double> offset(-0.06, 0.06);
  long monotone = 0;  // steps whose map is not uniform
  int moved = 0;
  for (int step = 0; step < steps; ++step) {
    moved = static_cast<int>(rng() % n);
    const Vec2 p = s.points()[moved];
    s = s.with_point(moved, {p.x + offset(rng), p.y + offset(rng)});
    RegionRequest r;
    // The region of: the moved point, the next one, or the first and last
    // point of the moved one's first span's window (a span boundary of the support).
    const int pick = static_cast<int>(rng() % 4);
    const int first = std::max(0, std::min(moved, N - 1));
    r.point = pick == 0 ? moved : pick == 1 ? (moved + 1) % n : pick == 2 ? first % n : std::min(first + d, n - 1);
    r.mode = rng() % 2 ? Mode::cmr : Mode::cmrwi;
    const int option = static_cast<int>(rng() % 6);
    if (option == 5) {  // one span the point acts on (segment i uses P_i..P_{i+d})
      const int a = std::clamp(r.point - d + 1, 0, N - 1);
      r.segments = SegmentRange{a, a};
    }
    if (option == 1 && N >= 2 && !s.closed()) r.split = 1 + static_cast<int>(rng() % (N - 1));
    if (option == 2) {
      const int a = static_cast<int>(rng() % N);
      r.segments = SegmentRange{a, std::min(N - 1, a + 1 + static_cast<int>(rng() % 3))};
    }
    if (option == 3 && N >= 2 && !s.closed()) r.each_piece = true;
    if (option == 4 && n > 2) {
      const int w = (r.point + 2) % n;
      if (w != r.point) r.with = {w};
    }
    r.max_depth = 6;
    r.width = 28;
    r.height = 22;
    const Vec2 c = s.points()[r.point];  // a view about the point (regions of a spiral are thin)
    r.view = View{c.x - 0.35, c.y - 0.3, c.x + 0.35, c.y + 0.3};
    const std::string where = f.name + " seed " + std::to_string(seed) + " step " + std::to_string(step) +
                              " (moved P" + std::to_string(moved) + "): " + describe(r);
    const RegionProblem a = memo.make(s, r);
    const RegionProblem b = RegionProblem::make(s, r);
    monotone += expect_same_maps(a, b, where);
    // Single positions (any p, not only pixel centres) agree too.
    for (int t = 0; t < 3; ++t) {
      const Vec2 q = s.points()[r.point] + Vec2{4 * offset(rng), 4 * offset(rng)};
      const RegionPixel x = a.classify(q), y = b.classify(q);
      EXPECT_EQ(x.label, y.label) << where;
      EXPECT_EQ(x.split_label, y.split_label) << where;
      EXPECT_EQ(x.piece_label, y.piece_label) << where;
      EXPECT_EQ(x.depth, y.depth) << where;
    }
  }
  // The comparison saw region boundaries, not only uniform maps.
  EXPECT_GT(monotone, 0) << f.name << " seed " << seed << ": every step's map was uniform";
}

TEST(RegionMemo, OpenCubicLabelMapsEqualFromScratch) {
  for (unsigned seed : {1u, 2u, 3u}) check_family({"open cubic", spiral(9, 3)}, seed, 14);
}

TEST(RegionMemo, ClosedCubicLabelMapsEqualFromScratch) {
  for (unsigned seed : {4u, 5u}) check_family({"closed cubic", spiral(8, 3, true)}, seed, 12);
}

TEST(RegionMemo, QuarticWithDoubleKnotLabelMapsEqualFromScratch) {
  for (unsigned seed : {6u, 7u}) check_family({"quartic, double knot", spiral(9, 4, false, false, true)}, seed, 10);
}

TEST(RegionMemo, RationalLabelMapsEqualFromScratch) {
  check_family({"rational cubic", spiral(8, 3, false, true)}, 8, 10);
}

// Every field of a base's analysis against analyze's (region_base), bitwise
// where it is a number.
void expect_same_analysis(const SplineAnalysis& a, const SplineAnalysis& b, const std::string& where) {
  EXPECT_EQ(a.cmrwi, b.cmrwi) << where;
  EXPECT_EQ(a.cmr, b.cmr) << where;
  EXPECT_EQ(a.cmr_algorithm2, b.cmr_algorithm2) << where;
  EXPECT_EQ(a.cusp, b.cusp) << where;
  EXPECT_EQ(a.pole, b.pole) << where;
  EXPECT_EQ(a.joint_conflicts, b.joint_conflicts) << where;
  EXPECT_EQ(a.exact_segments, b.exact_segments) << where;
  EXPECT_EQ(a.range.first, b.range.first) << where;
  EXPECT_EQ(a.range.last, b.range.last) << where;
  ASSERT_EQ(a.segments.size(), b.segments.size()) << where;
  ASSERT_EQ(a.shapes.size(), b.shapes.size()) << where;
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const SegmentClass &x = a.segments[i], &y = b.segments[i];
    EXPECT_EQ(x.monotonicity.curvature, y.monotonicity.curvature) << where << " seg " << i;
    EXPECT_EQ(x.monotonicity.depth, y.monotonicity.depth) << where << " seg " << i;
    EXPECT_EQ(x.inflection.inflection, y.inflection.inflection) << where << " seg " << i;
    EXPECT_EQ(x.inflection.depth, y.inflection.depth) << where << " seg " << i;
    EXPECT_EQ(x.inflection.kappa_sign, y.inflection.kappa_sign) << where << " seg " << i;
    EXPECT_EQ(x.exact_used, y.exact_used) << where << " seg " << i;
    const SegmentShape &u = a.shapes[i], &v = b.shapes[i];
    EXPECT_EQ(u.pole, v.pole) << where << " seg " << i;
    EXPECT_EQ(u.straight, v.straight) << where << " seg " << i;
    EXPECT_EQ(u.cusp, v.cusp) << where << " seg " << i;
    EXPECT_EQ(u.inflection, v.inflection) << where << " seg " << i;
    EXPECT_EQ(u.kappa_sign, v.kappa_sign) << where << " seg " << i;
  }
  ASSERT_EQ(a.joints.size(), b.joints.size()) << where;
  ASSERT_EQ(a.seam.has_value(), b.seam.has_value()) << where;
  std::vector<Joint> ja = a.joints, jb = b.joints;
  if (a.seam) {
    ja.push_back(*a.seam);
    jb.push_back(*b.seam);
  }
  for (std::size_t j = 0; j < ja.size(); ++j) {
    EXPECT_EQ(ja[j].index, jb[j].index) << where << " joint " << j;
    EXPECT_EQ(ja[j].jump, jb[j].jump) << where << " joint " << j;
    EXPECT_EQ(ja[j].continuity, jb[j].continuity) << where << " joint " << j;
    EXPECT_EQ(ja[j].g1, jb[j].g1) << where << " joint " << j;
    EXPECT_EQ(ja[j].g2, jb[j].g2) << where << " joint " << j;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(ja[j].kappa_left), std::bit_cast<std::uint64_t>(jb[j].kappa_left))
        << where << " joint " << j;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(ja[j].kappa_right), std::bit_cast<std::uint64_t>(jb[j].kappa_right))
        << where << " joint " << j;
  }
}

TEST(RegionMemo, AnalysisEqualsAnalyze) {
  std::mt19937 rng(9);
  RegionMemo memo;
  for (BSpline s : {spiral(10, 3), spiral(8, 3, true), spiral(9, 4, false, true, true)}) {
    for (int step = 0; step < 8; ++step) {
      const int k = static_cast<int>(rng() % s.unique_point_count());
      s = s.with_point(k, s.points()[k] + Vec2{0.2 * (step % 3) - 0.2, 0.1});
      AnalyzeOptions o;
      o.classify.max_depth = 1 + step % 6;
      if (step % 2 == 1 && !s.closed()) o.split = 1;
      if (step == 5) o.continuity.angle_deg = 2.0;  // not the base's tolerances: every span looked up
      const SplineAnalysis a = memo.analyze(s, o), b = analyze(s, o);
      const std::string where = s.name() + " step " + std::to_string(step);
      EXPECT_EQ(a.cmrwi, b.cmrwi) << where;
      EXPECT_EQ(a.cmr, b.cmr) << where;
      EXPECT_EQ(a.cmr_algorithm2, b.cmr_algorithm2) << where;
      EXPECT_EQ(a.split, b.split) << where;
      expect_same_analysis(a, b, where);
      ASSERT_EQ(a.segments.size(), b.segments.size()) << where;
      for (std::size_t i = 0; i < a.segments.size(); ++i) {
        EXPECT_EQ(a.segments[i].monotonicity.curvature, b.segments[i].monotonicity.curvature) << where << " seg " << i;
        EXPECT_EQ(a.segments[i].monotonicity.depth, b.segments[i].monotonicity.depth) << where << " seg " << i;
        EXPECT_EQ(a.segments[i].inflection.inflection, b.segments[i].inflection.inflection) << where << " seg " << i;
        EXPECT_EQ(a.shapes[i].inflection, b.shapes[i].inflection) << where << " seg " << i;
      }
      ASSERT_EQ(a.joints.size(), b.joints.size()) << where;
      for (std::size_t j = 0; j < a.joints.size(); ++j) {
        EXPECT_EQ(a.joints[j].jump, b.joints[j].jump) << where << " joint " << j;
        EXPECT_EQ(a.joints[j].g2, b.joints[j].g2) << where << " joint " << j;
        EXPECT_EQ(a.joints[j].continuity, b.joints[j].continuity) << where << " joint " << j;
      }
    }
  }
}

// Locality: after a move of one point of a 40-span cubic, the next problem
// (any point's) analyses only the spans whose window holds the moved point
// (at most d+1 shapes, d+1 classes and d+2 joints) and prepares only the
// entries whose window holds it.
TEST(RegionMemo, AMoveReanalysesOnlyTheSpansItActsOn) {
  RegionMemo memo;
  BSpline s = spiral(43, 3);
  RegionRequest r;
  r.point = 20;
  r.width = r.height = 8;
  r.max_depth = 4;
  (void)memo.make(s, r);
  const int d = s.degree();
  for (int k : {0, 7, 21, 42}) {
    s = s.with_point(k, s.points()[k] + Vec2{0.05, -0.03});
    const RegionMemo::Counts before = memo.counts();
    for (int point : {20, 21}) {  // the second: nothing new at all
      r.point = point;
      (void)memo.make(s, r);
    }
    const RegionMemo::Counts after = memo.counts();
    EXPECT_LE(after.spans_computed - before.spans_computed, 3 * d + 4) << "moved P" << k;
    EXPECT_GT(after.spans_computed - before.spans_computed, 0) << "moved P" << k;
    // P20 and P21 act on at most d+2 spans together; only those holding P_k are new.
    EXPECT_LE(after.entries_computed - before.entries_computed, 2 * (d + 1)) << "moved P" << k;
  }
}

// The spline reflected in the x axis (open, polynomial): its signed
// curvature runs the other way (a decreasing spiral's increases).
BSpline mirrored(const BSpline& s) {
  std::vector<Vec2> p = s.points();
  for (Vec2& q : p) q.y = -q.y;
  return BSpline::make(s.degree(), s.knots(), p, s.name() + " mirrored");
}

// The base a problem made through the memo reads (patched in place between
// moves, its whole-spline verdicts from the memo's tree of readings) is
// region_base's, field by field, over seeded moves of one and two points;
// a base still held by an earlier problem is copied, not changed under it.
TEST(RegionMemo, PatchedBaseEqualsRegionBase) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> offset(-0.8, 0.8);
  std::set<Direction> verdicts;
  long conflicts = 0, copies = 0;
  // A spiral with a knot inserted twice at an interior knot (the same curve:
  // a C1 joint whose jump the small moves turn up or down) gives decreasing
  // verdicts and conflicting jumps; the others give the rest.
  const BSpline doubled = insert_knot(spiral(11, 3), 5.0);
  for (const BSpline& start : {doubled, mirrored(doubled), spiral(11, 3), spiral(9, 3, true), spiral(10, 3, false, false, true),
                               spiral(9, 4, false, false, true), spiral(8, 3, false, true)}) {
    RegionMemo memo;
    BSpline s = start;
    RegionRequest r;
    r.width = r.height = 4;
    r.max_depth = 5;
    std::optional<RegionProblem> held;
    for (int step = 0; step < 12; ++step) {
      const int n = s.unique_point_count();
      for (int m = 0; m <= step % 2; ++m) {  // one or two points
        const int k = static_cast<int>(rng() % n);
        const double scale = step < 8 ? 0.01 : 1.0;  // small moves first (the verdicts change now and then), then large
        s = s.with_point(k, s.points()[k] + scale * Vec2{offset(rng), offset(rng)});
      }
      r.point = static_cast<int>(rng() % n);
      const RegionMemo::Counts before = memo.counts();
      const RegionProblem a = memo.make(s, r);
      const std::string where = s.name() + " step " + std::to_string(step);
      const SplineAnalysis want = backend::region_base(s, r.max_depth)->analysis;
      expect_same_analysis(a.setup().base->analysis, want, where);
      EXPECT_EQ(a.setup().spline().points(), s.points()) << where;
      copies += memo.counts().bases_copied - before.bases_copied;
      if (held) {  // the problem held from two steps back still reads its own spline's base
        const BSpline& old = held->setup().spline();
        expect_same_analysis(held->setup().base->analysis, backend::region_base(old, r.max_depth)->analysis,
                             where + " (held)");
      }
      if (step % 3 == 0) held = a;
      verdicts.insert(want.cmrwi);
      verdicts.insert(want.cmr);
      conflicts += static_cast<long>(want.joint_conflicts.size());
    }
  }
  // The moves changed the verdicts and made conflicting jumps; held problems forced copies.
  EXPECT_GE(verdicts.size(), 3u);
  EXPECT_GT(conflicts, 0);
  EXPECT_GT(copies, 0);
}

// n points on a slow wave, cubic, uniform knots (n - 3 spans).
BSpline wave(int n) {
  std::vector<Vec2> p;
  std::vector<double> knots;
  for (int i = 0; i < n; ++i) p.push_back({0.5 * i, std::sin(0.3 * i)});
  for (int i = 0; i < n + 2; ++i) knots.push_back(i);
  return BSpline::make(3, knots, p, "wave");
}

// Locality at scale (issue 23, item 4): after a move of one point of a
// 10 000-span cubic, the next problem patches the last base at the d+1 spans
// holding the point (no base analysed over every span, none copied: the
// last problem is gone) and analyses or looks up at most 3d+4 span results.
TEST(RegionMemo, AMoveOfATenThousandSpanSplineDoesConstantSpanWork) {
  RegionMemo memo;
  BSpline s = wave(10003);
  const int d = s.degree(), N = s.segment_count();
  ASSERT_EQ(N, 10000);
  RegionRequest r;
  r.point = 5001;
  r.width = r.height = 8;
  r.max_depth = 4;
  r.segments = SegmentRange{4998, 5001};  // the spans P5001 acts on (as the editor's bench)
  (void)memo.make(s, r);
  ASSERT_EQ(memo.counts().bases_built, 1);
  ASSERT_EQ(memo.counts().spans_computed, 3 * N - 1);  // every shape, class and joint once
  for (int k : {0, 5000, 5002, 10002}) {
    s = s.with_point(k, s.points()[k] + Vec2{0.0, 0.01});
    const RegionMemo::Counts before = memo.counts();
    (void)memo.make(s, r);
    const RegionMemo::Counts after = memo.counts();
    const std::string where = "moved P" + std::to_string(k);
    EXPECT_EQ(after.bases_built, before.bases_built) << where;
    EXPECT_EQ(after.bases_copied, before.bases_copied) << where;
    EXPECT_EQ(after.bases_patched, before.bases_patched + 1) << where;
    EXPECT_GT(after.spans_patched - before.spans_patched, 0) << where;
    EXPECT_LE(after.spans_patched - before.spans_patched, d + 1) << where;
    const long span_work = after.spans_computed + after.spans_reused - before.spans_computed - before.spans_reused;
    EXPECT_GT(span_work, 0) << where;
    EXPECT_LE(span_work, 3 * d + 4) << where;
    EXPECT_LE(after.entries_computed + after.entries_reused - before.entries_computed - before.entries_reused,
              2 * (d + 1))
        << where;
  }
  // The analysis of the moved spline (the editor's verdicts) reads the same
  // kept base: no span looked up beyond the moved point's.
  s = s.with_point(3000, s.points()[3000] + Vec2{0.0, 0.01});
  {
    AnalyzeOptions o;
    o.classify.max_depth = r.max_depth;
    o.segments = SegmentRange{100, 9000};
    const RegionMemo::Counts before = memo.counts();
    const SplineAnalysis a = memo.analyze(s, o);
    const RegionMemo::Counts after = memo.counts();
    EXPECT_EQ(after.bases_built, before.bases_built);
    EXPECT_LE(after.spans_computed + after.spans_reused - before.spans_computed - before.spans_reused, 3 * d + 4);
    const SplineAnalysis b = analyze(s, o);
    EXPECT_EQ(a.cmrwi, b.cmrwi);
    EXPECT_EQ(a.cmr, b.cmr);
    EXPECT_EQ(a.joint_conflicts, b.joint_conflicts);
    EXPECT_EQ(a.exact_segments, b.exact_segments);
  }
  // A problem still holding the base: the next move copies it once.
  const RegionProblem held = memo.make(s, r);
  s = s.with_point(7000, s.points()[7000] + Vec2{0.0, 0.01});
  const long copied = memo.counts().bases_copied;
  const RegionProblem next = memo.make(s, r);
  EXPECT_EQ(memo.counts().bases_copied, copied + 1);
  EXPECT_NE(held.setup().spline().points()[7000].y, next.setup().spline().points()[7000].y);
  // And the patched base is still region_base's.
  expect_same_analysis(next.setup().base->analysis, backend::region_base(s, r.max_depth)->analysis, "10 000 spans");
}

TEST(RegionMemo, BadRequestsFailAsRegionProblemMake) {
  RegionMemo memo;
  const BSpline s = spiral(6, 3);
  RegionRequest r;
  r.point = 6;
  try {
    (void)memo.make(s, r);
    ADD_FAILURE() << "point 6 of 6 was accepted";
  } catch (const InputError& e) {
    try {
      (void)RegionProblem::make(s, r);
    } catch (const InputError& f) {
      EXPECT_STREQ(e.what(), f.what());
    }
  }
}

}  // namespace
}  // namespace cmr
