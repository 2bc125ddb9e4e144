#include "region/region_reason.hpp"

#include <algorithm>

#include "bezierize/extract.hpp"
#include "region/region_setup.hpp"
#include "spline/fields.hpp"

namespace cmr {

std::vector<int> acted_segments(const RegionProblem& problem) {
  std::vector<int> out;
  for (const backend::RegionEntry& e : problem.setup().entries)
    if (e.classify) out.push_back(e.segment);
  return out;
}

std::vector<int> fixed_failing_segments(const RegionProblem& problem) {
  const backend::RegionSetup& s = problem.setup();
  const std::vector<int> acted = acted_segments(problem);
  std::vector<int> out;
  for (int seg = s.range.first; seg <= s.range.last; ++seg) {
    const bool pole = s.base->analysis.shapes[seg].pole;
    if (!pole && std::find(acted.begin(), acted.end(), seg) != acted.end()) continue;
    const SegmentClass& c = s.fixed()[seg];
    const bool fails = pole || c.monotonicity.curvature == Curvature::non_monotone ||
                       (s.options.mode == Mode::cmr && c.inflection.inflection == Inflection::present);
    if (fails) out.push_back(seg);
  }
  return out;
}

std::string segment_list_text(const std::vector<int>& segments) {
  if (segments.empty()) return "no segment";
  if (segments.size() == 1) return "segment " + std::to_string(segments[0]);
  bool run = true;
  for (std::size_t i = 1; i < segments.size(); ++i) run = run && segments[i] == segments[i - 1] + 1;
  if (run) return "segments " + std::to_string(segments.front()) + ".." + std::to_string(segments.back());
  std::string t = "segments ";
  for (std::size_t i = 0; i < segments.size(); ++i) t += (i ? ", " : "") + std::to_string(segments[i]);
  return t;
}

std::optional<SegmentRange> closed_support_range(const BSpline& spline, int point, const std::vector<int>& with) {
  if (!spline.closed()) return std::nullopt;
  std::vector<int> group{point};
  group.insert(group.end(), with.begin(), with.end());
  for (std::size_t i = 0, n = group.size(); i < n; ++i)
    if (const int t = spline.twin(group[i]); t >= 0) group.push_back(t);
  std::vector<int> segs;
  for (const SegmentInfluence& si : influence(spline, group)) segs.push_back(si.segment);
  std::sort(segs.begin(), segs.end());
  segs.erase(std::unique(segs.begin(), segs.end()), segs.end());
  if (segs.empty() || static_cast<int>(segs.size()) == spline.segment_count()) return std::nullopt;
  for (std::size_t i = 1; i < segs.size(); ++i)
    if (segs[i] != segs[i - 1] + 1) return std::nullopt;  // wraps around the seam
  return SegmentRange{segs.front(), segs.back()};
}

std::optional<std::string> region_reason(const RegionProblem& problem, const RegionResult& result) {
  std::uint64_t monotone = 0;
  for (std::size_t i = 0; i < result.size(); ++i) monotone += result.in_region(i);
  const bool empty = monotone == 0, full = monotone == result.size();
  if (!empty && !full) return std::nullopt;
  const backend::RegionSetup& s = problem.setup();
  std::string P = "P";  // (built in two steps: GCC 12 warns falsely on "P" + std::to_string)
  P += std::to_string(problem.request().point);
  const std::vector<int> acted = acted_segments(problem);
  if (acted.empty()) {
    std::vector<int> judged;
    for (int seg = s.range.first; seg <= s.range.last; ++seg) judged.push_back(seg);
    return P + " does not act on " + segment_list_text(judged) +
           ": every position gives the same answer (the region is all or nothing)";
  }
  if (empty && s.around) {
    std::string hint;
    if (const auto r = closed_support_range(problem.spline(), problem.request().point, problem.request().with))
      hint = " (" + field("segments") + " " + std::to_string(r->first) + ".." + std::to_string(r->last) + ")";
    return "a closed curve's curvature is never monotone over its whole period: judge the spans " + P +
           " acts on" + hint;
  }
  if (empty) {
    const std::vector<int> failing = fixed_failing_segments(problem);
    if (!failing.empty()) {
      const bool pole = s.base->analysis.shapes[failing[0]].pole;
      const char* what = pole ? (failing.size() > 1 ? "have a pole" : "has a pole")
                              : (failing.size() > 1 ? "are non-monotone" : "is non-monotone");
      return segment_list_text(failing) + " " + what + " whatever " + P + " does (" + P + " acts on " +
             segment_list_text(acted) + ")";
    }
    return "no monotone position of " + P + " in this view (it acts on " + segment_list_text(acted) +
           "; the region may lie outside the view: try a larger " + field("view") + ")";
  }
  return P + "'s region covers the whole view (it extends beyond it)";
}

}  // namespace cmr
