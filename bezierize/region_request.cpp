// The request side of the region API: the pixel -> world map's default view,
// validation, and the label types with their codes.
#include <algorithm>
#include <cmath>
#include <string>

#include "bezierize/region_setup.hpp"
#include "spline/errors.hpp"

namespace cmr {

const char* to_string(RegionLabel label) {
  switch (label) {
    case RegionLabel::not_monotone: return "not-monotone";
    case RegionLabel::increasing: return "increasing";
    case RegionLabel::decreasing: return "decreasing";
    case RegionLabel::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(SplitLabel label) {
  switch (label) {
    case SplitLabel::none: return "none";
    case SplitLabel::inc_inc: return "inc-inc";
    case SplitLabel::inc_dec: return "inc-dec";
    case SplitLabel::dec_inc: return "dec-inc";
    case SplitLabel::dec_dec: return "dec-dec";
    case SplitLabel::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(AlternatingLabel label) {
  switch (label) {
    case AlternatingLabel::fail: return "fail";
    case AlternatingLabel::first_increasing: return "inc-first";
    case AlternatingLabel::first_decreasing: return "dec-first";
    case AlternatingLabel::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(PieceLabel label) {
  switch (label) {
    case PieceLabel::fail: return "fail";
    case PieceLabel::each_monotone: return "each-monotone";
    case PieceLabel::undecided: return "undecided";
  }
  return "?";
}

std::vector<std::uint8_t> RegionResult::codes() const {
  std::vector<std::uint8_t> out(size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = code_at(i);
  return out;
}

int RegionResult::label_codes() const {
  return each_piece ? kPieceLabelCodes : alternating ? kAlternatingLabelCodes : split ? kSplitLabelCodes : kRegionLabelCodes;
}

const char* RegionResult::label_name(std::uint8_t c) const {
  CMR_CHECK(c < label_codes());
  return each_piece  ? to_string(static_cast<PieceLabel>(c))
         : alternating ? to_string(static_cast<AlternatingLabel>(c))
         : split     ? to_string(static_cast<SplitLabel>(c))
                     : to_string(static_cast<RegionLabel>(c));
}

View default_view(const BSpline& spline, int width, int height) {
  double x0 = spline.points()[0].x, x1 = x0, y0 = spline.points()[0].y, y1 = y0;
  for (const Vec2& p : spline.points()) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  double w = x1 - x0, h = y1 - y0;
  const double extent = std::max({w, h, 1e-300});
  w = std::max(w, 1e-3 * extent);
  h = std::max(h, 1e-3 * extent);
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  w *= 1.5;
  h *= 1.5;
  // Square pixels: widen the direction that is short for the image's aspect.
  const double aspect = static_cast<double>(width) / height;
  if (w / h < aspect) w = h * aspect;
  else h = w / aspect;
  return {cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h};
}

}  // namespace cmr

namespace cmr::backend {

void validate_region_options(const BSpline& spline, const RegionRequest& o) {
  const int m = spline.point_count();
  auto check_point = [&](int k, const char* what) {
    if (k < 0 || k >= m)
      throw InputError(std::string(what) + " " + std::to_string(k) + " is out of range 0.." + std::to_string(m - 1));
  };
  check_point(o.point, "point");
  for (int g : o.with) {
    check_point(g, "--with point");
    if (g == o.point) throw InputError("--with point " + std::to_string(g) + " is the moved point itself");
    if (std::count(o.with.begin(), o.with.end(), g) > 1)  // it would move twice as far
      throw InputError("--with point " + std::to_string(g) + " is named twice");
  }
  for (int v : {o.width, o.height})
    if (v < 1 || v > kMaxImageSize)
      throw InputError("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                       " is outside 1.." + std::to_string(kMaxImageSize));
  const int N = spline.segment_count();
  const SegmentRange range = judged_range(o.segments, N);
  if (o.split) validate_cuts({*o.split}, range, N);
  validate_cuts(o.splits, range, N);
  if (o.split && !o.splits.empty()) throw InputError("give one split joint or a list of them, not both");
  if (o.split && o.each_piece)
    throw InputError("--split and --each-piece exclude each other: give the joints to --each-piece");
  if (o.max_depth < 0 || o.max_depth > kMaxDepth)
    throw InputError("depth " + std::to_string(o.max_depth) + " is outside 0.." + std::to_string(kMaxDepth));
  if (o.view) {
    const View& v = *o.view;
    for (double x : {v.x0, v.y0, v.x1, v.y1})
      if (!std::isfinite(x)) throw InputError("view: coordinates must be finite");
    if (!(v.x1 > v.x0) || !(v.y1 > v.y0)) throw InputError("view: need X0 < X1 and Y0 < Y1");
    // Pixel centres are computed as documented (pixel_center): every step must stay finite.
    if (!std::isfinite((v.x1 - v.x0) * o.width) || !std::isfinite((v.y1 - v.y0) * o.height))
      throw InputError("view: too large for double arithmetic (its extent times the image size overflows)");
  }
}

uint8_t label_of(Direction d) {
  switch (d) {
    case Direction::increasing: return code(RegionLabel::increasing);
    case Direction::decreasing: return code(RegionLabel::decreasing);
    case Direction::undecided: return code(RegionLabel::undecided);
    case Direction::none: return code(RegionLabel::not_monotone);
  }
  return code(RegionLabel::not_monotone);
}

uint8_t label_of(Split s) {
  switch (s) {
    case Split::inc_inc: return code(SplitLabel::inc_inc);
    case Split::inc_dec: return code(SplitLabel::inc_dec);
    case Split::dec_inc: return code(SplitLabel::dec_inc);
    case Split::dec_dec: return code(SplitLabel::dec_dec);
    case Split::undecided: return code(SplitLabel::undecided);
    case Split::none: return code(SplitLabel::none);
  }
  return code(SplitLabel::none);
}

uint8_t label_of(EachPiece e) {
  switch (e) {
    case EachPiece::monotone: return code(PieceLabel::each_monotone);
    case EachPiece::undecided: return code(PieceLabel::undecided);
    case EachPiece::fail: return code(PieceLabel::fail);
  }
  return code(PieceLabel::fail);
}

uint8_t label_of(Alternation a) {
  switch (a) {
    case Alternation::first_increasing: return code(AlternatingLabel::first_increasing);
    case Alternation::first_decreasing: return code(AlternatingLabel::first_decreasing);
    case Alternation::undecided: return code(AlternatingLabel::undecided);
    case Alternation::fail: return code(AlternatingLabel::fail);
  }
  return code(AlternatingLabel::fail);
}

}  // namespace cmr::backend

namespace cmr {

AnalyzeOptions region_analyze_options(const RegionRequest& request) {
  AnalyzeOptions ao;
  ao.classify.max_depth = request.max_depth;
  ao.split = request.split;
  ao.splits = request.splits;
  ao.each_piece = request.each_piece;
  ao.split_mode = request.mode;
  ao.segments = request.segments;
  return ao;
}

std::uint8_t region_label_code(const SplineAnalysis& a, const RegionRequest& request) {
  using backend::label_of;
  if (!request.split && request.splits.empty() && !request.each_piece)
    return label_of(request.mode == Mode::cmr ? a.cmr_algorithm2 : a.cmrwi);
  const std::vector<int> cuts = request.split        ? std::vector<int>{*request.split}
                                : request.each_piece ? each_piece_cuts(a.range, request.splits)
                                                     : request.splits;
  std::vector<Direction> groups;
  for (const auto& [first, end] : segment_groups(a.range, cuts))
    groups.push_back(part_verdict(a.segments, a.joints, first, end, request.mode));
  if (request.split) return label_of(combine_split(groups[0], groups[1]));
  if (request.each_piece) return label_of(each_piece_verdict(groups));
  return label_of(alternation_verdict(groups));
}

}  // namespace cmr

namespace cmr::backend {

Labels labels_of(const RegionRequest& o) {
  if (o.each_piece) return Labels::each_piece;
  return !o.splits.empty() ? Labels::alternating : (o.split ? Labels::split : Labels::plain);
}

RegionLabel region_label(uint8_t c) {
  CMR_CHECK(c < kRegionLabelCodes);
  return static_cast<RegionLabel>(c);
}

SplitLabel split_label(uint8_t c) {
  CMR_CHECK(c < kSplitLabelCodes);
  return static_cast<SplitLabel>(c);
}

AlternatingLabel alternating_label(uint8_t c) {
  CMR_CHECK(c < kAlternatingLabelCodes);
  return static_cast<AlternatingLabel>(c);
}

PieceLabel piece_label(uint8_t c) {
  CMR_CHECK(c < kPieceLabelCodes);
  return static_cast<PieceLabel>(c);
}

RegionPixel to_pixel(const PixelResult& r, Labels kind) {
  RegionPixel p;
  if (kind == Labels::each_piece) p.piece_label = piece_label(r.label);
  else if (kind == Labels::alternating) p.alternating_label = alternating_label(r.label);
  else if (kind == Labels::split) p.split_label = split_label(r.label);
  else p.label = region_label(r.label);
  p.depth = r.depth;
  p.exact = r.exact;
  return p;
}

RegionResult to_result(RegionImage&& image, Labels kind) {
  RegionResult r;
  r.width = image.width;
  r.height = image.height;
  r.view = image.view;
  r.split = kind == Labels::split;
  r.alternating = kind == Labels::alternating;
  r.each_piece = kind == Labels::each_piece;
  if (r.each_piece) {
    r.piece_labels.reserve(image.labels.size());
    for (uint8_t c : image.labels) r.piece_labels.push_back(piece_label(c));
  } else if (r.alternating) {
    r.alternating_labels.reserve(image.labels.size());
    for (uint8_t c : image.labels) r.alternating_labels.push_back(alternating_label(c));
  } else if (r.split) {
    r.split_labels.reserve(image.labels.size());
    for (uint8_t c : image.labels) r.split_labels.push_back(split_label(c));
  } else {
    r.labels.reserve(image.labels.size());
    for (uint8_t c : image.labels) r.labels.push_back(region_label(c));
  }
  r.depth = std::move(image.depth);
  r.exact_pixels = image.exact_pixels;
  return r;
}

}  // namespace cmr::backend
