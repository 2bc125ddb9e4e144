#pragma once
/// Large collections: `cmr report ... --shard i/N` runs one part of a run,
/// `cmr report --merge DIR... --out DIR` combines the parts' outputs into one
/// report without judging anything again (docs/report.md, "Large
/// collections"). No scheduler: xargs -P, GNU parallel or a Slurm array run
/// the parts.
///
/// Sharding. The run's inputs are collected and expanded as usual
/// (collect_files: arguments in order, each folder walked and sorted, each
/// glob's matches sorted: an order that does not depend on the file
/// system's). The items are that list's files, a font's (or UFO's) glyphs
/// each an item of their own: glyph j (in the order of --glyphs, or the
/// font's for all) of the file at position k (0-based) is item k + j, any
/// other file item k; item k belongs to shard i of N when k mod N = i - 1.
/// So the N shards are disjoint, together they are the whole run, and a
/// font's glyphs are spread over all the shards. Every part reads each
/// font (cheap beside judging it) and judges only its own glyphs; the file
/// itself is counted by the part that owns position k.
///
/// Merging. report.json: the parts' "splines" concatenated in part order,
/// their ids renumbered s0, s1, ...; "skipped" the union (by path); the
/// summary counts (splines, pass, fail, invalid, files, findings; a
/// baseline's new and unchanged) summed and the exit code that of a run
/// with those counts (2 when a part had an invalid input, else 1 when one
/// failed, else 0). Parts whose schema or settings (gates, check, options)
/// differ are refused. JUnit: the parts' test suites, renumbered. SARIF:
/// the results of the parts' one run concatenated (refused when their tool
/// or rules differ). Markdown: one heading with the merged line, then each
/// part's summary. index.html: the merged summary and a link to each part's
/// own page; each part's folder is copied under DIR/parts/NAME, so that DIR
/// stands alone. Everything is written as one OutputSet (all or none).
///
/// Errors: InputError (exit 2, one line) for a part without report.json, a
/// report.json that is not a cmr report, parts that differ, a CI file asked
/// for that a part does not have, the output folder among the parts.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cmr::report {

/// `--shard i/N`: 1 <= index <= count.
struct Shard {
  int index = 1, count = 1;
  /// Whether item `k` (0-based, in collection order) belongs to this shard.
  bool takes(std::size_t k) const { return static_cast<int>(k % static_cast<std::size_t>(count)) == index - 1; }
};

/// Parses "i/N" (decimal, 1 <= i <= N). InputError "--shard TEXT: ..." otherwise.
Shard parse_shard(const std::string& text);

/// Keeps the files of `files` (and the parallel `bases`, when as long) that
/// hold items of `shard` (a file whose position it owns; every font), in
/// their order; returns the kept files' positions in the whole list
/// (BatchOptions::shard_positions).
std::vector<std::size_t> keep_shard(const Shard& shard, std::vector<std::string>& files, std::vector<std::string>& bases);

/// Keeps the glyphs of the font at `position` that belong to `shard`
/// (glyph j is item position + j), in their order.
template <class Glyph>
void keep_shard_glyphs(const Shard& shard, std::size_t position, std::vector<Glyph>& glyphs) {
  std::size_t kept = 0;
  for (std::size_t j = 0; j < glyphs.size(); ++j)
    if (shard.takes(position + j)) {
      if (kept != j) glyphs[kept] = std::move(glyphs[j]);
      ++kept;
    }
  glyphs.erase(glyphs.begin() + static_cast<std::ptrdiff_t>(kept), glyphs.end());
}

struct MergeOptions {
  std::vector<std::filesystem::path> parts;  ///< each a report folder (report.json, index.html)
  std::filesystem::path out;
  /// CI files to write: each is merged from the file of the same name in
  /// each part's folder (`--junit junit.xml`: DIR1/junit.xml, DIR2/junit.xml).
  std::optional<std::filesystem::path> junit, sarif, markdown;
  bool pretty = false;
  /// The parts are one run's planar and space inputs (`cmr report` given
  /// both): their settings may differ (a space report has none).
  bool mixed = false;
};

struct MergeSummary {
  int parts = 0, files = 0, splines = 0, pass = 0, fail = 0, invalid = 0, findings = 0;
  int exit_code = 0;
  std::string line;  ///< "merged 2 parts: 5 files: ..."
};

/// Merges the parts (see the file comment) and commits every output at once.
MergeSummary merge_reports(const MergeOptions& options);

}  // namespace cmr::report
