#pragma once
/// A run's summary as GitHub-flavoured Markdown (`cmr report --markdown
/// FILE`), for a pull request's comment: a heading with the verdict, the
/// run's one line, the baseline's new / fixed / unchanged counts, a table
/// with one row per font (one for all the spline and SVG files) giving the
/// glyphs (splines) that pass and fail and how many fail each gate, then the
/// new findings (with a baseline) and the failing glyphs and splines in
/// collapsible <details> blocks, one per file.
///
/// Size: a GitHub comment takes at most 65,536 characters. The summary
/// stays below `limit` bytes (so below as many characters): what does not
/// fit is left out from the end and counted in one last line ("… 812 more
/// failing glyphs and splines not shown …"). Memory is bounded by the limit
/// too: add() keeps a file's lines only while the kept text is below it.
///
/// Text from the inputs (glyph names, messages, file names) is escaped, so
/// that it is shown as it is and cannot open a tag or a table cell.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "report/corpus.hpp"

namespace cmr::report {

/// The default limit: GitHub's limit of a comment, 65,536 characters.
inline constexpr std::size_t kMarkdownLimit = 65536;
/// The smallest limit a summary takes (its heading, table head and last line fit).
inline constexpr std::size_t kMarkdownMinLimit = 2048;

/// Text shown as it is in Markdown (and inside HTML blocks): & < > as
/// entities, Markdown's punctuation (\ ` * _ [ ] | ~ #) escaped with '\',
/// line breaks as spaces.
std::string markdown_escape(const std::string& text);

class MarkdownSummary {
 public:
  /// `options`: the run's check and gates (the table's columns); `limit`:
  /// the size bound in bytes (at least kMarkdownMinLimit is used).
  MarkdownSummary(const ReportOptions& options, std::size_t limit = kMarkdownLimit);

  /// One file of the run, in run order: `name` its findings' file name,
  /// `title` a font's family and style ("" otherwise).
  void add(const FileRecord& file, const std::string& name, const std::string& title);

  /// The document (fewer than limit bytes). `baseline`: the file compared
  /// with (empty without one).
  std::string finish(const BatchSummary& summary, const std::string& baseline) const;

 private:
  struct Row {
    std::string label;  ///< the file (a font), or "N spline and SVG files"
    bool font = false;
    int files = 0, cases = 0, pass = 0, fail = 0, invalid = 0;
    std::vector<int> column_fail;  ///< per column (the check, then each gate): cases failing it
  };
  struct Item {
    int block = -1;    ///< index into blocks_
    std::string line;  ///< one failing glyph or spline
  };
  void add_row(Row& row, const FileRecord& file) const;

  std::vector<std::string> columns_;  ///< the check (when required), then each gate
  /// The checks `cmr fix` can fix by moving points (fixable_require), and how
  /// the run names its fields (the command a failing font source's block shows).
  std::string fix_require_;
  std::string fix_severity_;  ///< " --strict" or " --min-severity U" where the run differs from the default
  std::vector<std::string> fixable_;
  std::function<std::string(const std::string&)> show_fields_;
  std::size_t limit_;
  std::vector<Row> fonts_;
  Row others_;
  std::vector<std::string> blocks_;  ///< per file with kept items: its <summary> text
  std::vector<Item> items_;          ///< kept failing cases
  std::size_t kept_bytes_ = 0;
  int failing_ = 0;  ///< failing and invalid cases in all (kept or not)
};

}  // namespace cmr::report
