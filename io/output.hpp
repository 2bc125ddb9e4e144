#pragma once
/// Output helpers shared by the cmr libraries and the command: the output
/// path check, the one atomic file writer, and HTML escaping (the error
/// types are in spline/errors.hpp).
/// Nothing here depends on the command line (CLI11).
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "spline/bspline.hpp"
#include "spline/errors.hpp"

namespace cmr {

/// Throws InputError unless `path`'s folder exists and `path` is no folder
/// (checked before any work, so that a bad output path fails fast):
/// "OPTION PATH: the folder F does not exist", "OPTION PATH: is a directory".
void check_output_path(const std::filesystem::path& path, const std::string& option);

/// How many temporary names write_file_atomic tries before it gives up.
inline constexpr int kTempNameAttempts = 100;

/// The temporary name write_file_atomic tries on its `attempt`-th try for
/// `path`: a hidden file beside it, ".NAME.PID-ATTEMPT.tmp", so that the
/// rename stays inside one file system. The name is only a proposal: it is
/// created with O_CREAT | O_EXCL | O_NOFOLLOW, so a file or a symbolic link
/// already there (another process, an attacker) is skipped, never opened.
std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt);

class OutputSet;

/// A file of an OutputSet written in pieces (a report too large to hold in
/// memory): OutputSet::stage_stream opens its temporary; write() appends;
/// close() flushes it to disk (fsync). Close every stream before commit().
/// Errors as OutputSet::stage (EnvironmentError "PATH: <strerror>").
class StagedStream {
 public:
  StagedStream() = default;
  StagedStream(const StagedStream&) = delete;
  StagedStream& operator=(const StagedStream&) = delete;
  StagedStream(StagedStream&& o) noexcept : path_(std::move(o.path_)), fd_(o.fd_) { o.fd_ = -1; }
  StagedStream& operator=(StagedStream&& o) noexcept;
  ~StagedStream();
  void write(std::string_view bytes);
  void close();
  bool is_open() const { return fd_ >= 0; }

 private:
  friend class OutputSet;
  StagedStream(std::filesystem::path path, int fd) : path_(std::move(path)), fd_(fd) {}
  std::filesystem::path path_;
  int fd_ = -1;
};

/// Output files committed together: all of them, or none.
///
/// stage() writes each file's bytes to its own new temporary file beside it
/// (see temp_name_for) and flushes it to disk (fsync); nothing a user sees
/// changes. commit() then renames every temporary over its path, in staging
/// order, while it holds an exclusive flock(2) on every folder involved
/// (where the file system supports flock), so that two runs committing into
/// the same folder never interleave: the last commit wins with its whole set. Before the renames each existing output is
/// kept as a hard link under a temporary name; if a rename fails, the files
/// already renamed get their old contents back and the error propagates. A
/// set destroyed without commit() (an exception on the way) removes its
/// temporaries and the folders create_folder() made (when still empty): a
/// failed run leaves every pre-existing file as it was, and no new file.
///
/// Errors (thrown by stage, create_folder and commit):
///  - InputError "PATH: is a directory" when PATH is a folder or ends in '/';
///  - InputError "PATH: named twice" when one set stages PATH twice;
///  - InputError when PATH's folder does not exist or is not a folder;
///  - EnvironmentError "PATH: <strerror>" for every other failure, e.g.
///    "out.png: No space left on device".
class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  ~OutputSet();

  /// Creates `folder` and its missing parents; those it creates are removed
  /// again (if empty) unless the set is committed.
  void create_folder(const std::filesystem::path& folder);
  /// Writes `bytes` to a temporary file that commit() renames over `path`.
  void stage(const std::filesystem::path& path, std::string_view bytes);
  /// As stage, for a file written in pieces through the returned stream.
  StagedStream stage_stream(const std::filesystem::path& path);
  /// Puts every staged file in place (see the class comment). Call once.
  void commit();
  /// The paths staged so far, in staging order.
  std::vector<std::filesystem::path> paths() const;

 private:
  struct Staged {
    std::filesystem::path path, temp;
  };
  void discard() noexcept;
  std::vector<Staged> staged_;
  std::vector<std::filesystem::path> created_folders_;  // outermost first
  bool committed_ = false;
};

/// Writes `bytes` to `path` so that readers see the old file or the whole new
/// one, never a part: an OutputSet of one file. Errors as OutputSet.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

/// Writes a spline file (spline_to_json, indented) with write_file_atomic.
void write_spline_file(const std::filesystem::path& path, const BSpline& spline);

/// Text made safe for HTML element content and attribute values, and valid
/// UTF-8: & < > " ' become entities, and each byte that does not belong to a
/// well-formed UTF-8 sequence (a file name in another encoding) becomes
/// U+FFFD, so the page always decodes.
std::string html_escape(std::string_view text);

}  // namespace cmr
