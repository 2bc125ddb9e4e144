#include "io/output.hpp"
#include "io/output_guard.hpp"
#include "io/output_detail.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <dirent.h>
#include <signal.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

// The output set (output.hpp): OutputSet's staging and its commit, the
// streams, note_read, and the text helpers (utf8_sequence, html_escape,
// base64). The file layer under it (output names, temporary and hidden
// files, folder locks, the manifest and the commit journal, recovery) is in
// output_files.cpp.

namespace cmr {

using namespace output_detail;  // what the parts share (output_detail.hpp)

namespace {

/// An owned folder's manifest as it is now: (inode, modification time), or
/// (0, 0) when there is none. A commit renames a new manifest in (a new inode).
std::pair<unsigned long long, long long> manifest_stamp(const std::filesystem::path& folder) {
  struct stat st {};
  if (::lstat((folder / kManifestName).c_str(), &st) != 0) return {0, 0};
  return {static_cast<unsigned long long>(st.st_ino), mtime_ns(st)};
}

/// Per OutputSet, per owned folder: its manifest when own_folder was called
/// (a side table, so that io/output.hpp's layout stays as it is).
std::mutex stamps_mutex;
std::unordered_map<const OutputSet*, std::unordered_map<std::string, std::pair<unsigned long long, long long>>> stamps;

void forget_stamps(const OutputSet* set) {
  const std::lock_guard lock(stamps_mutex);
  stamps.erase(set);
}

/// note_read's files: the canonical path -> (device, inode, size, time).
using ReadStamp = std::array<long long, 4>;
std::mutex reads_mutex;
std::unordered_map<std::string, ReadStamp> reads;

std::string read_key(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::path c = std::filesystem::weakly_canonical(path, ec);
  return ec ? path.lexically_normal().string() : c.string();
}

std::optional<ReadStamp> read_stamp(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  return ReadStamp{static_cast<long long>(st.st_dev), static_cast<long long>(st.st_ino),
                   static_cast<long long>(st.st_size), mtime_ns(st)};
}

}  // namespace

void note_read(const std::filesystem::path& path) {
  const std::optional<ReadStamp> stamp = read_stamp(path);
  if (!stamp) return;
  const std::lock_guard lock(reads_mutex);
  reads[read_key(path)] = *stamp;
}

OutputSet::~OutputSet() {
  discard();
  forget_stamps(this);
}

void OutputSet::close_streams() noexcept {
  for (Staged& s : staged_) {
    if (s.close_fd && s.stream_fd >= 0) ::close(s.stream_fd);
    s.stream_fd = -1;
    if (s.spool_fd >= 0) ::close(s.spool_fd);
    s.spool_fd = -1;
  }
}

bool is_stdout_path(const std::filesystem::path& path) { return is_stdout_alias(path); }

void OutputSet::discard() noexcept {
  if (committed_) return;
  for (const Staged& s : staged_)
    if (!s.temp.empty()) ::unlink(s.temp.c_str());
  close_streams();
  staged_.clear();
  for (auto it = created_folders_.rbegin(); it != created_folders_.rend(); ++it) ::rmdir(it->c_str());
  created_folders_.clear();
}

void OutputSet::create_folder(const std::filesystem::path& folder) {
  check_output_name(folder);
  if (struct stat link {}; ::lstat(folder.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) check_shared_link(folder, link);
  std::vector<std::filesystem::path> missing;  // innermost first
  for (std::filesystem::path p = folder.lexically_normal(); !p.empty() && p != p.root_path(); p = p.parent_path()) {
    struct stat st {};
    if (::stat(p.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) throw InputError(p.string() + ": not a folder (cannot create " + folder.string() + ")");
      break;
    }
    if (errno != ENOENT) throw_errno(p, errno);
    missing.push_back(p);
    if (p.filename().empty()) p = p.parent_path();  // "dir/" -> "dir"
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) == 0) {
      created_folders_.push_back(*it);
    } else if (errno != EEXIST) {
      throw_errno(*it, errno);
    }
  }
}

// Concurrent runs: own_folder notes the folder's manifest as it is now; if,
// when commit() takes the folder's lock, another cmr run has committed into
// the folder since (its manifest was replaced), commit() writes nothing and
// throws EnvironmentError "FOLDER: another cmr run wrote this folder while
// this one ran; ...": the first run's whole set stays, the later one says so
// in one line (exit 3; docs/outputs.md).
void OutputSet::own_folder(const std::filesystem::path& folder) {
  CMR_CHECK(!committed_);
  owned_folders_.push_back(folder);
  const auto stamp = manifest_stamp(folder);
  const std::lock_guard lock(stamps_mutex);
  stamps[this].emplace(folder.string(), stamp);
}

namespace {

/// The folder's identity for the named-twice check: its canonical path
/// (links resolved), cached per spelling so that N files in one folder cost
/// one resolution.
std::string folder_key(const std::filesystem::path& folder) {
  static thread_local std::unordered_map<std::string, std::string> cache;
  auto it = cache.find(folder.string());
  if (it != cache.end()) return it->second;
  std::error_code ec;
  std::filesystem::path c = std::filesystem::weakly_canonical(std::filesystem::absolute(folder, ec), ec);
  std::string key = ec ? std::filesystem::absolute(folder).lexically_normal().string() : c.string();
  if (cache.size() > 4096) cache.clear();
  cache.emplace(folder.string(), key);
  return key;
}

}  // namespace

void OutputSet::stage(const std::filesystem::path& path, std::string_view bytes) {
  check_output_name(path);
  CMR_CHECK(!committed_);
  if (path.filename().empty()) throw_errno(path, EISDIR);
  Staged s;
  s.path = path;
  std::string key;
  struct stat st {};
  if (is_stdout_alias(path)) {
    s.stream_fd = STDOUT_FILENO;
    key = "stream:stdout";
  } else if (::lstat(path.c_str(), &st) != 0) {
    if (errno != ENOENT) throw_errno(path, errno);
    s.target = path;  // a new file (its folder is checked when the temporary is created)
  } else {
    if (S_ISLNK(st.st_mode)) {
      check_shared_link(path, st);
      if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) throw InputError(path.string() + ": a symbolic link to nothing (cmr follows links to files)");
        throw_errno(path, errno);
      }
      if (S_ISREG(st.st_mode)) {
        std::error_code ec;
        s.target = std::filesystem::canonical(path, ec);
        if (ec) throw_errno(path, ec.value());
      }
    } else if (S_ISREG(st.st_mode)) {
      s.target = path;
    }
    if (S_ISDIR(st.st_mode)) throw_errno(path, EISDIR);
    if (S_ISBLK(st.st_mode)) throw InputError(path.string() + ": is a block device, not a file cmr can write");
    if (S_ISSOCK(st.st_mode)) throw InputError(path.string() + ": is a socket, not a file cmr can write");
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
      key = "stream:" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
      if (key_set_.count(key) == 0) {
        const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
        if (fd < 0 && errno == ENXIO && S_ISFIFO(st.st_mode))
          throw InputError(path.string() + ": a FIFO with no reader");
        if (fd < 0) throw_errno(path, errno);
        const int flags = ::fcntl(fd, F_GETFL);
        if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);  // block on a full pipe, as a stream does
        s.stream_fd = fd;
        s.close_fd = true;
      }
    } else if (s.target.empty()) {
      throw InputError(path.string() + ": not a regular file, a device or a FIFO");
    }
  }
  if (key.empty()) key = folder_key(folder_of(s.target)) + "/" + s.target.filename().string();
  if (!key_set_.insert(key).second) {
    if (s.close_fd) ::close(s.stream_fd);
    throw InputError(path.string() + ": named twice");
  }
  if (s.stream_fd >= 0) {
    s.bytes.assign(bytes);
    staged_.push_back(std::move(s));
    return;
  }
  auto [temp, fd] = create_temp(s.target);
  s.temp = std::move(temp);
  staged_.push_back(std::move(s));
  const bool ok = write_all(fd, bytes);
  const int error = errno;
  if (::close(fd) != 0 && ok) throw_errno(path, errno);
  if (!ok) throw_errno(path, error);
}

StagedStream OutputSet::stage_stream(const std::filesystem::path& path) {
  check_output_name(path);
  CMR_CHECK(!committed_);
  if (path.filename().empty()) throw_errno(path, EISDIR);
  struct stat st {};
  if (is_stdout_alias(path) ||
      (::stat(path.c_str(), &st) == 0 && (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)))) {
    // A stream: stage() checks and opens it (named twice, a FIFO without a
    // reader); the pieces are spooled and written at commit.
    std::FILE* f = std::tmpfile();
    if (f == nullptr) throw EnvironmentError(path.string() + ": a spool file in the temporary folder: " + std::strerror(errno));
    const int spool = ::fcntl(::fileno(f), F_DUPFD_CLOEXEC, 0);
    const int error = errno;
    std::fclose(f);  // the unlinked file lives on in `spool`
    if (spool < 0) throw_errno(path, error);
    try {
      stage(path, {});
    } catch (...) {
      ::close(spool);
      throw;
    }
    Staged& staged = staged_.back();
    staged.spool_fd = spool;
    const int writer = ::fcntl(spool, F_DUPFD_CLOEXEC, 0);
    if (writer < 0) throw_errno(path, errno);
    return StagedStream(path, writer, false);
  }
  Staged s;
  s.path = path;
  s.target = path;
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) {  // a link to a regular file is followed, as by stage()
      check_shared_link(path, st);
      std::error_code ec;
      s.target = std::filesystem::canonical(path, ec);
      if (ec) {
        if (ec.value() == ENOENT) throw InputError(path.string() + ": a symbolic link to nothing (cmr follows links to files)");
        throw_errno(path, ec.value());
      }
      if (::stat(s.target.c_str(), &st) != 0) throw_errno(path, errno);
    }
    if (S_ISDIR(st.st_mode)) throw_errno(path, EISDIR);
    if (S_ISBLK(st.st_mode)) throw InputError(path.string() + ": is a block device, not a file cmr can write");
    if (S_ISSOCK(st.st_mode)) throw InputError(path.string() + ": is a socket, not a file cmr can write");
    if (!S_ISREG(st.st_mode)) throw InputError(path.string() + ": not a regular file, a device or a FIFO");
  }
  const std::string key = folder_key(folder_of(s.target)) + "/" + s.target.filename().string();
  if (!key_set_.insert(key).second) throw InputError(path.string() + ": named twice");
  auto [temp, fd] = create_temp(s.target);
  s.temp = std::move(temp);
  staged_.push_back(std::move(s));
  return StagedStream(path, fd, true);
}

StagedStream& StagedStream::operator=(StagedStream&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(o.path_);
    fd_ = o.fd_;
    sync_ = o.sync_;
    written_ = o.written_;
    unstarted_ = o.unstarted_;
    o.fd_ = -1;
  }
  return *this;
}

StagedStream::~StagedStream() {
  if (fd_ >= 0) ::close(fd_);
}

void StagedStream::write(std::string_view bytes) {
  CMR_CHECK(fd_ >= 0);
  if (!write_all(fd_, bytes)) throw_errno(path_, errno);
  written_ += bytes.size();
  unstarted_ += bytes.size();
  constexpr std::uint64_t kStartWriteBack = 8u << 20;
  if (sync_ && unstarted_ >= kStartWriteBack) {
    // A hint only (close still fsyncs): an error here changes nothing.
    (void)::sync_file_range(fd_, static_cast<off_t>(written_ - unstarted_), static_cast<off_t>(unstarted_),
                            SYNC_FILE_RANGE_WRITE);
    unstarted_ = 0;
  }
}

void StagedStream::close() {
  CMR_CHECK(fd_ >= 0);
  const bool ok = !sync_ || ::fsync(fd_) == 0;
  const int error = errno;
  const int rc = ::close(fd_);
  fd_ = -1;
  if (!ok) throw_errno(path_, error);
  if (rc != 0) throw_errno(path_, errno);
}

namespace {

/// A folder's journal of one commit (".cmr-journal.PID.N", this user's,
/// mode 0600, created with O_EXCL | O_NOFOLLOW in the locked folder): the
/// files of the commit there (temporary, name, inode), each backup as it is
/// made, the old owned files to remove, and then the commit point
/// ("commit", flushed with fdatasync before the first rename). Recovery
/// (recover_folder) acts only on what a journal of this user names.
class JournalFile {
 public:
  JournalFile() = default;
  JournalFile(const JournalFile&) = delete;
  JournalFile& operator=(const JournalFile&) = delete;
  ~JournalFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  /// Creates the journal in `dirfd` (the folder of `output`, which errors
  /// name: "OUTPUT: <strerror>").
  void create(int dirfd, const std::filesystem::path& output) {
    dirfd_ = dirfd;
    for (int attempt = 0; attempt < kTempNameAttempts; ++attempt) {
      std::string name = kJournalPrefix;
      name += std::to_string(::getpid());
      name += '.';
      name += std::to_string(attempt);
      fd_ = ::openat(dirfd, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
      if (fd_ >= 0) {
        name_ = std::move(name);
        path_ = output;  // errors name the output the journal is for
        append(std::string(kJournalHeader) + "\npid " + std::to_string(::getpid()) + " " +
               std::to_string(process_start(::getpid())) + "\n");
        return;
      }
      if (errno != EEXIST) throw_errno(output, errno);
    }
    throw EnvironmentError(output.string() + ": every journal name beside it is taken (" + kJournalPrefix + "...)");
  }
  /// Appends `text` (no flush: a killed process's writes stay in the file).
  void append(std::string_view text) {
    if (fd_ >= 0 && !write_all(fd_, text)) throw_errno(path_, errno);
  }
  void sync() {
    if (fd_ >= 0 && ::fdatasync(fd_) != 0) throw_errno(path_, errno);
  }
  /// Removes the journal (the commit is complete, or undone).
  void remove() noexcept {
    if (fd_ < 0) return;
    ::close(fd_);
    fd_ = -1;
    ::unlinkat(dirfd_, name_.c_str(), 0);
  }

 private:
  int dirfd_ = -1, fd_ = -1;
  std::string name_;
  std::filesystem::path path_;
};

}  // namespace

void OutputSet::commit_last(const std::filesystem::path& path) {
  CMR_CHECK(!committed_);
  last_ = path.string();
}

// One commit's steps, in their order (the class comment of OutputSet says
// why each comes where it does). Up to the commit point a failure discards
// the set and leaves every file as it was; after it, a failed rename undoes
// the renames made.
class OutputSet::Committer {
 public:
  explicit Committer(OutputSet& set) : set_(set) {}

  void run() {
    collect_folders();
    lock_and_recover();
    refuse_changed_reads();
    stage_manifests();
    sync_staged_data();
    write_streams();
    order_renames();
    journal_up_to_the_commit_point();
    rename_or_undo();
    finish();
  }

 private:
  /// An owned folder: the old manifest's entries and this run's names there.
  struct Owned {
    std::filesystem::path folder;
    std::vector<ManifestEntry> old;
    std::unordered_set<std::string> names;
  };

  /// The folders written into, each once, in first-use order.
  void collect_folders() {
    std::unordered_set<std::string> seen;
    for (const Staged& s : set_.staged_)
      if (!s.temp.empty() && seen.insert(folder_of(s.target).string()).second) folders_.push_back(folder_of(s.target));
    for (const std::filesystem::path& f : set_.owned_folders_)
      if (seen.insert(f.string()).second) folders_.push_back(f);
  }

  /// Locks each folder. Another run committed into an owned folder since
  /// own_folder: it wins, this run writes nothing (checked before recovery,
  /// which may finish a dead run's manifest). Then an interrupted commit
  /// there is finished or undone.
  void lock_and_recover() {
    for (const std::filesystem::path& f : folders_) {
      bool locked = false;
      const int fd = locks_.lock(f, &locked);
      std::optional<std::pair<unsigned long long, long long>> noted;
      {
        const std::lock_guard lock(stamps_mutex);
        if (const auto it = stamps.find(&set_); it != stamps.end())
          if (const auto at = it->second.find(f.string()); at != it->second.end()) noted = at->second;
      }
      if (noted && manifest_stamp(f) != *noted) {
        set_.discard();
        throw EnvironmentError(f.string() + ": another cmr run wrote this folder while this one ran; its files are "
                               "kept and this run's are not written (run it again)");
      }
      if (fd >= 0 && locked) recover_folder(fd, f);
    }
  }

  /// A file this program read (note_read) that another one wrote since: not
  /// replaced (two editors saving one file), checked under the folders' locks.
  void refuse_changed_reads() {
    const std::lock_guard lock(reads_mutex);
    for (const Staged& s : set_.staged_) {
      if (s.temp.empty() || reads.empty()) continue;
      const auto it = reads.find(read_key(s.target));
      if (it == reads.end() || read_stamp(s.target) == it->second) continue;
      const std::filesystem::path changed = s.path;
      set_.discard();
      throw EnvironmentError(changed.string() + ": changed on disk since this program read it (another editor or "
                             "program saved it); not written, so nothing of it is lost");
    }
  }

  /// Owned folders: this run's file names there, and the manifest staged last.
  void stage_manifests() {
    for (const std::filesystem::path& f : set_.owned_folders_) {
      const int dirfd = locks_.lock(f);
      std::vector<std::string> refused;
      Owned o{f, dirfd >= 0 ? read_manifest(dirfd, refused) : std::vector<ManifestEntry>{}, {}};
      if (!refused.empty())
        std::fprintf(stderr, "cmr: note: %s: %s: its files are left alone\n", f.string().c_str(), refused[0].c_str());
      const std::string key = folder_key(f);
      std::string manifest = std::string(kManifestHeader) + "\n";
      for (const Staged& s : set_.staged_) {
        if (s.temp.empty() || folder_key(folder_of(s.target)) != key) continue;
        const std::string name = s.target.filename().string();
        struct stat st {};
        if (name.find('\n') != std::string::npos || ::lstat(s.temp.c_str(), &st) != 0) continue;
        o.names.insert(name);
        manifest += std::to_string(st.st_ino) + " " + std::to_string(st.st_size) + " " + std::to_string(mtime_ns(st)) +
                    " " + name + "\n";
      }
      owned_.push_back(std::move(o));
      set_.stage(f / kManifestName, manifest);
      set_.staged_.back().manifest = true;
    }
  }

  /// Every staged file's data on disk: one syncfs per file system.
  void sync_staged_data() {
    std::vector<dev_t> synced;
    for (const std::filesystem::path& f : folders_) {
      const int fd = ::open(f.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd < 0) continue;
      struct stat st {};
      if (::fstat(fd, &st) == 0 && std::find(synced.begin(), synced.end(), st.st_dev) == synced.end()) {
        synced.push_back(st.st_dev);
        if (::syncfs(fd) != 0) {
          const int error = errno;
          ::close(fd);
          std::filesystem::path named = f;
          for (const Staged& s : set_.staged_)
            if (!s.temp.empty() && folder_of(s.target) == f) {
              named = s.path;
              break;
            }
          set_.discard();
          throw_errno(named, error);
        }
      }
      ::close(fd);
    }
  }

  /// Streams first: they cannot be taken back, so a failed one changes no file.
  void write_streams() {
    std::fflush(stdout);
    for (Staged& s : set_.staged_) {
      if (s.stream_fd < 0) continue;
      if (!write_all(s.stream_fd, s.bytes) || (s.spool_fd >= 0 && !copy_spool(s.spool_fd, s.stream_fd))) {
        const int error = errno;
        const std::filesystem::path failed = s.path;
        set_.discard();
        throw EnvironmentError(failed.string() + ": " + std::strerror(error));
      }
    }
    set_.close_streams();
  }

  /// The rename order: the files in staging order, then the manifests, then
  /// the set's marker (commit_last: a report's report.json), so that a
  /// reader who sees the marker's new version sees the whole new set.
  void order_renames() {
    for (int pass = 0; pass < 3; ++pass)
      for (std::size_t i = 0; i < set_.staged_.size(); ++i) {
        const Staged& s = set_.staged_[i];
        if (s.temp.empty()) continue;
        const int p = !set_.last_.empty() && s.path.string() == set_.last_ ? 2 : (s.manifest ? 1 : 0);
        if (p == pass) files_.push_back(i);
      }
  }

  /// One journal per folder, written before any backup or rename: each
  /// file (temporary, name, inode), the owned files to remove, each backup
  /// as it is made, then "commit", flushed: the commit point, from which
  /// recovery finishes this commit. A failure before it undoes the backups.
  void journal_up_to_the_commit_point() {
    std::unordered_map<int, std::size_t> journal_of_fd;
    journal_of_file_.assign(files_.size(), nullptr);
    kept_.reserve(files_.size());
    try {
      for (std::size_t k = 0; k < files_.size(); ++k) {
        const Staged& s = set_.staged_[files_[k]];
        const int dirfd = locks_.lock(folder_of(s.target));
        if (dirfd < 0) continue;  // renamed without a journal (the rename reports why it fails)
        auto it = journal_of_fd.find(dirfd);
        if (it == journal_of_fd.end()) {
          journals_.push_back(std::make_unique<JournalFile>());
          journals_.back()->create(dirfd, s.path.parent_path() == s.target.parent_path() ? s.path : s.target);
          it = journal_of_fd.emplace(dirfd, journals_.size() - 1).first;
        }
        JournalFile& j = *journals_[it->second];
        journal_of_file_[k] = &j;
        struct stat st {}, old {};
        if (::lstat(s.temp.c_str(), &st) != 0) throw_errno(s.path, errno);
        const bool existed = ::lstat(s.target.c_str(), &old) == 0;
        j.append("e " + std::to_string(k) + " " + (existed ? "1 " : "0 ") + std::to_string(st.st_ino) + " " +
                 hex_of(s.temp.filename().string()) + " " + hex_of(s.target.filename().string()) + "\n");
      }
      for (const Owned& o : owned_) {
        const auto it = journal_of_fd.find(locks_.lock(o.folder));
        if (it == journal_of_fd.end()) continue;
        std::string lines;
        for (const ManifestEntry& e : o.old)
          if (o.names.count(e.name) == 0)
            lines += "r " + std::to_string(e.ino) + " " + std::to_string(e.size) + " " + std::to_string(e.mtime_ns) +
                     " " + hex_of(e.name) + "\n";
        journals_[it->second]->append(lines);
      }
      // Each old file kept as a backup (the in-process undo), journaled as made.
      for (std::size_t k = 0; k < files_.size(); ++k) {
        kept_.push_back(keep_old(set_.staged_[files_[k]].target));
        struct stat st {};
        if (!kept_[k].link.empty() && journal_of_file_[k] != nullptr && ::lstat(kept_[k].link.c_str(), &st) == 0)
          journal_of_file_[k]->append("b " + std::to_string(k) + " " + std::to_string(st.st_ino) + " " +
                                      hex_of(kept_[k].link.filename().string()) + "\n");
      }
      for (auto& j : journals_) j->append("commit\n");
      for (auto& j : journals_) j->sync();
    } catch (...) {
      for (const Kept& k : kept_)
        if (!k.link.empty()) ::unlink(k.link.c_str());
      for (auto& j : journals_) j->remove();
      set_.discard();
      throw;
    }
  }

  /// Renames every file in order. When one fails, the journal says so first
  /// (a kill during the undo is undone too), then the old files go back and
  /// the new ones away, and the error propagates.
  void rename_or_undo() {
    std::size_t done = 0;
    for (; done < files_.size(); ++done) {
      const Staged& s = set_.staged_[files_[done]];
      if (::rename(s.temp.c_str(), s.target.c_str()) != 0) break;
    }
    const int error = errno;
    if (done < files_.size()) {
      try {
        for (auto& j : journals_) j->append("abort\n");
        for (auto& j : journals_) j->sync();
      } catch (...) {
      }
      for (std::size_t k = 0; k < done; ++k) {
        const Staged& s = set_.staged_[files_[k]];
        if (!kept_[k].link.empty()) ::rename(kept_[k].link.c_str(), s.target.c_str());
        else if (!kept_[k].existed) ::unlink(s.target.c_str());
      }
    }
    for (std::size_t k = done < files_.size() ? done : 0; k < kept_.size(); ++k)
      if (!kept_[k].link.empty()) ::unlink(kept_[k].link.c_str());
    if (done < files_.size()) {
      const std::filesystem::path failed = set_.staged_[files_[done]].path;
      for (std::size_t k = done; k < files_.size(); ++k) ::unlink(set_.staged_[files_[k]].temp.c_str());
      for (auto& j : journals_) j->remove();
      set_.staged_.clear();  // nothing of the set is left to remove but the folders it made
      set_.discard();
      throw_errno(failed, error);
    }
    set_.committed_ = true;
  }

  /// The files this program noted (note_read) are now the ones it wrote;
  /// the files cmr wrote in an owned folder last time and this run did not
  /// are removed when they are still cmr's (this user's, one link, same
  /// inode, size and time), so the folder holds this set. Then the journals
  /// go and the folders' entries reach the disk.
  void finish() {
    {
      const std::lock_guard lock(reads_mutex);
      if (!reads.empty())
        for (const Staged& s : set_.staged_)
          if (!s.temp.empty())
            if (const auto it = reads.find(read_key(s.target)); it != reads.end())
              if (const auto now = read_stamp(s.target)) it->second = *now;
    }
    for (const Owned& o : owned_) {
      const int dirfd = locks_.lock(o.folder);
      if (dirfd < 0) continue;
      for (const ManifestEntry& e : o.old)
        if (o.names.count(e.name) == 0) remove_if_still_ours(dirfd, e);
    }
    for (auto& j : journals_) j->remove();
    for (const std::filesystem::path& f : folders_) sync_folder(f);
  }

  OutputSet& set_;
  std::vector<std::filesystem::path> folders_;
  FolderLocks locks_;  // held until the commit ends (declared before the journals: released after them)
  std::vector<Owned> owned_;
  std::vector<std::size_t> files_;  // indices of the staged files (not streams), in rename order
  std::vector<std::unique_ptr<JournalFile>> journals_;
  std::vector<JournalFile*> journal_of_file_;  // parallel to files_
  std::vector<Kept> kept_;                     // parallel to files_
};

void OutputSet::commit() {
  CMR_CHECK(!committed_);
  Committer(*this).run();
}

std::vector<std::filesystem::path> OutputSet::paths() const {
  std::vector<std::filesystem::path> out;
  for (const Staged& s : staged_)
    if (!s.manifest) out.push_back(s.path);
  return out;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view bytes) {
  OutputSet set;
  set.stage(path, bytes);
  set.commit();
}

void write_spline_file(const std::filesystem::path& path, const BSpline& spline) {
  write_file_atomic(path, spline_to_json(spline).dump(2) + "\n");
}

std::size_t utf8_sequence(std::string_view s) {
  if (s.empty()) return 0;
  const auto b = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const auto cont = [&](std::size_t i) { return i < s.size() && (b(i) & 0xC0) == 0x80; };
  const unsigned char c = b(0);
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) return cont(1) ? 2 : 0;
  if (c >= 0xE0 && c <= 0xEF) {
    if (!cont(1) || !cont(2)) return 0;
    if (c == 0xE0 && b(1) < 0xA0) return 0;   // overlong
    if (c == 0xED && b(1) >= 0xA0) return 0;  // surrogate
    return 3;
  }
  if (c >= 0xF0 && c <= 0xF4) {
    if (!cont(1) || !cont(2) || !cont(3)) return 0;
    if (c == 0xF0 && b(1) < 0x90) return 0;   // overlong
    if (c == 0xF4 && b(1) >= 0x90) return 0;  // above U+10FFFF
    return 4;
  }
  return 0;
}

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  while (!text.empty()) {
    const std::size_t n = utf8_sequence(text);
    if (n == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD for a byte that is not UTF-8 (a file name from another locale)
      text.remove_prefix(1);
      continue;
    }
    switch (text[0]) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out.append(text.substr(0, n));
    }
    text.remove_prefix(n);
  }
  return out;
}

std::string base64(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

}  // namespace cmr
