// `cmr analyze`'s document streamed on several threads in chunks
// (report/analyze_json.hpp) against the single-thread path and against the
// whole tree of analyze()'s result: the same bytes, compact and indented, on
// seeded splines with inflections, cusps, straight runs, repeated knots,
// closed and rational ones, under every option that changes the document
// (--segments, --split, alternation, --each-piece); and the analysis it
// returns is analyze()'s. The same members written from a finished analysis
// (write_analysis_document, the Python module's dict) and the threaded
// analyze_on_threads give the same bytes; a set cancel flag stops the latter.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "bezierize/analyze.hpp"
#include "report/analyze_json.hpp"
#include "report/json_stream.hpp"
#include "spline/errors.hpp"

namespace cmr::report {
namespace {

// The first byte where two texts differ, with some context.
::testing::AssertionResult same_text(const std::string& expected, const std::string& actual) {
  if (expected == actual) return ::testing::AssertionSuccess();
  std::size_t i = 0;
  while (i < expected.size() && i < actual.size() && expected[i] == actual[i]) ++i;
  const std::size_t from = i < 60 ? 0 : i - 60;
  return ::testing::AssertionFailure() << "differ at byte " << i << " (sizes " << expected.size() << ", "
                                       << actual.size() << ")\n expected: " << expected.substr(from, 120)
                                       << "\n actual:   " << actual.substr(from, 120);
}

std::string streamed(const BSpline& s, const AnalyzeOptions& o, const AnalysisJsonOptions& j,
                     SplineAnalysis* analysis = nullptr) {
  std::ostringstream out;
  SplineAnalysis a = write_analysis_json(out, s, o, j);
  if (analysis) *analysis = std::move(a);
  return out.str();
}

// What `cmr analyze` printed before it streamed: the whole tree, dumped.
std::string tree_text(const BSpline& s, const AnalyzeOptions& o, bool pretty) {
  return analysis_json_tree(s, analyze(s, o), o.splits)
             .dump(pretty ? 2 : -1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) +
         "\n";
}

// Random splines: integer or real coordinates, straight runs (collinear
// points), cusps (a repeated point), repeated knots (C0/C1 joints), degree
// 2..5; every fourth rational, every third closed.
BSpline random_spline(std::mt19937_64& rng, int trial) {
  std::uniform_int_distribution<int> degree_of(2, 5), small(-40, 40), pick(0, 9);
  std::uniform_real_distribution<double> real(-10, 10), weight(0.5, 3);
  const int d = degree_of(rng);
  const int m = d + 2 + static_cast<int>(rng() % 10);
  std::vector<Vec2> P;
  for (int i = 0; i < m; ++i) {
    Vec2 p = trial % 2 == 0 ? Vec2(small(rng), small(rng)) : Vec2(real(rng), real(rng));
    const int k = pick(rng);
    if (i >= 2 && k == 0) p = P[i - 1] + (P[i - 1] - P[i - 2]);
    if (i >= 1 && k == 1) p = P[i - 1];
    P.push_back(p);
  }
  std::vector<double> w;
  if (trial % 4 == 3)
    for (int i = 0; i < m; ++i) w.push_back(weight(rng));
  const std::string name = "random " + std::to_string(trial);
  if (trial % 3 == 2) {  // closed: m + 1 knots of one period, multiplicities <= d
    std::vector<double> knots;
    double u = 0;
    while (static_cast<int>(knots.size()) < m + 1) {
      const int mult = std::min(m + 1 - static_cast<int>(knots.size()), 1 + static_cast<int>(rng() % d));
      for (int k = 0; k < mult; ++k) knots.push_back(u);
      u += 1 + (rng() % 3) * 0.5;
    }
    return BSpline::make_closed(d, knots, P, name, w);
  }
  std::vector<double> knots(d, 0.0);
  int interior = m - d - 1;
  double u = 0;
  while (interior > 0) {
    u += 1 + (rng() % 3) * 0.25;
    const int mult = std::min(interior, 1 + static_cast<int>(rng() % d));
    for (int k = 0; k < mult; ++k) knots.push_back(u);
    interior -= mult;
  }
  u += 1;
  for (int k = 0; k < d; ++k) knots.push_back(u);
  return BSpline::make(d, knots, P, name, w);
}

// The option sets that change the document, for a spline of n segments.
std::vector<std::pair<std::string, AnalyzeOptions>> option_sets(int n) {
  std::vector<std::pair<std::string, AnalyzeOptions>> out;
  out.emplace_back("default", AnalyzeOptions{});
  AnalyzeOptions shallow;
  shallow.classify.max_depth = 2;
  out.emplace_back("depth 2", shallow);
  if (n >= 3) {
    AnalyzeOptions range;
    range.segments = SegmentRange{1, n - 2};
    out.emplace_back("segments 1..n-2", range);
    AnalyzeOptions split;
    split.split = n / 2;
    out.emplace_back("split", split);
    AnalyzeOptions alternation;
    alternation.splits = {1, n - 1};
    out.emplace_back("alternation", alternation);
    AnalyzeOptions each;
    each.each_piece = true;
    out.emplace_back("each piece", each);
  }
  return out;
}

void expect_same_document(const BSpline& s, const std::string& ctx) {
  for (const auto& [what, o] : option_sets(s.segment_count()))
    for (const bool pretty : {false, true}) {
      const std::string c = ctx + ", " + what + (pretty ? ", pretty" : "");
      const std::string reference = tree_text(s, o, pretty);
      SplineAnalysis single;
      EXPECT_TRUE(same_text(reference, streamed(s, o, {.pretty = pretty, .threads = 1}, &single))) << c;
      // Chunks of 1 and 2 spans on 2 and 3 threads, windows of 1 and 3 chunks.
      EXPECT_TRUE(same_text(reference, streamed(s, o, {.pretty = pretty, .threads = 3, .chunk = 1, .window = 1})))
          << c << ", 3 threads, chunk 1";
      SplineAnalysis parallel;
      EXPECT_TRUE(
          same_text(reference, streamed(s, o, {.pretty = pretty, .threads = 2, .chunk = 2, .window = 3}, &parallel)))
          << c << ", 2 threads, chunk 2";
      const SplineAnalysis a = analyze(s, o);
      // The finished analysis written by the stream's member writers (what
      // the Python module builds its dict with), from analyze() and from
      // analyze_on_threads on 3 threads.
      std::string members;
      JsonStream whole(members, pretty ? 2 : -1);
      write_analysis_document(whole, s, a, o.splits);
      EXPECT_TRUE(same_text(reference, members + "\n")) << c << ", write_analysis_document";
      const SplineAnalysis threaded = analyze_on_threads(s, o, 3);
      std::string threaded_text;
      JsonStream threaded_stream(threaded_text, pretty ? 2 : -1);
      write_analysis_document(threaded_stream, s, threaded, o.splits);
      EXPECT_TRUE(same_text(reference, threaded_text + "\n")) << c << ", analyze_on_threads";
      EXPECT_EQ(parallel.exact_segments, a.exact_segments) << c;
      EXPECT_EQ(single.exact_segments, a.exact_segments) << c;
      EXPECT_EQ(parallel.cmrwi, a.cmrwi) << c;
      EXPECT_EQ(parallel.joint_conflicts, a.joint_conflicts) << c;
      if (::testing::Test::HasFailure()) return;
    }
}

TEST(AnalyzeJson, StreamedParallelTextIsTheSingleThreadTextAndTheTree) {
  std::mt19937_64 rng(23);
  int made = 0, closed = 0, rational = 0;
  for (int trial = 0; trial < 120; ++trial) {
    std::optional<BSpline> s;
    try {
      s = random_spline(rng, trial);
    } catch (const InputError&) {
      continue;  // an invalid draw
    }
    ++made;
    closed += s->closed() ? 1 : 0;
    rational += s->is_rational() ? 1 : 0;
    expect_same_document(*s, s->name());
    if (HasFailure()) return;
  }
  EXPECT_GT(made, 90);
  EXPECT_GT(closed, 20);
  EXPECT_GT(rational, 20);
}

TEST(AnalyzeJson, ACancelFlagStopsTheThreadedAnalysis) {
  std::vector<Vec2> P;
  std::vector<double> knots;
  for (int i = 0; i < 2000; ++i) P.emplace_back(i, (i * 7919) % 13);
  for (int i = 0; i < 2000 + 2; ++i) knots.push_back(i);
  const BSpline s = BSpline::make(3, knots, P, "long");
  const std::atomic<bool> set{true}, unset{false};
  EXPECT_THROW(analyze_on_threads(s, {}, 2, &set), Cancelled);
  EXPECT_EQ(analyze_on_threads(s, {}, 2, &unset).cmrwi, analyze(s, {}).cmrwi);
}

TEST(AnalyzeJson, KnownShapesAreCovered) {
  // An S curve (inflection), a cusp (a repeated point), a corner (C0 knot)
  // and a straight run; a single segment (no joints); a rational circle arc.
  const std::vector<BSpline> splines = {
      BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, {{0, 0}, {1, 2}, {2, 2}, {3, -2}, {4, -2}, {5, 0}}, "S"),
      BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, {{0, 0}, {1, 2}, {2, 0}, {2, 0}, {3, 2}, {4, 0}}, "cusp"),
      BSpline::make(2, {0, 0, 1, 1, 2, 2}, {{0, 0}, {1, 1}, {2, 0}, {3, 1}, {4, 0}}, "corner"),
      BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 1}, {5, 3}}, "straight"),
      BSpline::bezier({{0, 0}, {1, 2}, {3, 2}, {4, 0}}, "one"),
      BSpline::bezier({{1, 0}, {1, 1}, {0, 1}}, "arc", {1, std::sqrt(0.5), 1}),
  };
  for (const BSpline& s : splines) expect_same_document(s, s.name());
}

TEST(AnalyzeJson, LongSplineInChunks) {
  // A uniform cubic of 3,000 spans on a random walk of turning angles (the
  // scale benchmark's curve, tools/bench/scale.sh): chunks of 64 spans on 2
  // threads against one thread and the tree.
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> turn_step(-0.35, 0.35);
  std::vector<Vec2> P;
  double x = 0, y = 0, heading = 0, turn = 0;
  for (int i = 0; i < 3003; ++i) {
    turn = 0.85 * turn + turn_step(rng);
    heading += turn;
    x += std::cos(heading);
    y += std::sin(heading);
    P.emplace_back(std::round(x * 1e6) / 1e6, std::round(y * 1e6) / 1e6);
  }
  std::vector<double> knots;
  for (int k = 0; k < 3003 + 2; ++k) knots.push_back(k);
  const BSpline s = BSpline::make(3, knots, P, "walk");
  const AnalyzeOptions o;
  const std::string reference = tree_text(s, o, false);
  EXPECT_TRUE(same_text(reference, streamed(s, o, {.threads = 1})));
  EXPECT_TRUE(same_text(reference, streamed(s, o, {.threads = 2, .chunk = 64})));
}

TEST(AnalyzeJson, BadOptionsThrowBeforeAnythingIsWritten) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, {{0, 0}, {1, 2}, {2, 2}, {3, -2}, {4, -2}, {5, 0}});
  AnalyzeOptions o;
  o.split = 7;
  std::ostringstream out;
  EXPECT_THROW(write_analysis_json(out, s, o, {.threads = 2}), InputError);
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace cmr::report
