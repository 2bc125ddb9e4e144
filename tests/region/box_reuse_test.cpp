// The pieces of the block-proof reuse (region/box_reuse.hpp) on their
// own: which facts a box traversal records from a node's certain signs
// (block_piece's equality and zero cases included), how a record collapses a
// completed subtree of one direction, how a reader finds a node's fact in
// preorder, and a pixel traversal that takes recorded facts.
#include <gtest/gtest.h>

#include <vector>

#include "region/box_reuse.hpp"
#include "bezierize/decide.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

// A summary of fully read certain signs (kSignUnknown allowed).
SignSummary summary(const std::vector<int>& g) {
  SignSummary s;
  s.n1 = static_cast<int>(g.size());
  s.first = g.front();
  s.last = g.back();
  for (const int x : g) s.add(x);
  return s;
}

NodeFact fact(const std::vector<int>& g, bool eta) {
  const SignSummary s = summary(g);
  return box_fact(s, block_piece(s, eta), eta);
}

TEST(BoxReuse, FactsOfXi) {
  EXPECT_EQ(fact({1, 0, 1, 1}, false), NodeFact::increasing);   // >= 0, not all zero
  EXPECT_EQ(fact({-1, -1, 0, -1}, false), NodeFact::decreasing);
  EXPECT_EQ(fact({1, -1, 1, 1}, false), NodeFact::split);       // both signs, ends alike
  EXPECT_EQ(fact({0, -1, 1, 1}, false), NodeFact::split);       // a structural zero end: rule 3 certainly false
  EXPECT_EQ(fact({1, kSignUnknown, -1, 1}, false), NodeFact::split);  // signs seen: both
  EXPECT_EQ(fact({1, 1, kSignUnknown, 1}, false), NodeFact::none);    // a sub-box may find it increasing
  EXPECT_EQ(fact({kSignUnknown, -1, 1, 1}, false), NodeFact::none);   // a sub-box may prove rule 3
  EXPECT_EQ(fact({1, -1, 1, -1}, false), NodeFact::none);        // rule 3 proved: not a recorded split
  EXPECT_EQ(fact({0, 0, 0, 0}, false), NodeFact::none);          // zero piece: left to the pixels
}

TEST(BoxReuse, FactsOfNu) {
  EXPECT_EQ(fact({1, 1, 1}, true), NodeFact::increasing);       // strictly > 0
  EXPECT_EQ(fact({1, 0, 1}, true), NodeFact::split);            // a zero inside: Algorithm 2 splits
  EXPECT_EQ(fact({-1, 1, -1}, true), NodeFact::split);
  EXPECT_EQ(fact({1, kSignUnknown, 1}, true), NodeFact::none);  // a sub-box may find it strictly positive
  EXPECT_EQ(fact({0, 1, 1}, true), NodeFact::none);             // an inflection proved (ends touch)
  EXPECT_EQ(fact({kSignUnknown, -1, 1}, true), NodeFact::none);
}

TEST(BoxReuse, CompletedSubtreeOfOneDirectionCollapses) {
  SegmentRecord r;
  RecordWriter w(&r);
  w.node(0, 0, NodeFact::none);   // root split
  w.node(1, 0, NodeFact::split);  // left child split
  w.node(2, 0, NodeFact::increasing);
  w.done(2);
  w.node(2, 1, NodeFact::increasing);
  w.done(2);
  w.done(1);  // (1, 0) complete: one direction
  ASSERT_EQ(r.nodes.size(), 2u);
  EXPECT_EQ(r.nodes[1].key, SegmentRecord::key(1, 0));
  EXPECT_EQ(r.nodes[1].fact, NodeFact::increasing);
  EXPECT_EQ(r.whole(), NodeFact::none);
  w.node(1, 1, NodeFact::increasing);
  w.done(1);
  w.done(0);
  ASSERT_EQ(r.nodes.size(), 1u);
  EXPECT_EQ(r.whole(), NodeFact::increasing);
}

TEST(BoxReuse, MixedOrUnfinishedSubtreesStay) {
  SegmentRecord r;
  RecordWriter w(&r);
  w.node(0, 0, NodeFact::split);
  w.node(1, 0, NodeFact::increasing);
  w.done(1);
  w.node(1, 1, NodeFact::none);  // split at level D: nothing below it
  w.done(1);
  w.done(0);
  EXPECT_EQ(r.nodes.size(), 3u);
  EXPECT_EQ(r.whole(), NodeFact::none);  // a split root is not a direction
}

TEST(BoxReuse, ReaderFindsFactsInPreorder) {
  SegmentRecord r;
  r.nodes = {{SegmentRecord::key(0, 0), NodeFact::split},
             {SegmentRecord::key(1, 0), NodeFact::decreasing},
             {SegmentRecord::key(2, 2), NodeFact::split},
             {SegmentRecord::key(3, 5), NodeFact::decreasing}};
  RecordReader rd(&r);
  EXPECT_EQ(rd.at(0, 0), NodeFact::split);
  EXPECT_EQ(rd.at(1, 0), NodeFact::decreasing);
  EXPECT_EQ(rd.at(1, 1), NodeFact::none);  // not recorded
  EXPECT_EQ(rd.at(2, 2), NodeFact::split);
  EXPECT_EQ(rd.at(3, 4), NodeFact::none);
  EXPECT_EQ(rd.at(3, 5), NodeFact::decreasing);
  EXPECT_EQ(rd.at(2, 3), NodeFact::none);
  RecordReader none(nullptr);
  EXPECT_EQ(none.at(0, 0), NodeFact::none);
}

// A coefficient source whose signs must not be read where a fact decides.
struct CountingSource {
  std::vector<int> signs;
  int reads = 0;
  int size() const { return static_cast<int>(signs.size()); }
  int sign(int k) {
    ++reads;
    return signs[static_cast<std::size_t>(k)];
  }
  void split(int, int) {}
  void next(int, int) {}
};

TEST(BoxReuse, PixelTraversalTakesRecordedFacts) {
  // Every piece reads as "both signs" (split), but the record says the root
  // splits and both halves are increasing: no sign is read, answer increasing.
  CountingSource src{{1, -1, 1}};
  SegmentRecord r;
  r.nodes = {{SegmentRecord::key(0, 0), NodeFact::split},
             {SegmentRecord::key(1, 0), NodeFact::increasing},
             {SegmentRecord::key(1, 1), NodeFact::increasing}};
  std::uint64_t reused = 0;
  std::vector<Piece> seen;
  const bool ok = traverse_with_record(
      src, 4, monotonicity_piece,
      [&](Piece p, int) {
        seen.push_back(p);
        return false;
      },
      &r, reused);
  EXPECT_TRUE(ok);
  EXPECT_EQ(src.reads, 0);
  EXPECT_EQ(reused, 3u);
  EXPECT_EQ(seen, (std::vector<Piece>{Piece::increasing, Piece::increasing}));
}

// The switch (tools/ read CMR_BLOCK_REUSE into it; the library reads no
// environment): off, on, and back to the default, on.
TEST(BoxReuse, SwitchTurnsReuseOffAndBackOn) {
  set_block_reuse(0);
  EXPECT_FALSE(block_reuse());
  set_block_reuse(1);
  EXPECT_TRUE(block_reuse());
  set_block_reuse(-1);
  EXPECT_TRUE(block_reuse());
}

}  // namespace
}  // namespace cmr
