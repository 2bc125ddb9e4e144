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

/// The same document as one nlohmann tree from a finished analysis (splits:
/// AnalyzeOptions::splits): the reference the stream is tested against.
nlohmann::ordered_json analysis_json_tree(const BSpline& spline, const SplineAnalysis& a,
                                          const std::vector<int>& splits);

/// `cmr segments`' document: {"segments": [{"index", "interval", "points",
/// "weights" (rational only)}]}, every non-empty span in Bezier form.
nlohmann::ordered_json segments_json(const BSpline& spline);

}  // namespace cmr::report
