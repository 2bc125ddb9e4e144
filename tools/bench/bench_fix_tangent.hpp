#pragma once
// The tangent line search that `cmr report` offered before the certified fix
// (issue 22), kept here only as the benchmark's baseline (bench_fix.cpp):
// for each gate violation inside a segment, each handle of that segment (a
// control point that is not a node) moved along the line to one of its
// neighbours in steps of 1, 2, 4, ..., 64 grid units, both ways, the moved
// point snapped to the grid; a candidate is kept when the segment alone is
// monotone (Algorithm 1) or free of inflections (no-inflection), and the
// whole spline re-reported has fewer violations, none in that segment, and no
// smooth joint turned into a corner. At most one move per handle, the
// smallest first.
#include <vector>

#include "report/report.hpp"

namespace cmr::bench {

struct TangentMove {
  int point = 0;            ///< control point (distinct index)
  Vec2 from{0.0}, to{0.0};  ///< to is on the grid
  int neighbour = 0;        ///< the point whose line the move follows
};

/// The moves for a judged report (report::judged_report with gates).
std::vector<TangentMove> tangent_line_search(const report::SplineReport& report, const report::ReportOptions& options,
                                             double grid);

}  // namespace cmr::bench
