#pragma once
/// Output helpers shared by the cmr libraries and the command: the output
/// path check, the one atomic file writer, and HTML escaping (the error
/// types are in spline/errors.hpp).
/// Nothing here depends on the command line (CLI11).
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_set>
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

/// Every hidden file cmr leaves beside an output while it works starts with
/// this prefix and carries the writer's process id:
///   ".cmr-tmp.PID.ATTEMPT.NAME"  a staged temporary (renamed over NAME at commit)
///   ".cmr-bak.PID.ATTEMPT.NAME"  the old NAME kept during a commit (the undo)
///   ".cmr-journal.PID.ATTEMPT"   the journal of a commit into that folder
/// (NAME cut to 200 bytes, so that the entry stays within NAME_MAX). A run
/// that is killed leaves them behind; the next commit into that folder
/// finishes or undoes the killed commit as its journal says, and removes
/// the dead run's staged temporaries. Only files this user made are acted
/// on (owner geteuid(), one link, never through a link, the inode its
/// journal recorded): a name proves nothing (docs/outputs.md, threat model).
inline constexpr const char* kHiddenPrefix = ".cmr-";
/// The manifest an owned output folder carries: the files cmr wrote there in
/// its last commit (see OutputSet::own_folder).
inline constexpr const char* kManifestName = ".cmr-manifest";

/// The temporary name write_file_atomic tries on its `attempt`-th try for
/// `path`: a hidden file beside it (see kHiddenPrefix), so that the rename
/// stays inside one file system. The name is only a proposal: it is created
/// with O_CREAT | O_EXCL | O_NOFOLLOW, so a file or a symbolic link already
/// there (another process, an attacker) is skipped, never opened.
std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt);

/// Recovery of `folder`, under its lock: each journal of this user's dead
/// cmr processes there is carried out (a commit that passed its commit point
/// is finished: its staged files renamed into place; one that had not is
/// undone: its temporaries and backups removed, every old file untouched),
/// and the dead processes' staged temporaries (this user's, one link) are
/// removed. Nothing else is touched: a backup or journal that is not this
/// user's own, or that no journal names, is left alone, and one line on
/// stderr ("cmr: note: FOLDER: left alone, not rolled back: ...") says so.
/// Returns how many journals and temporaries it handled. Best effort: a
/// folder it cannot open or lock is skipped. OutputSet::commit runs it on
/// every folder it writes into, under the lock it already holds.
std::size_t clean_stale_hidden_files(const std::filesystem::path& folder);

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
  StagedStream(StagedStream&& o) noexcept
      : path_(std::move(o.path_)), fd_(o.fd_), sync_(o.sync_), written_(o.written_), unstarted_(o.unstarted_) {
    o.fd_ = -1;
  }
  StagedStream& operator=(StagedStream&& o) noexcept;
  ~StagedStream();
  void write(std::string_view bytes);
  void close();
  bool is_open() const { return fd_ >= 0; }

 private:
  friend class OutputSet;
  StagedStream(std::filesystem::path path, int fd, bool sync) : path_(std::move(path)), fd_(fd), sync_(sync) {}
  std::filesystem::path path_;
  int fd_ = -1;
  bool sync_ = true;  ///< fsync on close (a staged file; not a stream's spool)
  /// Bytes written, and those whose write-back to disk was not started yet:
  /// a synced stream starts it every few MiB (sync_file_range), so that
  /// close's fsync does not wait for a whole large file at the end of a run.
  std::uint64_t written_ = 0, unstarted_ = 0;
};

/// Output files committed together: all of them, or none.
///
/// What an output path may be:
///  - a regular file, or a name not yet taken: replaced atomically, as below;
///  - a symbolic link to a regular file: followed; the file it points to is
///    replaced atomically (the link stays a link). Two paths that reach one
///    file (a link and its target) are "named twice". A dangling link is
///    refused (InputError "PATH: a symbolic link to nothing");
///  - "-", /dev/stdout, /dev/fd/1: standard output, written as a stream;
///  - a character device or a FIFO (a pipe): written as a stream, never
///    unlinked or renamed over (/dev/null swallows it, /dev/full fails with
///    EnvironmentError "No space left on device"); a FIFO with no reader is
///    InputError "PATH: a FIFO with no reader" (nothing blocks);
///  - a block device or a socket: InputError ("PATH: is a block device,
///    not a file cmr can write").
/// Streams cannot be taken back: commit() writes them first, before any
/// file is renamed, so a failed stream leaves every file as it was.
///
/// stage() writes each file's bytes to its own new temporary file beside it
/// (see temp_name_for); nothing a user sees changes. commit() flushes every
/// staged file to disk (one syncfs(2) per file system), then renames every
/// temporary over its path (staging order, then the manifests, then the
/// commit_last marker) while it holds an exclusive flock(2) on every folder
/// involved (where the file system supports flock), so that two runs
/// committing into the same folder never interleave: the last commit wins
/// with its whole set. First, under those locks, it carries out the
/// journals of killed commits there (clean_stale_hidden_files), then writes
/// its own journal into each folder: its temporaries, each existing output
/// kept as a hard link under a backup name, the old owned files to remove,
/// and "commit", flushed: the commit point. A kill before it leaves the old
/// set (the next commit removes the leftovers); after it, the next commit
/// finishes the renames (docs/outputs.md). If a rename fails, the journal
/// says "abort", the files already renamed get their old contents back and
/// the error propagates. A set destroyed without commit() (an exception on the way)
/// removes its temporaries and the folders create_folder() made (when still
/// empty): a failed run leaves every pre-existing file as it was, and no new
/// file. Staging, committing and rolling back N files is O(N) (one hash
/// lookup per path, one lock, sync and directory scan per folder).
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
  /// Makes this set the owner of `folder` (an output folder such as
  /// `report --out` or `sweep --out-dir`): commit() also removes the files
  /// that cmr's previous owning commit wrote there (listed in its manifest,
  /// kManifestName) and that this set does not write, so that a reused
  /// folder holds only this run's files, and writes the new manifest. A file
  /// is removed only when it is still the very file cmr wrote (same inode and
  /// size): a user's own files, and files changed since, are never removed.
  void own_folder(const std::filesystem::path& folder);
  /// Writes `bytes` to a temporary file that commit() renames over `path`
  /// (or keeps them for a stream; see the class comment).
  void stage(const std::filesystem::path& path, std::string_view bytes);
  /// As stage, for a file written in pieces through the returned stream.
  /// Every output path stage() takes is taken: a file's pieces go to its
  /// temporary; a stream's ("-", /dev/stdout, a character device, a FIFO)
  /// to an unlinked spool file in the temporary folder (memory stays
  /// bounded), copied to the stream at commit() before any file is renamed,
  /// as stage()'s streams are.
  StagedStream stage_stream(const std::filesystem::path& path);
  /// Makes the staged file `path` (as given to stage) the set's marker: it
  /// is renamed last, after the manifest, so that its new version means the
  /// whole new set is in place (a report's report.json).
  void commit_last(const std::filesystem::path& path);
  /// Puts every staged file in place (see the class comment). Call once.
  void commit();
  /// The paths staged so far, in staging order.
  std::vector<std::filesystem::path> paths() const;

 private:
  struct Staged {
    std::filesystem::path path;    ///< as given
    std::filesystem::path target;  ///< the file replaced (path, or the file a link points to)
    std::filesystem::path temp;    ///< empty for a stream
    int stream_fd = -1;            ///< a device, FIFO or stdout: written at commit
    bool close_fd = false;
    std::string bytes;             ///< a stream's bytes
    int spool_fd = -1;             ///< a stream written in pieces: its bytes, after `bytes` (stage_stream)
    bool manifest = false;         ///< an owned folder's manifest (not in paths())
  };
  class Committer;  // commit()'s steps (output.cpp)
  void discard() noexcept;
  void close_streams() noexcept;
  std::vector<Staged> staged_;
  std::unordered_set<std::string> key_set_;  // what each staged path reaches (named-twice check)
  std::vector<std::filesystem::path> created_folders_;  // outermost first
  std::vector<std::filesystem::path> owned_folders_;
  std::string last_;  // commit_last's path
  bool committed_ = false;
};

/// Whether `path` names standard output for an OutputSet ("-", /dev/stdout,
/// /dev/fd/1): a command prints its own lines elsewhere then.
bool is_stdout_path(const std::filesystem::path& path);

/// Writes `bytes` to `path` so that readers see the old file or the whole new
/// one, never a part: an OutputSet of one file. Errors as OutputSet.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

/// Writes a spline file (spline_to_json, indented) with write_file_atomic.
void write_spline_file(const std::filesystem::path& path, const BSpline& spline);

/// Length of the well-formed UTF-8 sequence at the start of `s` (RFC 3629:
/// no overlong forms, no surrogates, at most U+10FFFF), or 0 when the first
/// byte does not start one (or `s` is empty).
std::size_t utf8_sequence(std::string_view s);

/// Text made safe for HTML element content and attribute values, and valid
/// UTF-8: & < > " ' become entities, and each byte that does not belong to a
/// well-formed UTF-8 sequence (a file name in another encoding) becomes
/// U+FFFD, so the page always decodes.
std::string html_escape(std::string_view text);

/// Standard base64 (RFC 4648, with '=' padding) of `bytes`: images inlined in
/// HTML reports as data: URLs.
std::string base64(std::string_view bytes);

}  // namespace cmr
