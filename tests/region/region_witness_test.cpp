// Block proofs that label a box 0 without deciding every segment
// (block.cpp): the not-monotone witness (not_monotone_witness: a failed box
// proof that finds a dyadic piece whose end values certainly have opposite
// signs over the box labels the whole box "not monotone"), and a segment
// left unresolved while the others fail whatever it does
// (fails_whatever_unknown: e.g. one certainly increasing, one certainly
// decreasing).
// Label maps (no depth map) rendered with the search must equal those
// rendered without it (set_witness_search) pixel by pixel, in the default
// view of a cubic Bezier (fig2 P1), the uniform cubic B-spline (fig8 P3),
// the degree-9 Bezier (P4) and a rational cubic B-spline (nurbs_cubic P3),
// D = 10 and 16, CMRWI and CMR; and every pixel of the default view of the
// two cubics must have the exact path's code, CMRWI and CMR. Each scene
// checks that a witness decided some block, so that equal maps cannot come
// from the search never succeeding, and the uniform cubic (three spans)
// that some block was labelled with a span unresolved. (An inflection
// witness for Algorithm 2, the same search on eta's pieces, was tried on 6
// Dec 2026: it decided no block in the default views of 13 example splines
// and every one of their points in CMR mode, so it was not kept.)
#include <gtest/gtest.h>

#include <optional>
#include <sstream>
#include <vector>
#include <string>

#include "region/box_reuse.hpp"
#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/spline_json.hpp"
#include "tests/region/boundary_point.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

const std::string kSource = CMR_SOURCE_DIR;

// Restores the default whatever the test's outcome.
struct WitnessSwitch {
  ~WitnessSwitch() { set_witness_search(-1); }
};

RegionImage render(const RegionSetup& s, bool witness) {
  set_witness_search(witness ? 1 : 0);
  return region_cpu(s, 2);
}

// Every pixel of the default view at exact_size^2 against the exact path (D = 10).
void expect_exact(const BSpline& spline, int point, int exact_size, Mode mode, const std::string& file,
                  bool expect_unknown) {
  const RegionProblem p =
      RegionProblem::make(spline, test::region_request(point, 10, exact_size, std::nullopt, false, mode));
  const RegionSetup& s = p.setup();
  const std::uint64_t exact_before = witness_blocks.load(), unknown_before = unknown_segment_blocks.load();
  const RegionImage on = render(s, true);
  EXPECT_GT(witness_blocks.load(), exact_before) << file << ": no witness at " << exact_size << "^2";
  if (expect_unknown && mode == Mode::cmrwi) {
    EXPECT_GT(unknown_segment_blocks.load(), unknown_before)
        << file << ": no block labelled with a span unresolved at " << exact_size << "^2";
  }
  std::ostringstream first;
  const int wrong = test::labels_not_exact(s, on, exact_size, first);
  EXPECT_EQ(wrong, 0) << file << " P" << point << (mode == Mode::cmr ? ", CMR, " : ", CMRWI, ") << exact_size
                      << "^2 against the exact path" << first.str();
}

void expect_witness_labels(const std::string& file, int point, int exact_size, bool expect_unknown = false) {
  const WitnessSwitch restore;
  const BSpline spline = read_spline_file(kSource + file);
  const std::uint64_t before = witness_blocks.load();
  for (const Mode mode : {Mode::cmrwi, Mode::cmr})
    for (const int depth : {10, 16}) {
      const RegionProblem p =
          RegionProblem::make(spline, test::region_request(point, depth, 256, std::nullopt, false, mode));
      const RegionImage on = render(p.setup(), true), off = render(p.setup(), false);
      int wrong = 0;
      std::ostringstream first;
      for (std::size_t at = 0; at < on.labels.size(); ++at)
        if (on.labels[at] != off.labels[at] && wrong++ < 3)
          first << "\n  pixel " << at % 256 << ", " << at / 256 << ": code " << int(on.labels[at])
                << " with the witness, " << int(off.labels[at]) << " without";
      EXPECT_EQ(wrong, 0) << file << " P" << point << (mode == Mode::cmr ? ", CMR" : ", CMRWI") << ", D = " << depth
                          << first.str();
    }
  EXPECT_GT(witness_blocks.load(), before) << file << ": no block was decided by a witness";
  if (exact_size == 0) return;
  for (const Mode mode : {Mode::cmrwi, Mode::cmr}) expect_exact(spline, point, exact_size, mode, file, expect_unknown);
}

TEST(RegionWitness, CubicBezierLabelsUnchangedAndExact) {
  expect_witness_labels("/examples/figures/fig2.json", 1, 128);
}

TEST(RegionWitness, UniformCubicLabelsUnchangedAndExact) {
  expect_witness_labels("/examples/figures/fig8.json", 3, 128, true);
}

TEST(RegionWitness, Degree9BezierLabelsUnchanged) { expect_witness_labels("/examples/bezier9.json", 4, 0); }

TEST(RegionWitness, RationalCubicLabelsUnchanged) {
  expect_witness_labels("/examples/rational/nurbs_cubic.json", 3, 0);
}

// The labels of groups of spans (a split at a joint, alternating groups,
// each span on its own) of the uniform cubic against the exact path, every
// pixel of its default view, CMRWI and CMR: a group fails on its own spans
// (fails_whatever_unknown judges each group), and the label kinds' own
// rules come after it.
TEST(RegionWitness, GroupsOfSpansAreExact) {
  const WitnessSwitch restore;
  const BSpline spline = read_spline_file(kSource + "/examples/figures/fig8.json");
  const int size = 64;
  struct Groups {
    const char* name;
    std::optional<int> split;
    std::vector<int> splits;
    bool each_piece;
  };
  const std::uint64_t unknown_before = unknown_segment_blocks.load();
  for (const Groups& g : {Groups{"split 1", 1, {}, false}, Groups{"split 2", 2, {}, false},
                          Groups{"alternating 1,2", std::nullopt, {1, 2}, false},
                          Groups{"each piece", std::nullopt, {}, true}})
    for (const Mode mode : {Mode::cmrwi, Mode::cmr}) {
      RegionRequest o = test::region_request(3, 10, size, std::nullopt, false, mode);
      o.split = g.split;
      o.splits = g.splits;
      o.each_piece = g.each_piece;
      const RegionProblem p = RegionProblem::make(spline, o);
      const RegionSetup& s = p.setup();
      const RegionImage on = render(s, true);
      std::ostringstream first;
      const int wrong = test::labels_not_exact(s, on, size, first);
      EXPECT_EQ(wrong, 0) << g.name << (mode == Mode::cmr ? ", CMR" : ", CMRWI") << first.str();
    }
  EXPECT_GT(unknown_segment_blocks.load(), unknown_before) << "no group labelled with a span unresolved";
}

}  // namespace
}  // namespace cmr
