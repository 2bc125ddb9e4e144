#pragma once
/// `cmr analyze`'s JSON document (docs/outputs.md): {"segments": [...],
/// "joints": [...], "spline": {verdicts}}, compact on one line or indented
/// by 2, one trailing newline.
///
/// write_analysis_json streams it (issue 23 item 4): the spans are analysed
/// on every available core in chunks (start_analysis / analyze_span /
/// finish_analysis, bezierize/analyze.hpp), each chunk's JSON text is
/// formatted by the thread that analysed it (JsonStream, json_stream.hpp:
/// no JSON tree), and the chunks are written in order as they complete
/// (parallel_ordered, spline/parallel.hpp). Memory is the spline, the
/// compact per-span results the verdicts need (about 150 bytes a span) and
/// a bounded window of chunk texts; never the document. The text is byte
/// for byte json_text of analysis_json_tree(spline, analyze(spline,
/// options), options.splits), whatever the thread count and chunk size
/// (tests/report/analyze_json_test.cpp).
#include <ostream>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/analyze.hpp"
#include "bezierize/joint_json.hpp"
#include "bezierize/segments.hpp"
#include "spline/bspline.hpp"

namespace cmr::report {

struct AnalysisJsonOptions {
  bool pretty = false;  ///< indented by 2 (--pretty); else compact, one line
  int threads = 0;      ///< analysis threads; 0: every available core (CPU affinity)
  int chunk = 2048;     ///< spans per job (>= 1)
  int window = 0;       ///< chunk texts that may wait unwritten; 0: 4 per thread
};

/// analyze(spline, options), its document written to `out` as above.
/// Options are validated (InputError, analyze's messages) before anything
/// is written. Returns the analysis.
SplineAnalysis write_analysis_json(std::ostream& out, const BSpline& spline, const AnalyzeOptions& options,
                                   const AnalysisJsonOptions& json = {});

/// The same document from a finished analysis, written into any writer with
/// JsonStream's interface (begin_object, key, value, member, ...): the
/// Python module builds its dict with it (python/cmr_module.cpp), with no
/// tree and no text in between. The members are the stream's own
/// (write_segment, write_joint, write_verdict below), so the dict, the
/// streamed text and the tree below cannot drift apart
/// (tests/report/analyze_json_test.cpp).
template <class Out>
void write_analysis_document(Out& out, const BSpline& spline, const SplineAnalysis& a, const std::vector<int>& splits);

/// The same document as one nlohmann tree from a finished analysis (splits:
/// AnalyzeOptions::splits): the reference the stream is tested against.
nlohmann::ordered_json analysis_json_tree(const BSpline& spline, const SplineAnalysis& a,
                                          const std::vector<int>& splits);

/// `cmr segments`' document: {"segments": [{"index", "interval", "points",
/// "weights" (rational only)}]}, every non-empty span in Bezier form.
nlohmann::ordered_json segments_json(const BSpline& spline);

// ------------------------------------------------------------ the members

/// A joint's marks in analyze's document: the seam mark, and "ignored" on a
/// joint outside the judged range (the seam is judged with the whole period
/// and no split joints).
struct JointMarks {
  bool seam = false;
  bool ignored = false;
};
JointMarks joint_marks(const SplineAnalysis& a, const Joint& j, const std::vector<int>& splits);

/// One element of "segments"; `judged`: inside --segments (else "ignored").
template <class Out>
void write_segment(Out& o, const Segment& s, const SegmentClass& c, const SegmentShape& sh, bool judged) {
  o.begin_object();
  o.member("index", s.index);
  o.key("interval");
  o.begin_array();
  o.value(s.a);
  o.value(s.b);
  o.end_array();
  if (!judged) {
    o.member("curvature", "ignored");
    o.member("inflection", "ignored");
    o.end_object();
    return;
  }
  o.member("class", shape_class(sh));
  o.member("curvature", to_string(c.monotonicity.curvature));
  o.member("inflection", to_string(sh.inflection));
  o.member("zero_curvature_at", kappa_zero_at(sh));
  o.member("algorithm2", to_string(c.inflection.inflection));
  o.member("depth", c.monotonicity.depth);
  o.member("inflection_depth", c.inflection.depth);
  o.member("exact", c.exact_used);
  if (sh.pole) {  // W = 0 there: the curve passes through infinity
    o.key("poles");
    o.begin_array();
    for (const double t : sh.poles) o.value(t);
    o.end_array();
  }
  o.end_object();
}

/// One element of "joints": joint_json's members and analyze's marks.
template <class Out>
void write_joint(Out& o, const SplineAnalysis& a, const Joint& j, const std::vector<int>& splits) {
  const JointMarks m = joint_marks(a, j, splits);
  o.begin_object();
  write_joint_members(o, j, {std::nullopt, true, m.seam});  // pole and seam marks
  if (m.ignored) o.member("ignored", true);
  o.end_object();
}

/// "spline": the verdicts.
template <class Out>
void write_verdict(Out& o, const SplineAnalysis& a, const std::vector<int>& splits) {
  o.begin_object();
  o.member("cmrwi", to_string(a.cmrwi));
  o.member("cmr", to_string(a.cmr));
  o.member("cmr_algorithm2", to_string(a.cmr_algorithm2));
  o.member("cusp", a.cusp);
  if (a.pole) o.member("pole", true);
  if (a.split) o.member("split", to_string(*a.split));
  if (a.alternation || a.each_piece) {
    // --split S1,S2,... (alternation) or --each-piece (each group on its own:
    // monotone in either direction): the groups between the cut joints.
    if (a.alternation) o.member("alternation", to_string(*a.alternation));
    else o.member("each_piece", to_string(*a.each_piece));
    o.key("groups");
    o.begin_array();
    const auto parts = segment_groups(a.range, a.alternation ? splits : a.cuts);
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
      o.begin_object();
      o.key("segments");
      o.begin_array();
      o.value(parts[g].first);
      o.value(parts[g].second - 1);
      o.end_array();
      o.member("direction", to_string(a.groups[g]));
      o.end_object();
    }
    o.end_array();
  }
  if (a.range != SegmentRange{0, static_cast<int>(a.segments.size()) - 1}) {
    o.key("segments");
    o.begin_array();
    o.value(a.range.first);
    o.value(a.range.last);
    o.end_array();
  }
  if (!a.joint_conflicts.empty()) {
    o.key("joint_conflicts");
    o.begin_array();
    for (const int j : a.joint_conflicts) o.value(j);
    o.end_array();
  }
  o.end_object();
}

template <class Out>
void write_analysis_document(Out& o, const BSpline& spline, const SplineAnalysis& a, const std::vector<int>& splits) {
  o.begin_object();
  o.key("segments");
  o.begin_array();
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const Segment& s = spline.segments()[i];
    write_segment(o, s, a.segments[i], a.shapes[i], a.judged(s.index));
  }
  o.end_array();
  o.key("joints");
  o.begin_array();
  for (const Joint& j : a.joints) write_joint(o, a, j, splits);
  if (a.seam) write_joint(o, a, *a.seam, splits);  // a closed spline's seam: joint N
  o.end_array();
  o.key("spline");
  write_verdict(o, a, splits);
  o.end_object();
}

}  // namespace cmr::report
