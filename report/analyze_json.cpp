#include "report/analyze_json.hpp"

#include <algorithm>
#include <string>

#include "bezierize/extract.hpp"
#include "bezierize/joint_json.hpp"
#include "io/stdout_error.hpp"
#include "report/json_stream.hpp"
#include "spline/parallel.hpp"

namespace cmr::report {

namespace {

using Json = nlohmann::ordered_json;

// ------------------------------------------------------------ the tree

Json segment_json(const Segment& s, const SegmentClass& c, const SegmentShape& sh, bool judged) {
  if (!judged)  // --segments: reported, not judged
    return {{"index", s.index}, {"interval", {s.a, s.b}}, {"curvature", "ignored"}, {"inflection", "ignored"}};
  Json seg = {{"index", s.index},
              {"interval", {s.a, s.b}},
              {"class", shape_class(sh)},
              {"curvature", to_string(c.monotonicity.curvature)},
              {"inflection", to_string(sh.inflection)},
              {"zero_curvature_at", kappa_zero_at(sh)},
              {"algorithm2", to_string(c.inflection.inflection)},
              {"depth", c.monotonicity.depth},
              {"inflection_depth", c.inflection.depth},
              {"exact", c.exact_used}};
  if (sh.pole) seg["poles"] = sh.poles;  // W = 0 there: the curve passes through infinity
  return seg;
}

Json verdict_json(const SplineAnalysis& a, const std::vector<int>& splits) {
  Json verdict = {{"cmrwi", to_string(a.cmrwi)},
                  {"cmr", to_string(a.cmr)},
                  {"cmr_algorithm2", to_string(a.cmr_algorithm2)},
                  {"cusp", a.cusp}};
  if (a.pole) verdict["pole"] = true;
  if (a.split) verdict["split"] = to_string(*a.split);
  if (a.alternation || a.each_piece) {
    // --split S1,S2,... (alternation) or --each-piece (each group on its own:
    // monotone in either direction): the groups between the cut joints.
    if (a.alternation) verdict["alternation"] = to_string(*a.alternation);
    else verdict["each_piece"] = to_string(*a.each_piece);
    Json groups = Json::array();
    const auto parts = segment_groups(a.range, a.alternation ? splits : a.cuts);
    for (std::size_t g = 0; g < a.groups.size(); ++g)
      groups.push_back({{"segments", {parts[g].first, parts[g].second - 1}}, {"direction", to_string(a.groups[g])}});
    verdict["groups"] = groups;
  }
  if (a.range != SegmentRange{0, static_cast<int>(a.segments.size()) - 1})
    verdict["segments"] = {a.range.first, a.range.last};
  if (!a.joint_conflicts.empty()) verdict["joint_conflicts"] = a.joint_conflicts;
  return verdict;
}

}  // namespace

JointMarks joint_marks(const SplineAnalysis& a, const Joint& j, const std::vector<int>& splits) {
  JointMarks m;
  m.seam = a.seam && j.index == a.seam->index;
  const bool inside = j.index > a.range.first && j.index <= a.range.last;
  const bool seam_judged = m.seam && a.range.first == 0 &&
                           a.range.last == static_cast<int>(a.segments.size()) - 1 && splits.empty() && !a.split &&
                           !a.each_piece;
  m.ignored = !inside && !seam_judged;
  return m;
}

namespace {

// Text that a JsonStream writing the whole document writes at one place in
// it: inside the top-level object, as the value of a member (depth 1) or as
// the first element of a member's array (depth 2; a later chunk of elements
// adds the comma). The stream is opened there and the opening is cut off.
class Placed {
 public:
  Placed(bool pretty, bool in_array) : stream_(text_, pretty ? 2 : -1) {
    stream_.begin_object();
    stream_.key("k");
    if (in_array) stream_.begin_array();
    start_ = text_.size();
  }
  JsonStream& stream() { return stream_; }
  /// What was written since the opening; `comma`: a chunk after the first.
  std::string take(bool comma) {
    if (comma) text_[--start_] = ',';  // reuse the byte before: '[' of the opening
    return text_.substr(start_);
  }

 private:
  std::string text_;
  JsonStream stream_;
  std::size_t start_ = 0;
};

}  // namespace

Json analysis_json_tree(const BSpline& spline, const SplineAnalysis& a, const std::vector<int>& splits) {
  Json doc;
  Json segments = Json::array();
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const Segment& s = spline.segments()[i];
    segments.push_back(segment_json(s, a.segments[i], a.shapes[i], a.judged(s.index)));
  }
  doc["segments"] = std::move(segments);
  Json joints = Json::array();
  const auto joint = [&](const Joint& j) {
    const JointMarks m = joint_marks(a, j, splits);
    Json json = joint_json(j, {std::nullopt, true, m.seam});  // pole and seam marks
    if (m.ignored) json["ignored"] = true;
    joints.push_back(std::move(json));
  };
  for (const Joint& j : a.joints) joint(j);
  if (a.seam) joint(*a.seam);  // a closed spline's seam: joint N
  doc["joints"] = std::move(joints);
  doc["spline"] = verdict_json(a, splits);
  return doc;
}

SplineAnalysis write_analysis_json(std::ostream& out, const BSpline& spline, const AnalyzeOptions& options,
                                   const AnalysisJsonOptions& json) {
  SplineAnalysis a = start_analysis(spline, options);  // throws before anything is written
  const AnalyzeParts parts = default_analyze_parts();
  const bool pretty = json.pretty;
  const int n = spline.segment_count();
  const int chunk = std::max(1, json.chunk);
  const std::size_t chunks = static_cast<std::size_t>((n + chunk - 1) / chunk);
  const int threads = thread_count(json.threads);
  const std::size_t window = json.window > 0 ? static_cast<std::size_t>(json.window) : 4 * static_cast<std::size_t>(threads);
  // A failed write to stdout keeps its errno for the one line main prints.
  const auto write = [&](const std::string& text) {
    write_noting_stdout_error(out, text.data(), static_cast<std::streamsize>(text.size()));
  };
  const auto range_of = [&](std::size_t k, int count) {
    const int first = static_cast<int>(k) * chunk;
    return std::pair<int, int>{first, std::min(count, first + chunk)};
  };

  // Segments: analysed (with the joint before each) and written chunk by chunk.
  write(pretty ? "{\n  \"segments\": [" : "{\"segments\":[");
  parallel_ordered(
      chunks, threads, window,
      [&](std::size_t k) {
        const auto [first, last] = range_of(k, n);
        for (int i = first; i < last; ++i) analyze_span(a, spline, options, parts, i);
        Placed text(pretty, true);
        for (int i = first; i < last; ++i) {
          const Segment& s = spline.segments()[i];
          write_segment(text.stream(), s, a.segments[i], a.shapes[i], a.judged(s.index));
        }
        return text.take(k > 0);
      },
      write);
  write(pretty ? "\n  ]" : "]");  // a spline has at least one segment
  finish_analysis(a, spline, options, parts);  // the seam and the verdicts

  // Joints (every one is known now), formatted in parallel, written in order.
  const int joints = static_cast<int>(a.joints.size()) + (a.seam ? 1 : 0);
  const auto joint_at = [&](int i) -> const Joint& { return i < static_cast<int>(a.joints.size()) ? a.joints[i] : *a.seam; };
  write(pretty ? ",\n  \"joints\": [" : ",\"joints\":[");
  parallel_ordered(
      static_cast<std::size_t>((joints + chunk - 1) / chunk), threads, window,
      [&](std::size_t k) {
        const auto [first, last] = range_of(k, joints);
        Placed text(pretty, true);
        for (int i = first; i < last; ++i) write_joint(text.stream(), a, joint_at(i), options.splits);
        return text.take(k > 0);
      },
      write);
  write(joints == 0 ? "]" : pretty ? "\n  ]" : "]");

  write(pretty ? ",\n  \"spline\": " : ",\"spline\":");
  Placed verdict(pretty, false);
  write_verdict(verdict.stream(), a, options.splits);
  write(verdict.take(false));
  write(pretty ? "\n}\n" : "}\n");
  write_noting_stdout_error(out, nullptr, 0);  // the flush
  return a;
}

Json segments_json(const BSpline& spline) {
  Json segs = Json::array();
  for (const BezierSegment& b : bezier_segments(spline)) {
    Json pts = Json::array();
    for (const Vec2& p : b.points) pts.push_back({p.x, p.y});
    segs.push_back({{"index", b.segment.index}, {"interval", {b.segment.a, b.segment.b}}, {"points", pts}});
    if (!b.weights.empty()) segs.back()["weights"] = b.weights;
  }
  return {{"segments", segs}};
}

}  // namespace cmr::report
