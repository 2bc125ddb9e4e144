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

/// A finding's file is matched to the baseline's by how the run named it,
/// and where the baseline has no finding of that name, by the one baseline
/// file whose name ends in the same path components (or whose components
/// end its name): a file given by itself is named relative to the working
/// folder, so `cmr report /abs/repo/Sans.ufo` run in /home names it
/// "../abs/repo/Sans.ufo", and `cmr report Sans.ufo` run in /abs/repo
/// "Sans.ufo"; both are the same file. Where several baseline files match,
/// none is taken (its findings are new).
class BaselineComparison {
 public:
  explicit BaselineComparison(const std::vector<std::string>& keys);
  /// "unchanged" when the baseline has this key left (and takes it), else "new".
  const char* judge(const Finding& f);
  /// Baseline findings not seen (so far): fixed.
  int fixed() const;

 private:
  /// The baseline's name for the run's file `file` ("" where none).
  const std::string& baseline_file(const std::string& file);
  std::map<std::string, int> left_;
  std::map<std::string, std::string> file_of_;  ///< the run's file name -> the baseline's
  std::vector<std::string> files_;              ///< the baseline's file names
};

}  // namespace cmr::report
