#pragma once
/// Spline QA at corpus scale (`cmr report FOLDER|GLOB|FILE...`): the files
/// of a run are found (folders walked recursively, globs expanded, include
/// and exclude patterns), reported one file at a time (files in parallel on
/// every core when there are enough of them, else one file's splines in
/// parallel), and written as they finish: report.json, the pages, a JUnit
/// XML and a SARIF 2.1.0 file, each streamed, so that memory holds the
/// reports of the files in flight, never the corpus (what stays is one
/// small record per file for the summary page, and the new findings).
///
/// A *finding* is one violation with a stable identity (file, glyph,
/// contour, node, gate): the key a baseline (an earlier run's report.json)
/// is compared by. docs/report.md describes the workflow.
///
/// Errors: InputError for an argument that names nothing, a pattern that
/// matches no file, a baseline that is not a cmr report; EnvironmentError
/// when an output cannot be written (nothing of the run is then left).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "report/batch.hpp"
#include "report/font_report.hpp"
#include "report/merge.hpp"
#include "report/report.hpp"

namespace cmr::report {

/// The default of `cmr report --time-limit` (seconds).
inline constexpr double kDefaultReportTimeLimit = 3600;

/// Which files a folder contributes (a file named on the command line is
/// always taken). Patterns are shell globs (fnmatch), matched against the
/// path relative to the folder and against the file name; `**` is `*`.
struct FileFilter {
  std::vector<std::string> include;  ///< empty: every font, .svg and .json file
  std::vector<std::string> exclude;  ///< a file matching one is left out
};

/// What a folder walk left out, and why: the run's own output folder, a
/// cmr output ("a cmr report (report.json of an earlier run)"), a JSON that
/// is not a spline file, an unreadable folder, a FIFO, a socket or device, a
/// dangling or looping link, a link to a folder (not followed).
struct SkippedPath {
  std::string path, reason;
};

/// The files of `args`, in argument order (a folder's files sorted): a file
/// as it is; a folder walked recursively (hidden entries skipped); an
/// argument with * ? or [ that names no file, expanded as a glob (sorted; a
/// folder it matches walked as a folder). With `bases`, each file's folder
/// argument (the folder walked; "" for a file named or globbed) is
/// appended to it, one per file: BatchOptions::bases. What a walk leaves out
/// is appended to `skipped` (when given) with its reason; a file named as an
/// argument is always taken. A walk never enters the folders `skip_folders`
/// (the run's own output folder, `--out`), matched by identity (device and
/// inode). InputError: "ARG: no such file or folder", "ARG: matches no file".
std::vector<std::string> collect_files(const std::vector<std::string>& args, const FileFilter& filter,
                                       std::vector<std::string>* bases = nullptr,
                                       std::vector<SkippedPath>* skipped = nullptr,
                                       const std::vector<std::filesystem::path>& skip_folders = {});

/// collect_files for a report's run: with an interpolation gate
/// (`whole_designspaces`) each .designspace argument is one file (its
/// masters judged together), after the other arguments' files, rather than
/// walked into its sources (each master a font of its own).
std::vector<std::string> collect_run_files(const std::vector<std::string>& args, const FileFilter& filter,
                                           bool whole_designspaces, std::vector<std::string>* bases,
                                           std::vector<SkippedPath>* skipped,
                                           const std::vector<std::filesystem::path>& skip_folders = {});

/// The name a run gives `file` in its findings (Finding::file, and so in a
/// baseline's keys): its path relative to the folder `base` ("" is the
/// working folder), '/'-separated, whatever the spelling: `/abs/in/a.ttf`,
/// `in/a.ttf` and `./in//a.ttf` against `in` (or `/abs/in`) are all `a.ttf`.
/// Both are made absolute with the symbolic links of their folders
/// resolved (a font that is itself a link keeps its own name). A file
/// outside `base` gets a name with `..`.
std::string source_name(const std::string& file, const std::string& base);
/// The SARIF artifact URI of `file` relative to the folder `root` ("" is the
/// working folder): a percent-encoded relative reference when the file lies
/// under `root` (SARIF's uriBaseId SRCROOT), else an absolute file:// URI;
/// `relative` says which.
std::string source_uri(const std::string& file, const std::string& root, bool* relative = nullptr);

enum class FileKind : std::uint8_t { spline, svg, font };
/// By extension: fonts (io/font.hpp) and font sources (.ufo, .glif: io/ufo.hpp), .svg, else a spline file.
FileKind file_kind(const std::string& path);

/// One violation with its stable identity.
struct Finding {
  std::string file;     ///< the input file's name: relative to its folder argument or the source root (source_name)
  std::string glyph;    ///< glyph name (fonts), else the spline's name
  int contour = 0;      ///< contour of the glyph (0 for a spline)
  std::string node;     ///< "p12" (a node), "p12-p15" (the segment between two nodes), "segment 3", "joint 2"; "" for the whole spline
  std::string gate;     ///< the gate's text ("curvature-extrema-at-nodes"), or the check ("cmr") for a spline failing it
  std::string message;  ///< one line a designer can act on (node names, what to move)
  /// Font sources: the .glif the finding lies in and the line of the <point>
  /// it names (the node, or the first handle to move); "" and 0 otherwise.
  std::string source{};
  int line = 0;
  /// The smallest certified move that removes it (report/severity.hpp); -1
  /// when not computed, +inf when none was found; `info`: below the run's
  /// --min-severity, so it does not fail.
  double severity = -1;
  bool info = false;
  /// Severity +inf: why ("no allowed move": none of the finding's points
  /// may move, report/contour_moves.hpp; "none found": the search found
  /// none in its limits); "" otherwise.
  std::string severity_note{};
  /// "file|glyph|cC|node|gate": what a baseline compares.
  std::string key() const;
};

/// One test case of a run: a glyph (all its contours) or a spline.
struct CaseRecord {
  std::string name;       ///< glyph or spline name
  std::string error;      ///< invalid input: why
  int contours = 1;
  bool pass = true;
  std::vector<Finding> findings;
};

/// What the summary page and the CI files keep of one file.
struct FileRecord {
  std::string path;
  FileKind kind = FileKind::spline;
  std::string title;      ///< "DejaVu Sans Book" for a font, else the path
  std::string page;       ///< its page, relative to the output folder ("" when none)
  double seconds = 0;     ///< analysis time
  int items = 0, items_pass = 0, items_fail = 0, items_invalid = 0;  ///< splines / contours
  std::vector<CaseRecord> cases;  ///< glyphs or splines (dropped after the file is written, see FileSummary)
};

/// How a batch runs and what it writes.
struct BatchOptions {
  ReportOptions report;                 ///< per spline (report.hpp); report.threads: 0 = every core
  std::vector<std::uint32_t> codepoints;  ///< the glyphs of the fonts
  bool all_glyphs = false;              ///< every glyph of a font source (UFO), whatever its code points
  import::Location location;            ///< a variable font's instance (binary fonts; io/font.hpp)
  /// --between LOC1:LOC2: the segment the interpolation gates judge
  /// (io/masters.hpp); none: the pieces along every axis.
  std::optional<std::pair<import::Location, import::Location>> between{};
  std::filesystem::path out;            ///< report.json, index.html, the pages
  std::optional<std::filesystem::path> junit, sarif;  ///< CI files
  std::optional<std::filesystem::path> baseline;      ///< an earlier report.json
  /// Per file of the run (collect_files' bases): the folder its findings'
  /// file name is taken relative to ("", or no entry: the working folder),
  /// so that a baseline does not depend on how a path was spelled.
  std::vector<std::string> bases;
  /// --source-root: every finding's file name, and SARIF's artifact URIs,
  /// relative to this folder (instead of the folder given; SARIF's default
  /// root is the working folder).
  std::optional<std::filesystem::path> source_root;
  /// --markdown: a GitHub-flavoured Markdown summary (report/markdown.hpp).
  std::optional<std::filesystem::path> markdown;
  /// The Markdown summary's size limit in bytes (a GitHub comment takes
  /// 65,536 characters); tests set a small one.
  std::size_t markdown_limit = 65536;
  bool pretty = false;                  ///< indent report.json
  /// Search the certified fixes of the failing contours of fonts (with
  /// report.regions, report/certified_fix.hpp); off: thumbnails without fixes.
  bool fixes = true;
  /// What the folder walks left out (collect_files): listed in report.json
  /// ("skipped") and on the page; they do not change the exit code.
  std::vector<SkippedPath> skipped;
  /// --shard (report/merge.hpp): with it, `shard_positions` gives each
  /// file's position in the whole collected list (keep_shard); a font keeps
  /// its glyphs j with position + j in the shard, and a file is counted
  /// (and an unreadable font's invalid item given) only by the part that
  /// owns its position.
  std::optional<Shard> shard;
  std::vector<std::size_t> shard_positions;
  /// Seconds for all fix searches of the run (report/batch.hpp FixBudget;
  /// <= 0: no limit): after them failing splines are reported without fixes.
  double fix_budget = kDefaultFixBudgetSeconds;
  /// The run's time limit in seconds (<= 0: none): checked before each file
  /// and each part of a file; past it the run stops with InputError and
  /// writes nothing.
  double time_limit = kDefaultReportTimeLimit;
  /// The resume cache (report/report_cache.hpp): a font's glyph whose key
  /// is in OUT/report.cache is not judged again, and the run writes its
  /// own cache with its outputs. Off (--no-cache): none read or written.
  bool cache = true;
};

/// The run's counts (the one-line summary) and its exit code.
struct BatchSummary {
  int files = 0, fonts = 0, glyphs = 0, glyphs_fail = 0;
  int items = 0, pass = 0, fail = 0, invalid = 0;  ///< splines and contours
  int findings = 0;
  bool baseline = false;
  int new_findings = 0, fixed = 0, unchanged = 0;  ///< with a baseline
  std::vector<Finding> new_list;  ///< the new findings (with a baseline)
  std::vector<std::string> invalid_messages;  ///< one per invalid item
  double seconds = 0;
  int exit_code = kExitPass;  ///< kExitInvalid, else kExitFail on a failure (on a new finding with a baseline), else kExitPass
  std::vector<std::filesystem::path> written;
  /// What the run's budgets left out (FixBudget::note), "" when nothing.
  std::string note;
  /// The resume cache: fonts' glyphs taken from it and judged; whether a
  /// cache was read; a note when it was ignored or damaged ("" otherwise).
  int glyphs_reused = 0, glyphs_judged = 0;
  bool cache_read = false;
  std::string cache_note;
};

/// "3 files (1 font, 52 glyphs): 70 contours and splines: 25 pass, 45 fail, 0 invalid; 61 findings (new 1,
/// fixed 0, unchanged 60); 2.1 s": the run's one line.
std::string summary_line(const BatchSummary& s);

/// Called after each file is written: (files done, files in all, splines
/// done, the file).
using BatchProgress = std::function<void(int, int, int, const std::string&)>;
/// The fonts' glyphs, instance and design-space segment of a batch as `cmr
/// report --glyphs SPEC [--location TAG=V,...] [--between LOC1:LOC2]` (and
/// the Python module's report) give them: `location` empty for the default
/// instance, `between` empty for the pieces between adjacent masters.
/// InputFieldError for a location given with a file that is not a font,
/// and for a segment without an interpolation gate among `checks`' gates.
void select_font_inputs(BatchOptions& batch, const ReportOptions& checks, const std::string& glyphs,
                        const std::string& location, const std::string& between,
                        const std::vector<std::string>& files);

/// A progress bar with ETA drawn in place on `err` (a terminal's stderr):
/// "[#####-----] 12/40 files, 3,210 splines, 1,870/s, ETA 0:12 name".
BatchProgress terminal_progress(std::ostream& err);
/// Clears the bar's line.
void clear_progress(std::ostream& err);

/// The findings of a baseline (report.json of an earlier run): key ->
/// count. InputError when it cannot be read or is not a cmr-report/2 with
/// findings.
std::vector<std::string> read_baseline(const std::filesystem::path& path);

/// Runs the batch and writes every output as one cmr::OutputSet (all or
/// none). Invalid files become invalid items; they do not stop the run.
BatchSummary run_batch(const std::vector<std::string>& files, const BatchOptions& options,
                       const BatchProgress& progress = {});

}  // namespace cmr::report
