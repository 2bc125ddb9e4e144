#include "bezierize/region_memo.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "bezierize/region_setup.hpp"

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

}  // namespace

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
  SplineAnalysis a = cmr::analyze(spline, options, parts());
  trim(static_cast<std::size_t>(spline.segment_count()));
  return a;
}

std::shared_ptr<const backend::RegionBase> RegionMemo::base(const BSpline& spline, int max_depth) {
  const backend::RegionBase* last = last_base_.get();
  const bool same_shape = last != nullptr && last->max_depth == max_depth &&
                          last->spline.degree() == spline.degree() && last->spline.closed() == spline.closed() &&
                          last->spline.is_rational() == spline.is_rational() &&
                          same_bits(last->spline.knots(), spline.knots()) &&
                          last->spline.point_count() == spline.point_count();
  // The spans whose window holds a control point (or weight) that differs
  // from the last base's: only these are looked up (or analysed); the others'
  // shapes, classes and joints are the last base's (the same exact data).
  std::vector<bool> changed;
  if (same_shape) {
    const int d = spline.degree();
    std::vector<bool> moved(spline.point_count(), false);
    bool any = false;
    for (int i = 0; i < spline.point_count(); ++i) {
      moved[i] = !same_point(last->spline, spline, i);
      any = any || moved[i];
    }
    if (!any) return last_base_;  // the same spline: the same base
    for (const Segment& g : spline.segments()) {
      bool c = false;
      for (int i = g.span - d + 1; i <= g.span + 1 && !c; ++i) c = moved[i];
      changed.push_back(c);
    }
  }
  AnalyzeParts p = parts();
  if (same_shape) {
    const SplineAnalysis& old = last->analysis;
    p.shape = [&, inner = p.shape](const BSpline& s, const Segment& g) {
      return changed[g.index] ? inner(s, g) : old.shapes[g.index];
    };
    p.classify = [&, inner = p.classify](const BSpline& s, const Segment& g, const ClassifyOptions& o) {
      return changed[g.index] ? inner(s, g, o) : old.segments[g.index];
    };
    p.joint = [&, inner = p.joint](const BSpline& s, int left, int right, const ContinuityTolerances& t) {
      if (changed[left] || changed[right]) return inner(s, left, right, t);
      return right == 0 ? *old.seam : old.joints[right - 1];
    };
  }
  AnalyzeOptions ao;  // as backend::region_base
  ao.classify.max_depth = max_depth;
  last_base_ = std::make_shared<const backend::RegionBase>(
      backend::RegionBase{spline, cmr::analyze(spline, ao, p), max_depth});
  return last_base_;
}

RegionProblem RegionMemo::make(const BSpline& spline, const RegionRequest& request) {
  ++call_;
  backend::validate_region_options(spline, request);  // before the analysis, as RegionProblem::make
  const std::shared_ptr<const backend::RegionBase> b = base(spline, request.max_depth);
  const backend::EntrySource entry = [this](const backend::RegionSetup& s, int segment, bool classify) {
    const BSpline& before = s.spline();
    const Segment& g = before.segments()[segment];
    Key k{'E', classify ? 1u : 0u, static_cast<std::uint64_t>(s.piece_levels)};
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
