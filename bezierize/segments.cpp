#include "bezierize/segments.hpp"

#include <algorithm>
#include <charconv>
#include <string>

#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr {

const char* to_string(Alternation a) {
  switch (a) {
    case Alternation::first_increasing: return "inc-first";
    case Alternation::first_decreasing: return "dec-first";
    case Alternation::fail: return "fail";
    case Alternation::undecided: return "undecided";
  }
  return "?";
}

const char* to_string(EachPiece e) {
  switch (e) {
    case EachPiece::monotone: return "each-monotone";
    case EachPiece::fail: return "fail";
    case EachPiece::undecided: return "undecided";
  }
  return "?";
}

std::vector<int> each_piece_cuts(SegmentRange range, const std::vector<int>& cuts) {
  if (!cuts.empty()) return cuts;
  std::vector<int> out;
  for (int j = range.first + 1; j <= range.last; ++j) out.push_back(j);
  return out;
}

SegmentRange judged_range(const std::optional<SegmentRange>& range, int segment_count) {
  const SegmentRange all{0, segment_count - 1};
  if (!range) return all;
  const std::string text =
      "segments " + std::to_string(range->first) + ".." + std::to_string(range->last);
  if (range->first > range->last) throw InputError(text + ": the first segment is after the last");
  if (range->first < 0 || range->last > all.last)
    throw InputError(text + ": the curve has segments 0.." + std::to_string(all.last));
  return *range;
}

void validate_cuts(const std::vector<int>& cuts, SegmentRange range, int segment_count) {
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    const int s = cuts[i];
    if (s < range.first + 1 || s > range.last) {
      if (segment_count == 1)
        throw InputError("split " + std::to_string(s) + ": the curve has one segment, so no joint to split at");
      if (range.first == range.last)
        throw InputError("split " + std::to_string(s) + ": segments " + std::to_string(range.first) + ".." +
                         std::to_string(range.last) + " are one segment, so no joint to split at");
      throw InputError("split " + std::to_string(s) + " is outside " + std::to_string(range.first + 1) + ".." +
                       std::to_string(range.last));
    }
    if (i > 0 && s <= cuts[i - 1])
      throw InputError("split joints must increase (" + std::to_string(s) + " after " + std::to_string(cuts[i - 1]) +
                       ")");
  }
}

std::vector<std::pair<int, int>> segment_groups(SegmentRange range, const std::vector<int>& cuts) {
  std::vector<std::pair<int, int>> out;
  int begin = range.first;
  for (int s : cuts) {
    out.emplace_back(begin, s);
    begin = s;
  }
  out.emplace_back(begin, range.last + 1);
  return out;
}

int group_of(const std::vector<int>& cuts, int seg) {
  return static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), seg) - cuts.begin());
}

bool joint_counts(SegmentRange range, const std::vector<int>& cuts, int joint) {
  return joint > range.first && joint <= range.last && !std::binary_search(cuts.begin(), cuts.end(), joint);
}

SegmentRange parse_segment_range(const std::string& text, const std::string& option) {
  const auto dots = text.find("..");
  const auto number = [&](std::string_view s, int& v) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && ec == std::errc() && end == s.data() + s.size() && v >= 0;
  };
  SegmentRange r;
  const bool ok = dots == std::string::npos
                      ? number(text, r.first) && (r.last = r.first, true)
                      : number(std::string_view(text).substr(0, dots), r.first) &&
                            number(std::string_view(text).substr(dots + 2), r.last);
  if (!ok) throw InputFieldError(option + ": expected A..B or A, segment indices (got '" + text + "')");
  return r;
}

std::vector<int> parse_joint_list(const std::string& text, const std::string& option) {
  std::vector<int> out;
  if (text.empty()) return out;
  const auto bad = [&] { return InputFieldError(option + ": expected joints S1,S2,... (got '" + text + "')"); };
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = text.find(',', at);
    const std::string item = text.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
    int v = 0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || ec != std::errc{} || end != item.data() + item.size() || v < 0) throw bad();
    out.push_back(v);
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return out;
}

}  // namespace cmr
