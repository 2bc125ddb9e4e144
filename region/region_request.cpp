// The request side of the region API: the pixel -> world map's default view,
// validation, and the label types with their codes.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "region/region_setup.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr {

RegionResult RegionResult::blank(int width, int height, const View& view) {
  RegionResult out;
  out.width = width;
  out.height = height;
  out.view = view;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  out.labels.assign(n, Direction::none);
  out.depth.assign(n, 0);
  return out;
}

std::vector<std::uint8_t> RegionResult::codes() const {
  std::vector<std::uint8_t> out(size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = code_at(i);
  return out;
}

namespace {

// The one rule of "in the region" over label codes: a certified pass of the
// request's kind of label (not a fail, not undecided).
bool passes(std::uint8_t c, bool each_piece, bool alternating, bool split) {
  if (each_piece) return c == code(EachPiece::monotone);
  if (alternating) return c == code(Alternation::first_increasing) || c == code(Alternation::first_decreasing);
  if (split) return c >= code(Split::inc_inc) && c <= code(Split::dec_dec);
  return c == code(Direction::increasing) || c == code(Direction::decreasing);
}

}  // namespace

bool RegionResult::in_region(std::size_t index) const {
  return passes(code_at(index), each_piece, alternating, split);
}

std::uint8_t label_code(const RegionPixel& pixel, const RegionRequest& request) {
  return request.each_piece          ? code(pixel.piece_label)
         : !request.splits.empty()   ? code(pixel.alternating_label)
         : request.split.has_value() ? code(pixel.split_label)
                                     : code(pixel.label);
}

bool in_region(const RegionPixel& pixel, const RegionRequest& request) {
  return passes(label_code(pixel, request), request.each_piece, !request.splits.empty(), request.split.has_value());
}

int RegionResult::label_codes() const {
  return each_piece ? kPieceLabelCodes : alternating ? kAlternatingLabelCodes : split ? kSplitLabelCodes : kRegionLabelCodes;
}

const char* RegionResult::label_name(std::uint8_t c) const {
  CMR_CHECK(c < label_codes());
  return each_piece  ? to_string(static_cast<EachPiece>(c))
         : alternating ? to_string(static_cast<Alternation>(c))
         : split     ? to_string(static_cast<Split>(c))
                     : to_string(static_cast<Direction>(c));
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
  auto check_point = [&](int k, const std::string& what) {
    if (k < 0 || k >= m)
      throw InputFieldError(what + " " + std::to_string(k) + " is out of range 0.." + std::to_string(m - 1));
  };
  check_point(o.point, "point");
  const std::string with = field("with") + " point ";
  for (int g : o.with) {
    check_point(g, field("with") + " point");
    if (g == o.point) throw InputFieldError(with + std::to_string(g) + " is the moved point itself");
    if (std::count(o.with.begin(), o.with.end(), g) > 1)  // it would move twice as far
      throw InputFieldError(with + std::to_string(g) + " is named twice");
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
    throw InputFieldError(field("split") + " and " + field("each_piece") + " exclude each other: give the joints to " +
                          field("each_piece"));
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
  if (!request.split && request.splits.empty() && !request.each_piece)
    return code(request.mode == Mode::cmr ? a.cmr_algorithm2 : a.cmrwi);
  const std::vector<int> cuts = request.split        ? std::vector<int>{*request.split}
                                : request.each_piece ? each_piece_cuts(a.range, request.splits)
                                                     : request.splits;
  std::vector<Direction> groups;
  for (const auto& [first, end] : segment_groups(a.range, cuts))
    groups.push_back(part_verdict(a.segments, a.joints, first, end, request.mode));
  if (request.split) return code(combine_split(groups[0], groups[1]));
  if (request.each_piece) return code(each_piece_verdict(groups));
  return code(alternation_verdict(groups));
}

}  // namespace cmr

namespace cmr::backend {

Labels labels_of(const RegionRequest& o) {
  if (o.each_piece) return Labels::each_piece;
  return !o.splits.empty() ? Labels::alternating : (o.split ? Labels::split : Labels::plain);
}

Direction region_label(uint8_t c) {
  CMR_CHECK(c < kRegionLabelCodes);
  return static_cast<Direction>(c);
}

Split split_label(uint8_t c) {
  CMR_CHECK(c < kSplitLabelCodes);
  return static_cast<Split>(c);
}

Alternation alternating_label(uint8_t c) {
  CMR_CHECK(c < kAlternatingLabelCodes);
  return static_cast<Alternation>(c);
}

EachPiece piece_label(uint8_t c) {
  CMR_CHECK(c < kPieceLabelCodes);
  return static_cast<EachPiece>(c);
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

// kind() reads the variant's index as a Labels value.
static_assert(static_cast<int>(Labels::plain) == 0 && static_cast<int>(Labels::split) == 1 &&
              static_cast<int>(Labels::alternating) == 2 && static_cast<int>(Labels::each_piece) == 3);

LabelCodes::LabelCodes(Labels kind, std::size_t count) {
  switch (kind) {
    case Labels::plain: store_ = std::vector<Direction>(count); break;
    case Labels::split: store_ = std::vector<Split>(count); break;
    case Labels::alternating: store_ = std::vector<Alternation>(count); break;
    case Labels::each_piece: store_ = std::vector<EachPiece>(count); break;
  }
  bind();
}

LabelCodes::LabelCodes(Labels kind, const std::vector<std::uint8_t>& codes) : LabelCodes(kind, codes.size()) {
  if (!codes.empty()) std::memcpy(data_, codes.data(), codes.size());
}

LabelCodes& LabelCodes::operator=(const LabelCodes& other) {
  store_ = other.store_;
  bind();
  return *this;
}

LabelCodes& LabelCodes::operator=(LabelCodes&& other) noexcept {
  store_ = std::move(other.store_);
  bind();
  other.bind();
  return *this;
}

void LabelCodes::bind() {
  std::visit(
      [&](auto& v) {
        using Label = typename std::remove_reference_t<decltype(v)>::value_type;
        static_assert(sizeof(Label) == 1 && std::is_same_v<std::underlying_type_t<Label>, std::uint8_t>);
        // A byte pointer may read and write any object's bytes, and every
        // byte value is a value of an enum whose underlying type is uint8_t.
        data_ = reinterpret_cast<std::uint8_t*>(v.data());
        size_ = v.size();
      },
      store_);
}

bool LabelCodes::operator==(const LabelCodes& other) const {
  return size_ == other.size_ && (size_ == 0 || std::memcmp(data_, other.data_, size_) == 0);
}

void LabelCodes::move_into(RegionResult& r) {
  std::visit(
      [&](auto& v) {
        using Label = typename std::remove_reference_t<decltype(v)>::value_type;
        if constexpr (std::is_same_v<Label, Direction>) r.labels = std::move(v);
        else if constexpr (std::is_same_v<Label, Split>) r.split_labels = std::move(v);
        else if constexpr (std::is_same_v<Label, Alternation>) r.alternating_labels = std::move(v);
        else r.piece_labels = std::move(v);
      },
      store_);
  bind();
}

void check_codes(const LabelCodes& codes) {
  std::uint8_t largest = 0;
  for (const std::uint8_t c : codes) largest = std::max(largest, c);
  const Labels kind = codes.kind();
  if (kind == Labels::each_piece) (void)piece_label(largest);  // CMR_CHECK: below the kind's count
  else if (kind == Labels::alternating) (void)alternating_label(largest);
  else if (kind == Labels::split) (void)split_label(largest);
  else (void)region_label(largest);
}

RegionResult to_result(RegionImage&& image) {
  const Labels kind = image.labels.kind();
  RegionResult r;
  r.width = image.width;
  r.height = image.height;
  r.view = image.view;
  r.split = kind == Labels::split;
  r.alternating = kind == Labels::alternating;
  r.each_piece = kind == Labels::each_piece;
  CMR_CHECK(image.labels.size() == image.depth.size());
  image.labels.move_into(r);
  r.depth = std::move(image.depth);
  r.exact_pixels = image.exact_pixels;
  return r;
}

}  // namespace cmr::backend
