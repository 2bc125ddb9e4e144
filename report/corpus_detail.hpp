#pragma once
// Internal to cmr::report: what a corpus run (corpus.cpp) and its inputs
// (corpus_inputs.cpp) share.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "io/svg.hpp"
#include "report/batch.hpp"
#include "report/corpus.hpp"
#include "report/font_report.hpp"
#include "report/report_cache.hpp"

namespace cmr::report::corpus_detail {

/// A file's reports while they are written (then dropped).
struct FileWork {
  std::string path;
  std::string name;  ///< its findings' file name (source_name)
  std::string uri;   ///< its SARIF artifact URI (source_uri)
  bool uri_relative = false;
  FileKind kind = FileKind::spline;
  std::optional<FontInfo> font;
  std::vector<SplineReport> reports;
  double seconds = 0;
  /// The resume cache (a font): per glyph its key, and what the cache had
  /// of it (then its items were not judged: their reports are empty);
  /// `store`: the glyphs judged here are complete and go into the new cache.
  std::vector<CacheKey> keys;
  std::vector<std::optional<CachedGlyph>> cached;
  bool store = false, store_failing = false;
};

/// What a run's resume cache needs while files are processed.
struct CacheContext {
  const ReportCache* old = nullptr;  ///< the previous run's (may be unusable: nothing found)
  std::string run_prefix;           ///< run_key_prefix
};

struct ItemNames {
  std::string glyph;
  int contour = 0;
  const std::vector<std::string>* joints = nullptr;  ///< font: node starting each segment
  const std::vector<std::string>* points = nullptr;  ///< font: each control point's name
  const std::string* source = nullptr;                ///< font source: the glyph's .glif
  const std::vector<int>* point_lines = nullptr;      ///< font source: each control point's <point> line
  const std::vector<int>* joint_lines = nullptr;      ///< font source: each segment's starting node's line
};

// Defined in corpus_inputs.cpp:
std::vector<ReportInput> svg_inputs(const std::string& path, const std::vector<import::PathSpline>& paths,
                                    std::size_t begin, std::size_t end);
/// Processes w.path (w.name and w.uri set) into `w`.
void process_file(FileWork& w, std::size_t index, const BatchOptions& options, int threads, FixBudget* budget,
                  const CacheContext* cache);
std::vector<Finding> findings_of(const SplineReport& r, const std::string& file, const ItemNames& n,
                                 const ReportOptions& options);

}  // namespace cmr::report::corpus_detail
