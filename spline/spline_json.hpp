#pragma once
// Spline files: {"degree": d, "knots": [...], "points": [[x,y],...], "name": "optional",
//                "weights": [w0, ...] (optional: a rational curve, one finite weight per point, not all 0; bspline.hpp)}.
// Without "knots" the file is one Bezier curve of degree points-1 ("degree",
// if given, must agree). Knots are polar-form (points + degree - 1 of them).
// Every error is an InputError whose message names the file, the field and
// the index ("spline.json: points[2][1] is not a number").
//
// Closed splines (BSpline::make_closed): "closed": true, "degree" required,
// "points" the m distinct control points and "knots" the m+1 knots of one
// period (uniform 0..m when absent). "point_names" (optional, one string per
// point: the importers' node names such as "A/c0/p3") is checked and not kept.
//
// A conventional (full, non-polar) knot vector has points + degree + 1 knots:
// its first and last knots do not influence the curve, and dropping them gives
// the polar form. Such a file is recognised and refused with that advice
// unless ReadOptions::conventional is set, in which case the two are dropped.
#include <filesystem>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "spline/bspline.hpp"

namespace cmr {

/// How spline files are read.
struct ReadOptions {
  /// The file's "knots" are the conventional (full) vector of points + degree
  /// + 1 values; its first and last are dropped. Any other count is an error.
  /// (A file without "knots", one Bezier curve, is read as usual.)
  bool conventional = false;
};

BSpline spline_from_json(const nlohmann::json& doc, const ReadOptions& options = {});
/// Reads and validates a spline file (through read_input_file); messages are
/// prefixed with the path.
BSpline read_spline_file(const std::filesystem::path& path, const ReadOptions& options = {});
/// read_spline_file in two steps, for a caller that looks at the document
/// first (cmr analyze: its dimension) without parsing it twice: the file's
/// JSON with read_spline_file's reading and parse errors, then
/// spline_from_json with messages prefixed with the path.
/// Out of memory while parsing is std::bad_alloc (never an abort: the
/// partial document is torn down with release_json).
nlohmann::json read_spline_document(const std::filesystem::path& path);
/// Empties `doc` without allocating (children first, from the last), so that
/// a large document can be destroyed while memory is exhausted:
/// nlohmann::json's destructor allocates a stack as large as the largest
/// array, and a std::bad_alloc there, inside a noexcept destructor, aborts
/// the process (issue 42: cmr analyze of 10^6 knots under `ulimit -v`).
void release_json(nlohmann::json& doc) noexcept;
/// Calls release_json on the document when it goes out of scope (also while
/// an exception unwinds).
class JsonReleaser {
 public:
  explicit JsonReleaser(nlohmann::json& doc) : doc_(&doc) {}
  JsonReleaser(const JsonReleaser&) = delete;
  JsonReleaser& operator=(const JsonReleaser&) = delete;
  ~JsonReleaser() { release_json(*doc_); }

 private:
  nlohmann::json* doc_;
};
BSpline spline_from_document(const nlohmann::json& doc, const std::filesystem::path& path,
                             const ReadOptions& options = {});
/// The spline as a file's JSON. (Writing a file: cmr::write_spline_file in
/// io/output.hpp, atomically.)
nlohmann::json spline_to_json(const BSpline& spline);

/// The path that names standard input: every command that reads a spline,
/// points or script file reads standard input when given "-".
inline constexpr const char* kStdinPath = "-";
/// How messages name an input: "stdin" for "-", else the path.
std::string input_name(const std::filesystem::path& path);
/// Called by cmr's main when file descriptor 0 was closed at start (it then
/// holds /dev/null, so that no file cmr opens lands there): reading "-"
/// says "stdin: closed".
void note_stdin_closed() noexcept;
/// Forgets what standard input held (read_input_file keeps it) and that it
/// was closed, so that the next read of "-" reads descriptor 0 again: for a
/// process that reads one standard input after another (fuzz/fuzz_stdin.cpp),
/// never cmr itself.
void forget_stdin() noexcept;

/// The whole content of an input file (spline, points, script), read safely:
/// opened with O_NONBLOCK, so that a FIFO with no writer cannot hang the
/// open; then fstat must show a regular file or a FIFO (a device such as
/// /dev/zero, a folder or a socket is refused at once, before any read);
/// and at most kMaxInputBytes are read (a larger or growing file or stream
/// is refused, after reading at most one byte past the limit).
/// A FIFO (a pipe reached through /dev/stdin or /dev/fd/N, or mkfifo's) is
/// read until no writer holds it; one that gives nothing (no writer, or a
/// writer that closed it at once) is "PATH: empty (...)", at once.
/// "-" reads standard input (kStdinPath): a pipe, a file, a socket or a
/// device such as /dev/null, not a terminal or a folder; empty or closed is
/// one line ("stdin: empty (nothing to read)", "stdin: closed (...)"). It is
/// read once per process and kept: reading "-" again gives the same text.
/// Throws InputError "PATH: cannot open the file (<strerror>)", "PATH: not a
/// regular file (a character device)", "PATH: larger than the 64 MiB input
/// limit", ... (PATH as input_name writes it).
std::string read_input_file(const std::filesystem::path& path);

}  // namespace cmr
