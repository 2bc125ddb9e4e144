#include "tools/edit/engine.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include <sstream>

#include "bezierize/extract.hpp"
#include "region/region_reason.hpp"
#include "report/extremum.hpp"
#include "bezierize/knot_ops.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "draw/draw.hpp"
#include "report/report.hpp"
#include "tools/field_flags.hpp"

namespace cmr::edit {

std::vector<RegionResult> compute_regions(const BSpline& spline, const std::vector<RegionRequest>& layers,
                                          RegionMemo* memo) {
  std::vector<RegionResult> out;
  out.reserve(layers.size());
  CpuRegionBackend backend;  // all cores
  for (const RegionRequest& r : layers)
    out.push_back(backend.render(memo != nullptr ? memo->make(spline, r) : RegionProblem::make(spline, r)));
  return out;
}

namespace {

/// a - b as (rounded difference, rounding error): s + e == a - b exactly
/// (Knuth's TwoSum), so the pair is a function of the exact difference.
void push_difference(std::vector<double>& key, double a, double b) {
  const double s = a - b;
  const double bb = s - a;
  const double e = (a - (s - bb)) + (-b - bb);
  key.push_back(s);
  key.push_back(e);
}

}  // namespace

// The key holds every field of RegionRequest that shapes the labels (all but
// `cancel`, a caller's flag); a new field must join it (the size check makes
// a merge that adds one fail here rather than cache wrongly).
static_assert(sizeof(void*) != 8 || sizeof(RegionRequest) == 152,  // each_piece fits the padding
              "RegionRequest changed: add the new field to region_key, then update this size");

std::vector<double> region_key(const BSpline& spline, const RegionRequest& r) {
  std::vector<double> key;
  // One allocation (a long spline's key is long): the fields below, at most.
  key.reserve(24 + r.with.size() + r.splits.size() + spline.knots().size() + spline.weights().size() +
              4 * spline.points().size());
  const auto count = [&](std::size_t n) { key.push_back(static_cast<double>(n)); };
  // Pushed one by one: insert of an initializer list into the empty vector
  // makes GCC 12 warn falsely (-Wstringop-overflow).
  for (const double v : {static_cast<double>(r.mode), r.split ? static_cast<double>(*r.split) : -1.0,
                         static_cast<double>(r.max_depth), r.depth ? 1.0 : 0.0, static_cast<double>(r.width),
                         static_cast<double>(r.height), static_cast<double>(r.point)})
    key.push_back(v);
  count(r.with.size());
  for (int w : r.with) key.push_back(w);
  key.insert(key.end(), {r.segments ? 1.0 : 0.0, r.segments ? static_cast<double>(r.segments->first) : 0.0,
                         r.segments ? static_cast<double>(r.segments->last) : 0.0});
  count(r.splits.size());
  for (int s : r.splits) key.push_back(s);
  key.push_back(r.each_piece ? 1.0 : 0.0);
  key.push_back(spline.degree());
  count(spline.knots().size());
  key.insert(key.end(), spline.knots().begin(), spline.knots().end());
  // The weights (none for a polynomial spline): every weight, the moved
  // point's included, shapes the region of a rational spline.
  count(spline.weights().size());
  key.insert(key.end(), spline.weights().begin(), spline.weights().end());
  const std::vector<Vec2>& pts = spline.points();
  count(pts.size());
  const bool k_valid = r.point >= 0 && r.point < spline.point_count();
  // Without a view the default one follows the control polygon, P_k included.
  const bool relative = k_valid && r.view.has_value();
  if (r.view) key.insert(key.end(), {r.view->x0, r.view->y0, r.view->x1, r.view->y1});
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
    const bool moved = relative && (i == r.point || std::find(r.with.begin(), r.with.end(), i) != r.with.end());
    if (i == r.point && relative) continue;
    if (moved) {
      push_difference(key, pts[i].x, pts[r.point].x);
      push_difference(key, pts[i].y, pts[r.point].y);
    } else {
      key.push_back(pts[i].x);
      key.push_back(pts[i].y);
    }
  }
  return key;
}

std::uint64_t RegionCache::hash(const std::vector<double>& key) {
  std::uint64_t h = 0x9E3779B97F4A7C15ull ^ key.size();
  for (const double v : key) {
    // Equal keys (==, element by element) hash alike: -0.0 as 0.0.
    h ^= (v == 0 ? 0 : std::bit_cast<std::uint64_t>(v)) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
  }
  return h;
}

RegionCache::Entry* RegionCache::entry(const std::vector<double>& key) {
  // The hash first: a long spline's keys are long and share their knots and
  // most points, so comparing them whole against every entry costs O(N) each.
  // The most recent entry first, compared without hashing: the editor asks
  // for the layer it has just been given.
  if (!entries_.empty() && entries_.front().key == key) return &entries_.front();
  const std::uint64_t h = hash(key);
  const auto it =
      std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.hash == h && e.key == key; });
  if (it == entries_.end()) return nullptr;
  std::rotate(entries_.begin(), it, it + 1);
  return &entries_.front();
}

const RegionResult* RegionCache::find(const std::vector<double>& key) {
  const Entry* e = entry(key);
  return e != nullptr ? e->result.get() : nullptr;
}

std::optional<std::string> RegionCache::reason(const BSpline& spline, const RegionRequest& request,
                                               const std::vector<double>& key, RegionMemo* memo) {
  Entry* e = entry(key);
  if (e == nullptr) return std::nullopt;
  if (!e->reason) {
    ++reasons_worked_out_;
    try {
      std::optional<std::string> why = region_reason(
          memo != nullptr ? memo->make(spline, request) : RegionProblem::make(spline, request), *e->result);
      if (why) why = cli::show_fields(*why);  // the library's fields as the command's flags
      e->reason = std::move(why);
    } catch (const InputError&) {
      e->reason = std::optional<std::string>{};
    }
  }
  return *e->reason;
}

const RegionResult& RegionCache::get(const BSpline& spline, const RegionRequest& request, RegionMemo* memo) {
  return get(spline, request, region_key(spline, request), memo);
}

const RegionResult& RegionCache::get(const BSpline& spline, const RegionRequest& request, std::vector<double> key,
                                     RegionMemo* memo) {
  if (const RegionResult* hit = find(key)) return *hit;
  auto result = std::make_shared<const RegionResult>(std::move(compute_regions(spline, {request}, memo).front()));
  const std::uint64_t h = hash(key);
  entries_.insert(entries_.begin(), Entry{std::move(key), h, std::move(result), std::nullopt});
  if (entries_.size() > capacity_) entries_.resize(capacity_);
  return *entries_.front().result;
}

void RegionCache::set_capacity(std::size_t capacity) {
  capacity_ = std::max<std::size_t>(1, capacity);
  if (entries_.size() > capacity_) entries_.resize(capacity_);
}

std::vector<uint8_t> region_rgba(const std::vector<const RegionResult*>& layers, bool split, bool depth_shading,
                                 int max_depth) {
  std::vector<uint8_t> rgba;
  region_rgba(layers, split, depth_shading, max_depth, rgba);
  return rgba;
}

void region_rgba(const std::vector<const RegionResult*>& layers, bool split, bool depth_shading, int max_depth,
                 std::vector<uint8_t>& rgba) {
  if (layers.empty()) {
    rgba.clear();
    return;
  }
  draw::RegionPicture picture;
  picture.layers = layers;
  picture.split = split;
  picture.alternating = layers.front()->alternating;
  picture.each_piece = layers.front()->each_piece;
  picture.depth_shading = depth_shading;
  picture.max_depth = max_depth;
  const std::size_t count = layers.front()->size();
  rgba.resize(count * 4);  // every byte is written below
  // Rows in parallel: the colour of a pixel depends on that pixel alone, so a
  // pixel whose labels (and levels, when shaded) equal its left neighbour's
  // takes that colour without recomputing it (regions are mostly runs).
  const int width = layers.front()->width;
  const auto byte = [](double c) { return static_cast<uint8_t>(std::lround(255 * std::clamp(c, 0.0, 1.0))); };
  const auto same_as_left = [&](std::size_t i) {
    for (const RegionResult* l : layers) {
      if (l->code_at(i) != l->code_at(i - 1) || (depth_shading && l->depth[i] != l->depth[i - 1])) return false;
    }
    return true;
  };
  parallel_for(static_cast<std::size_t>(layers.front()->height), 0, [&](std::size_t row) {
    for (std::size_t i = row * width; i < (row + 1) * width; ++i) {
      if (i > row * width && same_as_left(i)) {
        std::copy_n(&rgba[4 * (i - 1)], 4, &rgba[4 * i]);
        continue;
      }
      const draw::Rgb c = draw::pixel_colour(picture, i);
      rgba[4 * i] = byte(c.r);
      rgba[4 * i + 1] = byte(c.g);
      rgba[4 * i + 2] = byte(c.b);
      rgba[4 * i + 3] = 255;
    }
  });
}

SplineAnalysis verdicts(const BSpline& spline, int max_depth, std::optional<int> split, Mode mode,
                        std::optional<SegmentRange> segments, RegionMemo* memo) {
  AnalyzeOptions o;
  o.classify.max_depth = max_depth;
  o.split = split;
  o.split_mode = mode;
  o.segments = segments;
  return memo != nullptr ? memo->analyze(spline, o) : analyze(spline, o);
}

CurvatureEvents curvature_events(const BSpline& spline, int max_depth) {
  report::ReportOptions o;
  o.max_depth = max_depth;
  o.regions = false;
  o.threads = 1;
  const report::SplineReport r = report::report_spline(spline, o);
  CurvatureEvents e;
  for (const report::CurveEvent& x : r.extrema) {  // by |kappa| (docs/semantics.md)
    const ExtremumKind k = report::event_kind(r, x);
    (k == ExtremumKind::sharpest ? e.maxima : k == ExtremumKind::flattest ? e.minima : e.inflections).push_back(x.t);
    e.extrema.push_back({x.t, x.kappa, static_cast<int>(k), x.segment, x.joint});
  }
  for (const report::CurveEvent& x : r.inflections) e.inflections.push_back(x.t);
  return e;
}

namespace {

std::string number(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

}  // namespace

KnotResult knot_operation(const BSpline& spline, const std::string& name, double a, double b) {
  if (name == "insert") {
    const int times = b > 0 ? static_cast<int>(b) : 1;
    return {insert_knot(spline, a, times), "inserted knot " + number(a) + (times > 1 ? " x" + std::to_string(times) : "")};
  }
  if (name == "remove") {
    const double tolerance = b > 0 ? b : kRemovalRelativeTolerance * extent(spline);
    KnotRemoval r = remove_knot(spline, a, tolerance);
    return {std::move(r.spline), "removed knot " + number(a) + " (the curve moved by up to " + number(r.distance) + ")"};
  }
  if (name == "elevate") return {elevate_degree(spline), "degree elevated to " + std::to_string(spline.degree() + 1)};
  if (name == "clamp") return {clamp(spline), "clamped: the ends have multiplicity " + std::to_string(spline.degree())};
  if (name == "uniform") return {make_uniform(spline), "uniform knots 0, 1, 2, ..."};
  throw InputError("unknown knot operation '" + name + "' (insert, remove, elevate, clamp, uniform)");
}

}  // namespace cmr::edit
