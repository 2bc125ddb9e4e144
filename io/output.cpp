#include "io/output.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <dirent.h>
#include <signal.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

namespace cmr {

void check_output_path(const std::filesystem::path& path, const std::string& option) {
  const std::filesystem::path folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(option + " " + path.string() + ": the folder " + folder.string() + " does not exist");
  if (path.filename().empty() || std::filesystem::is_directory(path, ec))
    throw InputError(option + " " + path.string() + ": is a directory");
}

namespace {

/// The error for a failed system call on `path`: the caller's fault for the
/// errno values a user fixes by choosing another path, the environment's for
/// the rest.
[[noreturn]] void throw_errno(const std::filesystem::path& path, int error) {
  const std::string message = path.string() + ": " + std::strerror(error);
  switch (error) {
    case EISDIR: throw InputError(path.string() + ": is a directory");
    case ENOENT:
    case ENOTDIR: throw InputError(message + " (does the folder exist?)");
    case ENAMETOOLONG: throw InputError(message);
    default: throw EnvironmentError(message);
  }
}

/// Creates the first free temporary name beside `path`, never following a
/// link; returns the name and an open descriptor.
std::pair<std::filesystem::path, int> create_temp(const std::filesystem::path& path) {
  for (int attempt = 0; attempt < kTempNameAttempts; ++attempt) {
    std::filesystem::path name = temp_name_for(path, attempt);
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return {std::move(name), fd};
    if (errno != EEXIST) throw_errno(path, errno);
  }
  throw EnvironmentError(path.string() + ": every temporary name beside it is taken (" +
                         temp_name_for(path, 0).filename().string() + " ...)");
}

/// Writes all of `bytes` to `fd`, retrying short writes and interruptions;
/// errno is set when it returns false.
bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

std::filesystem::path folder_of(const std::filesystem::path& path) {
  return path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
}

/// Flushes a folder's entries (the renames); best effort (some file systems
/// refuse fsync on folders, and the data itself is already on disk).
void sync_folder(const std::filesystem::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

/// Exclusive flock(2)s on folders, released on destruction. One lock per
/// folder (by device and inode): two descriptors of one folder would
/// deadlock the process against itself. Best effort: where a folder cannot
/// be opened or locked (a file system without flock), the commit goes on
/// unlocked, each file still replaced atomically.
class FolderLocks {
 public:
  FolderLocks() = default;
  FolderLocks(const FolderLocks&) = delete;
  FolderLocks& operator=(const FolderLocks&) = delete;
  ~FolderLocks() {
    for (const Held& h : held_) ::close(h.fd);  // closing releases the lock
  }
  void lock(const std::filesystem::path& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
      ::close(fd);
      return;
    }
    for (const Held& h : held_) {
      if (h.dev == st.st_dev && h.ino == st.st_ino) {
        ::close(fd);
        return;
      }
    }
    int locked;
    while ((locked = ::flock(fd, LOCK_EX)) != 0 && errno == EINTR) {
    }
    if (locked != 0) {
      ::close(fd);
      return;
    }
    held_.push_back({fd, st.st_dev, st.st_ino});
  }

 private:
  struct Held {
    int fd;
    dev_t dev;
    ino_t ino;
  };
  std::vector<Held> held_;
};

/// Longest NAME kept whole in a hidden name (NAME_MAX is 255; the prefix,
/// the pid and the attempt take at most 30).
constexpr std::size_t kHiddenNameMax = 200;

std::filesystem::path hidden_name(const std::string& kind, const std::filesystem::path& path, long pid, int attempt) {
  std::string name = kHiddenPrefix;  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string&&
  name += kind;
  name += '.';
  name += std::to_string(pid);
  name += '.';
  name += std::to_string(attempt);
  name += '.';
  name += path.filename().string().substr(0, kHiddenNameMax);
  const std::filesystem::path folder = path.parent_path();
  return folder.empty() ? std::filesystem::path(name) : folder / name;
}

/// What keep_old found at an output path before the commit.
struct Kept {
  bool existed = false;
  std::filesystem::path link;  ///< hard link to the old file; empty when none could be made
};

/// Keeps the file now at `path` (if any) as a hard link under a free
/// backup name, so that a failed commit can put it back. File systems
/// without hard links give no link (the commit goes on without the undo).
Kept keep_old(const std::filesystem::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {};
  for (int attempt = 0; attempt < kTempNameAttempts; ++attempt) {
    std::filesystem::path name = hidden_name("bak", path, ::getpid(), attempt);
    if (::link(path.c_str(), name.c_str()) == 0) return {true, std::move(name)};
    if (errno != EEXIST) break;
  }
  return {true, {}};
}

/// Whether process `pid` exists (kill(pid, 0) reaches it or is refused).
bool process_alive(long pid) {
  if (pid <= 0 || pid != static_cast<pid_t>(pid)) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

/// The stdout aliases written as a stream to file descriptor 1.
bool is_stdout_alias(const std::filesystem::path& path) {
  const std::string p = path.string();
  return p == "-" || p == "/dev/stdout" || p == "/dev/fd/1" || p == "/proc/self/fd/1";
}

/// Copies the whole spool file `from` (a stream's pieces) to `to`; false
/// with errno set when a read or a write fails.
bool copy_spool(int from, int to) {
  char buf[1 << 16];
  for (off_t at = 0;;) {
    const ssize_t n = ::pread(from, buf, sizeof buf, at);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) return true;
    if (!write_all(to, std::string_view(buf, static_cast<std::size_t>(n)))) return false;
    at += n;
  }
}

/// A manifest entry: a file cmr wrote into an owned folder.
struct ManifestEntry {
  unsigned long long ino = 0, size = 0;
  std::string name;
};
constexpr const char* kManifestHeader = "cmr output manifest 1";

std::vector<ManifestEntry> read_manifest(const std::filesystem::path& folder) {
  std::vector<ManifestEntry> out;
  const int fd = ::open((folder / kManifestName).c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return out;
  std::string text;
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size < (64 << 20)) {
    text.resize(static_cast<std::size_t>(st.st_size));
    std::size_t used = 0;
    while (used < text.size()) {
      const ssize_t n = ::read(fd, text.data() + used, text.size() - used);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      used += static_cast<std::size_t>(n);
    }
    text.resize(used);
  }
  ::close(fd);
  std::size_t at = text.find('\n');
  if (at == std::string::npos || text.substr(0, at) != kManifestHeader) return out;  // not cmr's: remove nothing
  while (++at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string line = text.substr(at, end - at);
    at = end;
    ManifestEntry e;
    char* rest = nullptr;
    e.ino = std::strtoull(line.c_str(), &rest, 10);
    if (rest == nullptr || *rest != ' ') continue;
    e.size = std::strtoull(rest + 1, &rest, 10);
    if (rest == nullptr || *rest != ' ') continue;
    e.name = rest + 1;
    if (e.name.empty() || e.name.find('/') != std::string::npos || e.name == "." || e.name == "..") continue;
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace

std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt) {
  return hidden_name("tmp", path, ::getpid(), attempt);
}

std::size_t clean_stale_hidden_files(const std::filesystem::path& folder) {
  DIR* dir = ::opendir(folder.c_str());
  if (dir == nullptr) return 0;
  std::vector<std::string> names;
  while (const dirent* e = ::readdir(dir)) {
    const std::string_view n(e->d_name);
    if (n.rfind(".cmr-tmp.", 0) == 0 || n.rfind(".cmr-bak.", 0) == 0) names.emplace_back(n);
  }
  ::closedir(dir);
  std::size_t handled = 0;
  for (const std::string& n : names) {
    // ".cmr-KIND.PID.ATTEMPT.NAME"
    const std::size_t pid_at = 9, pid_end = n.find('.', pid_at);
    if (pid_end == std::string::npos || pid_end == pid_at || pid_end - pid_at > 10) continue;
    const std::size_t attempt_end = n.find('.', pid_end + 1);
    if (attempt_end == std::string::npos) continue;
    bool digits = true;
    for (std::size_t i = pid_at; i < attempt_end; ++i) digits = digits && (std::isdigit(static_cast<unsigned char>(n[i])) || i == pid_end);
    if (!digits) continue;
    const long pid = std::stol(n.substr(pid_at, pid_end - pid_at));
    if (pid == ::getpid() || process_alive(pid)) continue;
    const std::filesystem::path entry = folder / n;
    struct stat st {};
    if (::lstat(entry.c_str(), &st) != 0) continue;
    const std::string name = n.substr(attempt_end + 1);
    if (n[5] == 'b' && S_ISREG(st.st_mode) && !name.empty() && name.size() < kHiddenNameMax) {
      // A killed commit's backup: the old file back in place (a no-op when
      // it was not replaced yet: both names are one file).
      ::rename(entry.c_str(), (folder / name).c_str());
    }
    if (!S_ISDIR(st.st_mode)) ::unlink(entry.c_str());
    ++handled;
  }
  return handled;
}

OutputSet::~OutputSet() { discard(); }

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

void OutputSet::own_folder(const std::filesystem::path& folder) {
  CMR_CHECK(!committed_);
  owned_folders_.push_back(folder);
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

void OutputSet::commit() {
  CMR_CHECK(!committed_);
  // The folders written into, each once, in first-use order.
  std::vector<std::filesystem::path> folders;
  std::unordered_set<std::string> seen;
  for (const Staged& s : staged_)
    if (!s.temp.empty() && seen.insert(folder_of(s.target).string()).second) folders.push_back(folder_of(s.target));
  for (const std::filesystem::path& f : owned_folders_)
    if (seen.insert(f.string()).second) folders.push_back(f);
  FolderLocks locks;
  for (const std::filesystem::path& f : folders) locks.lock(f);
  for (const std::filesystem::path& f : folders) clean_stale_hidden_files(f);

  // Owned folders: this run's file names there, and the manifest staged last.
  struct Owned {
    std::filesystem::path folder;
    std::vector<ManifestEntry> old;
    std::unordered_set<std::string> names;
  };
  std::vector<Owned> owned;
  for (const std::filesystem::path& f : owned_folders_) {
    Owned o{f, read_manifest(f), {}};
    const std::string key = folder_key(f);
    std::string manifest = std::string(kManifestHeader) + "\n";
    for (const Staged& s : staged_) {
      if (s.temp.empty() || folder_key(folder_of(s.target)) != key) continue;
      const std::string name = s.target.filename().string();
      struct stat st {};
      if (name.find('\n') != std::string::npos || ::stat(s.temp.c_str(), &st) != 0) continue;
      o.names.insert(name);
      manifest += std::to_string(st.st_ino) + " " + std::to_string(st.st_size) + " " + name + "\n";
    }
    owned.push_back(std::move(o));
    stage(f / kManifestName, manifest);
    staged_.back().manifest = true;
  }

  // Every staged file's data on disk: one syncfs per file system.
  {
    std::vector<dev_t> synced;
    for (const std::filesystem::path& f : folders) {
      const int fd = ::open(f.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd < 0) continue;
      struct stat st {};
      if (::fstat(fd, &st) == 0 && std::find(synced.begin(), synced.end(), st.st_dev) == synced.end()) {
        synced.push_back(st.st_dev);
        if (::syncfs(fd) != 0) {
          const int error = errno;
          ::close(fd);
          std::filesystem::path named = f;
          for (const Staged& s : staged_)
            if (!s.temp.empty() && folder_of(s.target) == f) {
              named = s.path;
              break;
            }
          discard();
          throw_errno(named, error);
        }
      }
      ::close(fd);
    }
  }

  // Streams first: they cannot be taken back, so a failed one changes no file.
  std::fflush(stdout);
  for (Staged& s : staged_) {
    if (s.stream_fd < 0) continue;
    if (!write_all(s.stream_fd, s.bytes) || (s.spool_fd >= 0 && !copy_spool(s.spool_fd, s.stream_fd))) {
      const int error = errno;
      const std::filesystem::path failed = s.path;
      discard();
      throw EnvironmentError(failed.string() + ": " + std::strerror(error));
    }
  }
  close_streams();

  std::vector<std::size_t> files;  // indices of the staged files (not streams)
  for (std::size_t i = 0; i < staged_.size(); ++i)
    if (!staged_[i].temp.empty()) files.push_back(i);
  std::vector<Kept> kept;
  kept.reserve(files.size());
  for (std::size_t i : files) kept.push_back(keep_old(staged_[i].target));
  std::size_t done = 0;
  for (; done < files.size(); ++done) {
    const Staged& s = staged_[files[done]];
    if (::rename(s.temp.c_str(), s.target.c_str()) != 0) break;
  }
  const int error = errno;
  if (done < files.size()) {  // undo: the old files back, new ones away
    for (std::size_t k = 0; k < done; ++k) {
      const Staged& s = staged_[files[k]];
      if (!kept[k].link.empty()) ::rename(kept[k].link.c_str(), s.target.c_str());
      else if (!kept[k].existed) ::unlink(s.target.c_str());
    }
  }
  for (std::size_t k = done < files.size() ? done : 0; k < kept.size(); ++k)
    if (!kept[k].link.empty()) ::unlink(kept[k].link.c_str());
  if (done < files.size()) {
    const std::filesystem::path failed = staged_[files[done]].path;
    for (std::size_t k = done; k < files.size(); ++k) ::unlink(staged_[files[k]].temp.c_str());
    staged_.clear();  // nothing of the set is left to remove but the folders it made
    discard();
    throw_errno(failed, error);
  }
  committed_ = true;
  // The files cmr wrote there last time and this run did not: removed when
  // they are still cmr's (same inode and size), so the folder holds this set.
  for (const Owned& o : owned) {
    for (const ManifestEntry& e : o.old) {
      if (o.names.count(e.name) > 0) continue;
      const std::filesystem::path p = o.folder / e.name;
      struct stat st {};
      if (::lstat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && static_cast<unsigned long long>(st.st_ino) == e.ino &&
          static_cast<unsigned long long>(st.st_size) == e.size)
        ::unlink(p.c_str());
    }
  }
  for (const std::filesystem::path& f : folders) sync_folder(f);
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

namespace {

/// Length of the well-formed UTF-8 sequence at the start of `s` (RFC 3629:
/// no overlong forms, no surrogates, at most U+10FFFF), or 0 when the first
/// byte does not start one.
std::size_t utf8_sequence(std::string_view s) {
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

}  // namespace

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
