#pragma once
/// Regression baselines (`cmr report --baseline OLD/report.json`): the
/// findings of this run against those of an accepted one, by stable identity
/// (Finding::key: file, glyph, contour, node, gate). Keys are counted, so
/// two equal findings (two dips in one segment) are two: a third is new.
#include <map>
#include <string>
#include <vector>

#include "report/corpus.hpp"

namespace cmr::report {

class BaselineComparison {
 public:
  explicit BaselineComparison(const std::vector<std::string>& keys);
  /// "unchanged" when the baseline has this key left (and takes it), else "new".
  const char* judge(const Finding& f);
  /// Baseline findings not seen (so far): fixed.
  int fixed() const;

 private:
  std::map<std::string, int> left_;
};

}  // namespace cmr::report
