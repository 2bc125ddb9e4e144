#include "region/region_memo.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <set>

#include "numeric/fast_path.hpp"
#include "region/region_setup.hpp"

namespace cmr {

namespace {

using Key = std::vector<std::uint64_t>;

void push(Key& k, double v) { k.push_back(std::bit_cast<std::uint64_t>(v)); }

// A span's exact data: its index, the degree, its 2d knots, its d+1 control
// points and (rational) weights: everything segment_window,
// segment_bezier_points and segment_homogeneous_points read.
void push_window(Key& k, const BSpline& spline, const Segment& g) {
  const int d = spline.degree(), first = g.span - d + 1;
  k.push_back(static_cast<std::uint64_t>(g.index));
  k.push_back(static_cast<std::uint64_t>(d));
  k.push_back(spline.is_rational() ? 1 : 0);
  for (int i = first; i <= g.span + d; ++i) push(k, spline.knots()[i]);
  for (int i = first; i <= first + d; ++i) {
    push(k, spline.points()[i].x);
    push(k, spline.points()[i].y);
    if (spline.is_rational()) push(k, spline.weight(i));
  }
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Bitwise equality of a control point (and its weight): -0.0 and 0.0 differ.
bool same_point(const BSpline& a, const BSpline& b, int i) {
  const Vec2 p = a.points()[i], q = b.points()[i];
  const double wa = a.weight(i), wb = b.weight(i);
  return std::memcmp(&p.x, &q.x, sizeof(double)) == 0 && std::memcmp(&p.y, &q.y, sizeof(double)) == 0 &&
         std::memcmp(&wa, &wb, sizeof(double)) == 0;
}

template <class V, class Map, class F>
V remembered(Map& map, Key&& key, long call, long& computed, long& reused, F&& compute) {
  if (const auto it = map.find(key); it != map.end()) {
    it->second.used = call;
    ++reused;
    return it->second.value;
  }
  V v = compute();
  ++computed;
  map.emplace(std::move(key), typename Map::mapped_type{v, call});
  return v;
}


// A span's class as analyze gives it (every span judged): a pole or a
// straight polynomial span is written down, the others classified.
SegmentClass span_class(const BSpline& spline, const Segment& g, const SegmentShape& shape,
                        const ClassifyOptions& co, const AnalyzeParts& p) {
  const bool straight = fast_paths_enabled() && shape.straight && !spline.is_rational();
  return shape.pole ? pole_class() : straight ? straight_class() : p.classify(spline, g, co);
}

// What part_verdict (analyze.cpp) reads of a run of segments in one mode:
// the flags of its classes, the first and last sign of the curvature chain
// (CMR; 0: none seen), and the jumps of the joints inside the run. Two
// adjacent runs join through the joint between them, so the reading of
// [0, N) is a tree of readings and a span's change costs O(log N).
struct Reading {
  bool any = false;  // holds a segment
  bool inc = false, dec = false, none = false, undecided = false, up = false, down = false;
  int k_first = 0, k_last = 0;
};

Reading read(const SegmentClass& c, Mode mode) {
  Reading r;
  r.any = true;
  switch (c.monotonicity.curvature) {
    case Curvature::increasing: r.inc = true; break;
    case Curvature::decreasing: r.dec = true; break;
    case Curvature::non_monotone: r.none = true; break;
    case Curvature::undecided: r.undecided = true; break;
    case Curvature::constant: break;
  }
  if (mode != Mode::cmr) return r;
  switch (c.inflection.inflection) {
    case Inflection::present: r.none = true; break;
    case Inflection::undecided: r.undecided = true; break;
    case Inflection::none: r.k_first = r.k_last = c.inflection.kappa_sign; break;  // 0: straight, skipped
  }
  return r;
}

// l's segments, then r's, with the joint between them of jump `jump`.
Reading join(const Reading& l, const Reading& r, int jump) {
  if (!l.any) return r;
  if (!r.any) return l;
  Reading o;
  o.any = true;
  o.inc = l.inc || r.inc;
  o.dec = l.dec || r.dec;
  o.undecided = l.undecided || r.undecided;
  o.none = l.none || r.none || (l.k_last != 0 && r.k_first != 0 && l.k_last != r.k_first);  // a sign change
  o.up = l.up || r.up || jump > 0;
  o.down = l.down || r.down || jump < 0;
  o.k_first = l.k_first != 0 ? l.k_first : r.k_first;
  o.k_last = r.k_last != 0 ? r.k_last : l.k_last;
  return o;
}

// part_verdict's answer from its reading of the part.
Direction verdict_of(const Reading& r) {
  if (r.none || (r.inc && r.dec)) return Direction::none;
  if ((r.up && r.dec) || (r.down && r.inc) || (r.up && r.down)) return Direction::none;  // a jump against the direction
  if (r.undecided) return Direction::undecided;
  if (r.dec || r.down) return Direction::decreasing;
  return Direction::increasing;
}

}  // namespace

// The base's whole-spline verdicts (analyze with every span judged; a closed
// spline's seam judged like every other joint) from a tree of readings over
// its segments, in the three lists analyze judges: the classes in CMRWI, the
// classes in CMR (cmr_algorithm2), the exact-inflection classes in CMR (cmr);
// with the flags and counts analyze ORs and sums over the spans.
struct RegionMemo::Whole {
  struct Node {
    std::array<Reading, 3> r;
    int first = 0;  // its first segment (the joint before it joins it to its left sibling)
  };
  int size = 1;  // leaves: a power of two >= N
  std::vector<Node> nodes;
  std::set<int> ups, downs;  // joint positions (the seam at N-1) whose jump is > 0, < 0
  long cusps = 0, poles = 0, exact = 0;

  static int jump_before(const SplineAnalysis& a, int first) { return a.joints[first - 1].jump; }
  void leaf(const SplineAnalysis& a, int g) {
    Node& n = nodes[size + g];
    n.first = g;
    const SegmentClass reported = exact_inflection_classes({a.segments[g]}, {a.shapes[g]}).front();
    n.r = {read(a.segments[g], Mode::cmrwi), read(a.segments[g], Mode::cmr), read(reported, Mode::cmr)};
  }
  void combine(const SplineAnalysis& a, int i) {
    const Node &l = nodes[2 * i], &r = nodes[2 * i + 1];
    Node& n = nodes[i];
    const int jump = l.r[0].any && r.r[0].any ? jump_before(a, r.first) : 0;
    for (int m = 0; m < 3; ++m) n.r[m] = join(l.r[m], r.r[m], jump);
    n.first = l.r[0].any ? l.first : r.first;
  }
  void pull(const SplineAnalysis& a, int g) {
    for (int i = (size + g) / 2; i >= 1; i /= 2) combine(a, i);
  }
  void count(const SplineAnalysis& a, int g, int sign) {
    cusps += sign * (a.shapes[g].cusp ? 1 : 0);
    poles += sign * (a.shapes[g].pole ? 1 : 0);
    exact += sign * (a.segments[g].exact_used ? 1 : 0);
  }
  void jump(int position, int j, int sign) {
    std::set<int>& s = j > 0 ? ups : downs;
    if (j == 0) return;
    if (sign > 0) s.insert(position);
    else s.erase(position);
  }
  void build(const SplineAnalysis& a) {
    const int N = static_cast<int>(a.segments.size());
    while (size < N) size *= 2;
    nodes.assign(2 * static_cast<std::size_t>(size), Node{});
    for (int g = 0; g < N; ++g) {
      leaf(a, g);
      count(a, g, +1);
    }
    for (int i = size - 1; i >= 1; --i) combine(a, i);
    for (int j = 0; j + 1 < N; ++j) jump(j, a.joints[j].jump, +1);
    if (a.seam) jump(N - 1, a.seam->jump, +1);
  }
  // analyze's cmrwi, cmr, cmr_algorithm2, joint_conflicts, cusp, pole and
  // exact_segments, from the tree.
  void finish(SplineAnalysis& a) const {
    std::array<Reading, 3> w = nodes[1].r;
    if (a.seam) {  // the whole period: a neutral class after segment N-1, the seam before it
      w[0] = join(w[0], read(neutral_class(), Mode::cmrwi), a.seam->jump);
      w[1] = join(w[1], read(neutral_class(), Mode::cmr), a.seam->jump);
      w[2] = join(w[2], read(neutral_class(), Mode::cmr), a.seam->jump);
    }
    a.cmrwi = verdict_of(w[0]);
    a.cmr_algorithm2 = verdict_of(w[1]);
    a.cmr = verdict_of(w[2]);
    // part_verdict's conflicts (CMRWI): unless the segments alone fail, every
    // joint whose jump goes against the segments' direction, in order.
    a.joint_conflicts.clear();
    const Reading& c = w[0];
    if (!(c.none || (c.inc && c.dec)) && (c.inc || c.dec))
      for (const int j : c.dec ? ups : downs)
        a.joint_conflicts.push_back(j < static_cast<int>(a.joints.size()) ? a.joints[j].index : a.seam->index);
    a.cusp = cusps > 0;
    a.pole = poles > 0;
    a.exact_segments = static_cast<int>(exact);
  }
};

std::size_t RegionMemo::KeyHash::operator()(const std::vector<std::uint64_t>& k) const noexcept {
  std::uint64_t h = 0x9E3779B97F4A7C15ull ^ k.size();
  for (const std::uint64_t v : k) {
    h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
  }
  return static_cast<std::size_t>(h ^ (h >> 31));
}

RegionMemo::RegionMemo() = default;
RegionMemo::~RegionMemo() = default;

AnalyzeParts RegionMemo::parts() {
  AnalyzeParts p;
  p.shape = [this](const BSpline& spline, const Segment& s) {
    Key k{'S'};
    push_window(k, spline, s);
    return remembered<SegmentShape>(shapes_, std::move(k), call_, counts_.spans_computed, counts_.spans_reused,
                                    [&] { return segment_shape(spline, s); });
  };
  p.classify = [this](const BSpline& spline, const Segment& s, const ClassifyOptions& o) {
    Key k{'C', static_cast<std::uint64_t>(o.max_depth), o.inflection ? 1u : 0u};
    push_window(k, spline, s);
    return remembered<SegmentClass>(classes_, std::move(k), call_, counts_.spans_computed, counts_.spans_reused,
                                    [&] { return classify_segment(spline, s, o); });
  };
  p.joint = [this](const BSpline& spline, int left, int right, const ContinuityTolerances& t) {
    const Segment& L = spline.segments()[left];
    const Segment& R = spline.segments()[right];
    // The multiplicity is counted over the whole knot vector (cyclically on a
    // closed spline): in the key as joint_between reads it.
    Key k{'J', static_cast<std::uint64_t>(spline.segment_count()),
          static_cast<std::uint64_t>(spline.multiplicity(R.a))};
    push(k, t.angle_deg);
    push(k, t.curvature_rel);
    push_window(k, spline, L);
    push_window(k, spline, R);
    return remembered<Joint>(joints_, std::move(k), call_, counts_.spans_computed, counts_.spans_reused,
                             [&] { return joint_between(spline, left, right, t); });
  };
  return p;
}

SplineAnalysis RegionMemo::analyze(const BSpline& spline, const AnalyzeOptions& options) {
  ++call_;
  // The per-span results are the base's of that depth (kept and patched as
  // for make(): no span looked up by its data) when the tolerances are the
  // base's; the fields below are all that selects them.
  static_assert(sizeof(ClassifyOptions) == 2 * sizeof(int) && sizeof(ContinuityTolerances) == 2 * sizeof(double),
                "a new option: check that it does not change the base's per-span results");
  const ContinuityTolerances plain = AnalyzeOptions{}.continuity;
  const bool via_base = options.classify.max_depth >= 0 && options.classify.max_depth <= kMaxDepth &&
                        std::bit_cast<std::uint64_t>(options.continuity.angle_deg) ==
                            std::bit_cast<std::uint64_t>(plain.angle_deg) &&
                        std::bit_cast<std::uint64_t>(options.continuity.curvature_rel) ==
                            std::bit_cast<std::uint64_t>(plain.curvature_rel);
  if (via_base) {
    const std::shared_ptr<const backend::RegionBase> b = base(spline, options.classify.max_depth);
    const SplineAnalysis& k = b->analysis;
    AnalyzeParts p;
    p.shape = [&k](const BSpline&, const Segment& g) { return k.shapes[g.index]; };
    p.classify = [&k](const BSpline&, const Segment& g, const ClassifyOptions&) { return k.segments[g.index]; };
    p.joint = [&k](const BSpline&, int, int right, const ContinuityTolerances&) {
      return right == 0 ? *k.seam : k.joints[right - 1];
    };
    SplineAnalysis a = cmr::analyze(spline, options, p);
    trim(static_cast<std::size_t>(spline.segment_count()));
    return a;
  }
  SplineAnalysis a = cmr::analyze(spline, options, parts());
  trim(static_cast<std::size_t>(spline.segment_count()));
  return a;
}

std::shared_ptr<const backend::RegionBase> RegionMemo::base(const BSpline& spline, int max_depth) {
  AnalyzeOptions ao;  // as backend::region_base
  ao.classify.max_depth = max_depth;
  // The kept base of this depth, degree, knots and point count, if any
  // (one per depth: the editor's regions and its analysis may differ in it).
  const auto fits = [&](const BaseSlot& k) {
    const backend::RegionBase* last = k.base.get();
    return last != nullptr && k.whole != nullptr && last->max_depth == max_depth &&
           last->spline.degree() == spline.degree() && last->spline.closed() == spline.closed() &&
           last->spline.is_rational() == spline.is_rational() && last->spline.point_count() == spline.point_count() &&
           same_bits(last->spline.knots(), spline.knots());
  };
  auto slot = std::find_if(bases_.begin(), bases_.end(), fits);
  const bool same_shape = slot != bases_.end();
  if (!same_shape) {
    // A new slot, or the least recently used one.
    if (bases_.size() < kBaseSlots) slot = bases_.insert(bases_.end(), BaseSlot{});
    else slot = std::min_element(bases_.begin(), bases_.end(), [](const BaseSlot& x, const BaseSlot& y) { return x.used < y.used; });
  }
  slot->used = call_;
  std::shared_ptr<backend::RegionBase>& kept = slot->base;
  std::unique_ptr<Whole>& whole = slot->whole;
  const backend::RegionBase* last = kept.get();
  if (!same_shape) {
    // Every span analysed (or found in the maps): the first base, or new knots.
    kept = std::make_shared<backend::RegionBase>(
        backend::RegionBase{spline, cmr::analyze(spline, ao, parts()), max_depth});
    whole = std::make_unique<Whole>();
    whole->build(kept->analysis);
    ++counts_.bases_built;
    return kept;
  }
  // The points (and weights) that differ from the last base's, bitwise.
  // Blocks of 64 compared with memcmp, points within a differing block one by one.
  std::vector<int> moved;
  const std::vector<Vec2>&P = spline.points(), &Q = last->spline.points();
  const std::vector<double>&W = spline.weights(), &V = last->spline.weights();
  constexpr int kBlock = 64;
  for (int i0 = 0; i0 < spline.point_count(); i0 += kBlock) {
    const int m = std::min(kBlock, spline.point_count() - i0);
    const bool same = std::memcmp(&P[i0], &Q[i0], m * sizeof(Vec2)) == 0 &&
                      (W.empty() || std::memcmp(&W[i0], &V[i0], m * sizeof(double)) == 0);
    if (!same)
      for (int i = i0; i < i0 + m; ++i)
        if (!same_point(last->spline, spline, i)) moved.push_back(i);
  }
  if (moved.empty()) return kept;  // the same spline: the same base
  // The spans whose window (P_{span-d+1} .. P_{span+1}) holds a moved point:
  // span in [i-1, i+d-1]; the segments are in ascending span order.
  const int d = spline.degree(), N = spline.segment_count();
  const std::vector<Segment>& segs = spline.segments();
  std::vector<int> changed;
  for (const int i : moved) {
    auto it = std::lower_bound(segs.begin(), segs.end(), i - 1,
                               [](const Segment& g, int span) { return g.span < span; });
    for (; it != segs.end() && it->span <= i + d - 1; ++it) changed.push_back(it->index);
  }
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  // Patch in place unless a problem still holds the last base (it must not change under it).
  if (kept.use_count() > 1) {
    kept = std::make_shared<backend::RegionBase>(*kept);
    ++counts_.bases_copied;
  }
  ++counts_.bases_patched;
  backend::RegionBase& b = *kept;
  b.spline = spline;
  SplineAnalysis& a = b.analysis;
  const AnalyzeParts p = parts();
  ClassifyOptions co = ao.classify;
  co.inflection = true;  // as analyze: CMR verdicts always need Algorithm 2
  for (const int g : changed) {
    whole->count(a, g, -1);
    a.shapes[g] = p.shape(spline, segs[g]);
    a.segments[g] = span_class(spline, segs[g], a.shapes[g], co, p);
    whole->count(a, g, +1);
    ++counts_.spans_patched;
  }
  // The joints beside a changed span: joints[j] lies between segments j and
  // j+1; position N-1 is a closed spline's seam (segment N-1 against 0).
  std::vector<int> joints;
  for (const int g : changed) {
    if (g >= 1) joints.push_back(g - 1);
    if (g + 1 < N) joints.push_back(g);
    if (a.seam && (g == 0 || g == N - 1)) joints.push_back(N - 1);
  }
  std::sort(joints.begin(), joints.end());
  joints.erase(std::unique(joints.begin(), joints.end()), joints.end());
  for (const int j : joints) {
    Joint& at = j < N - 1 ? a.joints[j] : *a.seam;
    whole->jump(j, at.jump, -1);
    at = j < N - 1 ? p.joint(spline, j, j + 1, ao.continuity) : p.joint(spline, N - 1, 0, ao.continuity);
    whole->jump(j, at.jump, +1);
  }
  for (const int g : changed) whole->leaf(a, g);
  for (const int g : changed) {
    whole->pull(a, g);
    if (g + 1 < N) whole->pull(a, g + 1);  // the joint before it may have changed
  }
  whole->finish(a);
  return kept;
}

RegionProblem RegionMemo::make(const BSpline& spline, const RegionRequest& request) {
  ++call_;
  backend::validate_region_options(spline, request);  // before the analysis, as RegionProblem::make
  const std::shared_ptr<const backend::RegionBase> b = base(spline, request.max_depth);
  const backend::EntrySource entry = [this](const backend::RegionSetup& s, int segment, bool classify) {
    const BSpline& before = s.spline();
    const Segment& g = before.segments()[segment];
    Key k{'E', classify ? 1u : 0u, static_cast<std::uint64_t>(s.piece_levels),
          static_cast<std::uint64_t>(static_cast<std::int64_t>(s.scale_exponent))};  // entries are scaled by it
    push_window(k, before, g);
    const int first = g.span - before.degree() + 1;
    for (int i = first; i <= first + before.degree(); ++i)  // which window points the group moves
      k.push_back(std::find(s.group.begin(), s.group.end(), i) != s.group.end() ? 1 : 0);
    const auto e = remembered<std::shared_ptr<const backend::RegionEntry>>(
        entries_, std::move(k), call_, counts_.entries_computed, counts_.entries_reused,
        [&] { return std::make_shared<const backend::RegionEntry>(backend::prepare_entry(s, segment, classify)); });
    return *e;
  };
  RegionProblem problem(
      std::make_shared<const backend::RegionSetup>(backend::prepare_region(spline, request, b, entry)));
  trim(static_cast<std::size_t>(spline.segment_count()));
  return problem;
}

void RegionMemo::trim(std::size_t spans) {
  const std::size_t capacity = std::max(kMinCapacity, 8 * spans);
  constexpr long kKeepCalls = 64;  // what the last calls used stays (every layer of an editor's frame)
  const auto prune = [&](auto& map) {
    if (map.size() <= capacity) return;
    for (auto it = map.begin(); it != map.end();) it = it->second.used < call_ - kKeepCalls ? map.erase(it) : std::next(it);
  };
  prune(shapes_);
  prune(classes_);
  prune(joints_);
  prune(entries_);
}

}  // namespace cmr
