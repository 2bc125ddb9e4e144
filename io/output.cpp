#include "io/output.hpp"
#include "io/output_guard.hpp"

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

namespace cmr {

namespace {

/// Refuses (InputError) an output path with a control character (a newline,
/// a tab, ESC...): every message and manifest line names a file on one line,
/// and a terminal must not be driven by a file name. The message shows each
/// such byte escaped (a newline as backslash-n).
void check_output_name(const std::filesystem::path& path) {
  const std::string& text = path.native();
  if (std::none_of(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    return;
  std::string shown;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') shown += "\\n";
    else if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      shown += buf;
    } else shown += c;
  }
  throw InputError(shown + ": an output name with a newline or another control character is refused");
}

/// Refuses (InputError) to follow the output path `path`, a symbolic link
/// (`link`: its lstat), that another user planted in a shared folder (sticky
/// or writable by all, e.g. /tmp): as the kernel's protected_symlinks, a
/// link there is followed only when it is this user's or the folder
/// owner's, so that another user cannot aim cmr's output at a file of ours.
void check_shared_link(const std::filesystem::path& path, const struct stat& link) {
  const std::filesystem::path folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  struct stat dir {};
  if (::stat(folder.c_str(), &dir) != 0 || (dir.st_mode & (S_ISVTX | S_IWOTH)) == 0) return;
  if (link.st_uid == ::geteuid() || link.st_uid == dir.st_uid) return;
  throw InputError(path.string() + ": a symbolic link owned by uid " + std::to_string(link.st_uid) +
                   " in a shared folder (sticky or writable by all): not followed");
}

}  // namespace

void check_output_path(const std::filesystem::path& path, const std::string& option) {
  check_output_name(path);
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
/// unlocked, each file still replaced atomically (and no recovery runs
/// there: it needs the lock). The open folder is kept for the *at() calls
/// of the journal and of recovery (no path is resolved twice).
class FolderLocks {
 public:
  FolderLocks() = default;
  FolderLocks(const FolderLocks&) = delete;
  FolderLocks& operator=(const FolderLocks&) = delete;
  ~FolderLocks() {
    for (const Held& h : held_) ::close(h.fd);  // closing releases the lock
  }
  /// Locks `folder`; returns its open descriptor (owned here), or -1 when
  /// it could not be opened. `locked` tells whether the flock is held.
  int lock(const std::filesystem::path& folder, bool* locked = nullptr) {
    if (locked != nullptr) *locked = false;
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return -1;
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
      ::close(fd);
      return -1;
    }
    for (const Held& h : held_) {
      if (h.dev == st.st_dev && h.ino == st.st_ino) {
        ::close(fd);
        if (locked != nullptr) *locked = h.locked;
        return h.fd;
      }
    }
    int rc;
    while ((rc = ::flock(fd, LOCK_EX)) != 0 && errno == EINTR) {
    }
    held_.push_back({fd, st.st_dev, st.st_ino, rc == 0});
    if (locked != nullptr) *locked = rc == 0;
    return fd;
  }

 private:
  struct Held {
    int fd;
    dev_t dev;
    ino_t ino;
    bool locked;
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

/// A manifest entry: a file cmr wrote into an owned folder, by identity
/// (inode, size, modification time in ns) and name.
struct ManifestEntry {
  unsigned long long ino = 0, size = 0;
  long long mtime_ns = 0;
  std::string name;
};
/// Version 2 carries the modification time; a version 1 manifest (inode and
/// size only, too weak to prove a file is cmr's) is ignored: it removes nothing.
constexpr const char* kManifestHeader = "cmr output manifest 2";
constexpr const char* kJournalHeader = "cmr commit journal 1";
constexpr const char* kJournalPrefix = ".cmr-journal.";

long long mtime_ns(const struct stat& st) {
  return static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
}

/// Whether a folder is shared with other users: sticky (/tmp) or writable by
/// all. There, recovery never touches another user's file.
bool folder_shared(int dirfd) {
  struct stat st {};
  return ::fstat(dirfd, &st) == 0 && (st.st_mode & (S_ISVTX | S_IWOTH)) != 0;
}

/// The entry `name` of the open folder, not followed: true when it is a
/// regular file (its stat in `st`).
bool regular_entry(int dirfd, const std::string& name, struct stat& st) {
  return ::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode);
}

/// Whether `st` is a file this user made and nothing else names: owner
/// geteuid(), one link, and the inode the journal or manifest recorded.
bool own_single_file(const struct stat& st, unsigned long long ino) {
  return st.st_uid == ::geteuid() && st.st_nlink == 1 && static_cast<unsigned long long>(st.st_ino) == ino;
}

/// Reads a small regular file of the open folder, never following a link:
/// false unless it is a regular file of this user with one link (the
/// owner's uid in `*owner` when it is someone else's).
bool read_own_file(int dirfd, const std::string& name, std::string& text, uid_t* owner = nullptr) {
  struct stat before {};
  if (!regular_entry(dirfd, name, before)) return false;  // a device or FIFO is never opened
  const int fd = ::openat(dirfd, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat st {};
  bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_ino == before.st_ino && st.st_nlink == 1 &&
            st.st_uid == ::geteuid() && st.st_size < (64 << 20);
  if (owner != nullptr) *owner = st.st_uid;
  if (ok) {
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
  return ok;
}

/// Names in the journal are hex: any byte (a newline, a space) survives.
std::string hex_of(std::string_view s) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(2 * s.size());
  for (const char c : s) {
    out += kDigits[static_cast<unsigned char>(c) >> 4];
    out += kDigits[static_cast<unsigned char>(c) & 15];
  }
  return out;
}
bool unhex(std::string_view h, std::string& out) {
  if (h.size() % 2 != 0) return false;
  out.clear();
  const auto digit = [](char c) { return c >= '0' && c <= '9' ? c - '0' : (c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1); };
  for (std::size_t i = 0; i < h.size(); i += 2) {
    const int a = digit(h[i]), b = digit(h[i + 1]);
    if (a < 0 || b < 0) return false;
    out += static_cast<char>(a * 16 + b);
  }
  return true;
}
/// A plain file name of the folder (no '/', not "." or "..", not empty).
bool plain_name(const std::string& n) { return !n.empty() && n.find('/') == std::string::npos && n != "." && n != ".."; }

/// The lines of `text`, split on '\n', each split on ' '.
std::vector<std::vector<std::string>> lines_of(const std::string& text) {
  std::vector<std::vector<std::string>> out;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    std::vector<std::string> words;
    std::size_t w = at;
    while (w < end) {
      const std::size_t sp = std::min(text.find(' ', w), end);
      words.emplace_back(text.substr(w, sp - w));
      w = sp + 1;
    }
    out.push_back(std::move(words));
    at = end + 1;
  }
  return out;
}

/// The manifest of the open folder, if it is this user's own file (owner
/// geteuid(), one link, not a link). A manifest someone else owns is noted
/// in `refused` and names nothing.
std::vector<ManifestEntry> read_manifest(int dirfd, std::vector<std::string>& refused) {
  std::vector<ManifestEntry> out;
  std::string text;
  uid_t owner = ::geteuid();
  if (!read_own_file(dirfd, kManifestName, text, &owner)) {
    struct stat st {};
    if (::fstatat(dirfd, kManifestName, &st, AT_SYMLINK_NOFOLLOW) == 0)
      refused.push_back(std::string(kManifestName) +
                        (st.st_uid != ::geteuid() ? " (owned by uid " + std::to_string(st.st_uid) + ", not this user)"
                                                  : " (not a regular file with one link)"));
    return out;
  }
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
    e.mtime_ns = std::strtoll(rest + 1, &rest, 10);
    if (rest == nullptr || *rest != ' ') continue;
    e.name = rest + 1;
    if (!plain_name(e.name) || e.name.rfind(kHiddenPrefix, 0) == 0) continue;
    out.push_back(std::move(e));
  }
  return out;
}

/// Removes a file an earlier owning commit listed, if it is still the very
/// file cmr wrote: this user's, one link, same inode, size and time.
void remove_if_still_ours(int dirfd, const ManifestEntry& e) {
  struct stat st {};
  if (regular_entry(dirfd, e.name, st) && own_single_file(st, e.ino) &&
      static_cast<unsigned long long>(st.st_size) == e.size && mtime_ns(st) == e.mtime_ns)
    ::unlinkat(dirfd, e.name.c_str(), 0);
}

/// The start time of process `pid` (clock ticks after boot: field 22 of
/// /proc/PID/stat), or 0 when it cannot be read. With the pid it names one
/// process even after the pid is reused.
unsigned long long process_start(long pid) {
  std::FILE* f = std::fopen(("/proc/" + std::to_string(pid) + "/stat").c_str(), "r");
  if (f == nullptr) return 0;
  char buf[1024];
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, f);
  std::fclose(f);
  buf[n] = '\0';
  const char* p = std::strrchr(buf, ')');
  if (p == nullptr) return 0;
  for (int field = 2; field < 22 && p != nullptr; ++field) p = std::strchr(p + 1, ' ');
  return p == nullptr ? 0 : std::strtoull(p + 1, nullptr, 10);
}

/// One folder's part of a commit, as its journal records it.
struct JournalEntry {
  std::string name, temp, backup;  ///< file names in the folder
  unsigned long long temp_ino = 0, backup_ino = 0;
  bool existed = false;
};
struct Journal {
  long pid = 0;
  unsigned long long start = 0;
  std::vector<JournalEntry> entries;
  std::vector<ManifestEntry> removals;  ///< an owned folder's old files to remove once committed
  bool committed = false, aborted = false;
};

/// Parses a journal; false when it is not one (then nothing is done).
bool parse_journal(const std::string& text, Journal& j) {
  const auto lines = lines_of(text);
  if (lines.empty() || lines[0].size() != 4 || lines[0][0] + " " + lines[0][1] + " " + lines[0][2] + " " + lines[0][3] != kJournalHeader)
    return false;
  std::unordered_map<std::string, std::size_t> by_index;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto& w = lines[i];
    if (w.empty()) continue;
    if (w[0] == "pid" && w.size() == 3) {
      j.pid = std::strtol(w[1].c_str(), nullptr, 10);
      j.start = std::strtoull(w[2].c_str(), nullptr, 10);
    } else if (w[0] == "e" && w.size() == 6) {
      JournalEntry e;
      e.existed = w[2] == "1";
      e.temp_ino = std::strtoull(w[3].c_str(), nullptr, 10);
      if (!unhex(w[4], e.temp) || !unhex(w[5], e.name) || !plain_name(e.temp) || !plain_name(e.name) ||
          e.temp.rfind(".cmr-tmp.", 0) != 0)
        return false;
      by_index[w[1]] = j.entries.size();
      j.entries.push_back(std::move(e));
    } else if (w[0] == "b" && w.size() == 4) {
      auto it = by_index.find(w[1]);
      if (it == by_index.end()) return false;
      JournalEntry& e = j.entries[it->second];
      e.backup_ino = std::strtoull(w[2].c_str(), nullptr, 10);
      if (!unhex(w[3], e.backup) || !plain_name(e.backup) || e.backup.rfind(".cmr-bak.", 0) != 0) return false;
    } else if (w[0] == "r" && w.size() == 5) {
      ManifestEntry m;
      m.ino = std::strtoull(w[1].c_str(), nullptr, 10);
      m.size = std::strtoull(w[2].c_str(), nullptr, 10);
      m.mtime_ns = std::strtoll(w[3].c_str(), nullptr, 10);
      if (!unhex(w[4], m.name) || !plain_name(m.name)) return false;
      j.removals.push_back(std::move(m));
    } else if (w[0] == "commit") {
      j.committed = true;
    } else if (w[0] == "abort") {
      j.aborted = true;
    }
  }
  return j.pid > 0;
}

/// Whether recovery may rename over `name`: it is absent, or the folder is
/// not shared, or it is this user's file. Otherwise it is noted in `refused`.
bool may_replace(int dirfd, bool shared, const std::string& name, std::vector<std::string>& refused) {
  struct stat st {};
  if (::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) return errno == ENOENT;
  if (!shared || st.st_uid == ::geteuid()) return true;
  refused.push_back(name + " (owned by uid " + std::to_string(st.st_uid) + ", not this user, in a shared folder)");
  return false;
}

/// Unlinks the entry if it is this user's single-linked regular file with `ino`.
void unlink_own(int dirfd, const std::string& name, unsigned long long ino) {
  struct stat st {};
  if (regular_entry(dirfd, name, st) && own_single_file(st, ino)) ::unlinkat(dirfd, name.c_str(), 0);
}

/// Whether a backup entry is the one the journal made: a regular file with
/// the journaled inode, at most two links (before the rename it is also the
/// old file's name), and this user's unless the folder is private.
bool journaled_backup(int dirfd, bool shared, const JournalEntry& e, struct stat& st) {
  return !e.backup.empty() && regular_entry(dirfd, e.backup, st) &&
         static_cast<unsigned long long>(st.st_ino) == e.backup_ino && st.st_nlink <= 2 &&
         (!shared || st.st_uid == ::geteuid());
}

/// Finishes an interrupted commit as its journal says: after the commit
/// point ("commit"), forward (the staged files renamed into place, the old
/// owned files removed); before it, nothing was renamed yet, so only its
/// temporaries and backups go; after "abort" (a failed rename being undone),
/// back (the backups renamed over their names, new names removed).
void apply_journal(int dirfd, bool shared, const Journal& j, std::vector<std::string>& refused) {
  struct stat st {};
  if (j.committed && !j.aborted) {
    for (const JournalEntry& e : j.entries) {
      if (regular_entry(dirfd, e.temp, st) && own_single_file(st, e.temp_ino)) {
        if (may_replace(dirfd, shared, e.name, refused)) ::renameat(dirfd, e.temp.c_str(), dirfd, e.name.c_str());
        else ::unlinkat(dirfd, e.temp.c_str(), 0);
      }
      if (journaled_backup(dirfd, shared, e, st)) ::unlinkat(dirfd, e.backup.c_str(), 0);
    }
    for (const ManifestEntry& m : j.removals) remove_if_still_ours(dirfd, m);
    return;
  }
  for (const JournalEntry& e : j.entries) {
    if (j.aborted) {
      struct stat now {};
      const bool present = ::fstatat(dirfd, e.name.c_str(), &now, AT_SYMLINK_NOFOLLOW) == 0;
      if (journaled_backup(dirfd, shared, e, st)) {
        if (!(present && now.st_ino == st.st_ino) && may_replace(dirfd, shared, e.name, refused))
          ::renameat(dirfd, e.backup.c_str(), dirfd, e.name.c_str());
      } else if (!e.existed && present && S_ISREG(now.st_mode) && own_single_file(now, e.temp_ino)) {
        ::unlinkat(dirfd, e.name.c_str(), 0);  // a new file of the undone commit
      }
    }
    unlink_own(dirfd, e.temp, e.temp_ino);
    if (journaled_backup(dirfd, shared, e, st)) ::unlinkat(dirfd, e.backup.c_str(), 0);
  }
}

/// The pid in a hidden name ".cmr-KIND.PID.REST", or 0.
long hidden_pid(const std::string& n, std::size_t at) {
  const std::size_t end = n.find('.', at);
  if (end == std::string::npos || end == at || end - at > 10) return 0;
  for (std::size_t i = at; i < end; ++i)
    if (!std::isdigit(static_cast<unsigned char>(n[i]))) return 0;
  return std::stol(n.substr(at, end - at));
}

/// Recovery in one folder, under its lock (see clean_stale_hidden_files).
std::size_t recover_folder(int dirfd, const std::filesystem::path& folder) {
  const int scan_fd = ::dup(dirfd);
  if (scan_fd < 0) return 0;
  DIR* dir = ::fdopendir(scan_fd);
  if (dir == nullptr) {
    ::close(scan_fd);
    return 0;
  }
  ::rewinddir(dir);
  std::vector<std::string> journals, hidden;
  while (const dirent* e = ::readdir(dir)) {
    const std::string_view n(e->d_name);
    if (n.rfind(kJournalPrefix, 0) == 0) journals.emplace_back(n);
    else if (n.rfind(".cmr-tmp.", 0) == 0 || n.rfind(".cmr-bak.", 0) == 0) hidden.emplace_back(n);
  }
  ::closedir(dir);
  const bool shared = folder_shared(dirfd);
  const long self = ::getpid();
  std::vector<std::string> refused;
  std::size_t handled = 0;
  std::unordered_set<std::string> journaled;  // the temporaries and backups a journal of this user names
  for (const std::string& n : journals) {
    const long pid = hidden_pid(n, std::strlen(kJournalPrefix));
    if (pid == 0 || pid == self) continue;
    std::string text;
    uid_t owner = ::geteuid();
    if (!read_own_file(dirfd, n, text, &owner)) {
      struct stat st {};
      if (::fstatat(dirfd, n.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0)
        refused.push_back(n + (st.st_uid != ::geteuid() ? " (owned by uid " + std::to_string(st.st_uid) + ", not this user)"
                                                        : " (not a regular file with one link)"));
      continue;
    }
    Journal j;
    if (!parse_journal(text, j) || j.pid != pid) {
      refused.push_back(n + " (not a journal cmr wrote)");
      continue;
    }
    // A live process's journal is a commit in progress (it holds the lock
    // where flock works); a pid reused by another process is not it.
    if (process_alive(pid) && (j.start == 0 || process_start(pid) == j.start)) continue;
    for (const JournalEntry& e : j.entries) {
      journaled.insert(e.temp);
      if (!e.backup.empty()) journaled.insert(e.backup);
    }
    apply_journal(dirfd, shared, j, refused);
    ::unlinkat(dirfd, n.c_str(), 0);
    ++handled;
  }
  for (const std::string& n : hidden) {
    // ".cmr-KIND.PID.ATTEMPT.NAME"
    const long pid = hidden_pid(n, 9);
    if (pid == 0 || pid == self || journaled.count(n) > 0 || process_alive(pid)) continue;
    struct stat st {};
    if (::fstatat(dirfd, n.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
    if (n[5] == 't') {
      // A dead run's staged temporary (killed before its commit): nothing
      // refers to it. Only this user's own single file goes.
      if (S_ISREG(st.st_mode) && st.st_uid == ::geteuid() && st.st_nlink == 1) {
        ::unlinkat(dirfd, n.c_str(), 0);
        ++handled;
      }
    } else {
      // A backup no journal of this user names: never renamed anywhere (a
      // name proves nothing; it may be planted), never removed.
      refused.push_back(n + (st.st_uid != ::geteuid() ? " (owned by uid " + std::to_string(st.st_uid) + ", not this user)"
                                                      : " (no journal of an interrupted commit names it)"));
    }
  }
  if (!refused.empty()) {
    std::string line = "cmr: note: " + folder.string() + ": left alone, not rolled back: " + refused[0];
    if (refused.size() > 1) line += " and " + std::to_string(refused.size() - 1) + " more";
    for (char& c : line)
      if (c == '\n' || c == '\r') c = '?';
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  return handled;
}

}  // namespace

std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt) {
  return hidden_name("tmp", path, ::getpid(), attempt);
}

std::size_t clean_stale_hidden_files(const std::filesystem::path& folder) {
  FolderLocks lock;
  bool locked = false;
  const int fd = lock.lock(folder, &locked);
  if (fd < 0 || !locked) return 0;
  return recover_folder(fd, folder);
}

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
  for (const std::filesystem::path& f : folders) {
    bool locked = false;
    const int fd = locks.lock(f, &locked);
    // Another run committed into an owned folder since own_folder: it wins,
    // this run writes nothing (checked before recovery, which may finish a
    // dead run's manifest).
    std::optional<std::pair<unsigned long long, long long>> noted;
    {
      const std::lock_guard lock(stamps_mutex);
      if (const auto it = stamps.find(this); it != stamps.end())
        if (const auto at = it->second.find(f.string()); at != it->second.end()) noted = at->second;
    }
    if (noted && manifest_stamp(f) != *noted) {
      discard();
      throw EnvironmentError(f.string() + ": another cmr run wrote this folder while this one ran; its files are "
                             "kept and this run's are not written (run it again)");
    }
    if (fd >= 0 && locked) recover_folder(fd, f);  // an interrupted commit here is finished or undone first
  }
  // A file this program read (note_read) that another one wrote since: not
  // replaced (two editors saving one file), checked under the folders' locks.
  {
    const std::lock_guard lock(reads_mutex);
    for (const Staged& s : staged_) {
      if (s.temp.empty() || reads.empty()) continue;
      const auto it = reads.find(read_key(s.target));
      if (it == reads.end() || read_stamp(s.target) == it->second) continue;
      const std::filesystem::path changed = s.path;
      discard();
      throw EnvironmentError(changed.string() + ": changed on disk since this program read it (another editor or "
                             "program saved it); not written, so nothing of it is lost");
    }
  }

  // Owned folders: this run's file names there, and the manifest staged last.
  struct Owned {
    std::filesystem::path folder;
    std::vector<ManifestEntry> old;
    std::unordered_set<std::string> names;
  };
  std::vector<Owned> owned;
  for (const std::filesystem::path& f : owned_folders_) {
    const int dirfd = locks.lock(f);
    std::vector<std::string> refused;
    Owned o{f, dirfd >= 0 ? read_manifest(dirfd, refused) : std::vector<ManifestEntry>{}, {}};
    if (!refused.empty())
      std::fprintf(stderr, "cmr: note: %s: %s: its files are left alone\n", f.string().c_str(), refused[0].c_str());
    const std::string key = folder_key(f);
    std::string manifest = std::string(kManifestHeader) + "\n";
    for (const Staged& s : staged_) {
      if (s.temp.empty() || folder_key(folder_of(s.target)) != key) continue;
      const std::string name = s.target.filename().string();
      struct stat st {};
      if (name.find('\n') != std::string::npos || ::lstat(s.temp.c_str(), &st) != 0) continue;
      o.names.insert(name);
      manifest += std::to_string(st.st_ino) + " " + std::to_string(st.st_size) + " " + std::to_string(mtime_ns(st)) +
                  " " + name + "\n";
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

  // The rename order: the files in staging order, then the manifests, then
  // the set's marker (commit_last: a report's report.json), so that a
  // reader who sees the marker's new version sees the whole new set.
  std::vector<std::size_t> files;  // indices of the staged files (not streams)
  for (int pass = 0; pass < 3; ++pass)
    for (std::size_t i = 0; i < staged_.size(); ++i) {
      const Staged& s = staged_[i];
      if (s.temp.empty()) continue;
      const int p = !last_.empty() && s.path.string() == last_ ? 2 : (s.manifest ? 1 : 0);
      if (p == pass) files.push_back(i);
    }

  // One journal per folder, written before any backup or rename.
  std::vector<std::unique_ptr<JournalFile>> journals;
  std::unordered_map<int, std::size_t> journal_of_fd;
  std::vector<JournalFile*> journal_of_file(files.size(), nullptr);
  const auto fail_before_commit_point = [&](const auto& undo_backups) {
    undo_backups();
    for (auto& j : journals) j->remove();
    discard();
  };
  std::vector<Kept> kept;
  kept.reserve(files.size());
  try {
    for (std::size_t k = 0; k < files.size(); ++k) {
      const Staged& s = staged_[files[k]];
      const int dirfd = locks.lock(folder_of(s.target));
      if (dirfd < 0) continue;  // renamed without a journal (the rename reports why it fails)
      auto it = journal_of_fd.find(dirfd);
      if (it == journal_of_fd.end()) {
        journals.push_back(std::make_unique<JournalFile>());
        journals.back()->create(dirfd, s.path.parent_path() == s.target.parent_path() ? s.path : s.target);
        it = journal_of_fd.emplace(dirfd, journals.size() - 1).first;
      }
      JournalFile& j = *journals[it->second];
      journal_of_file[k] = &j;
      struct stat st {}, old {};
      if (::lstat(s.temp.c_str(), &st) != 0) throw_errno(s.path, errno);
      const bool existed = ::lstat(s.target.c_str(), &old) == 0;
      j.append("e " + std::to_string(k) + " " + (existed ? "1 " : "0 ") + std::to_string(st.st_ino) + " " +
               hex_of(s.temp.filename().string()) + " " + hex_of(s.target.filename().string()) + "\n");
    }
    for (const Owned& o : owned) {
      const int dirfd = locks.lock(o.folder);
      auto it = journal_of_fd.find(dirfd);
      if (it == journal_of_fd.end()) continue;
      std::string lines;
      for (const ManifestEntry& e : o.old)
        if (o.names.count(e.name) == 0)
          lines += "r " + std::to_string(e.ino) + " " + std::to_string(e.size) + " " + std::to_string(e.mtime_ns) + " " +
                   hex_of(e.name) + "\n";
      journals[it->second]->append(lines);
    }
    // Each old file kept as a backup (the in-process undo), journaled as made.
    for (std::size_t k = 0; k < files.size(); ++k) {
      kept.push_back(keep_old(staged_[files[k]].target));
      struct stat st {};
      if (!kept[k].link.empty() && journal_of_file[k] != nullptr && ::lstat(kept[k].link.c_str(), &st) == 0)
        journal_of_file[k]->append("b " + std::to_string(k) + " " + std::to_string(st.st_ino) + " " +
                                   hex_of(kept[k].link.filename().string()) + "\n");
    }
    // The commit point: from here on, recovery finishes this commit.
    for (auto& j : journals) j->append("commit\n");
    for (auto& j : journals) j->sync();
  } catch (...) {
    fail_before_commit_point([&] {
      for (const Kept& k : kept)
        if (!k.link.empty()) ::unlink(k.link.c_str());
    });
    throw;
  }

  std::size_t done = 0;
  for (; done < files.size(); ++done) {
    const Staged& s = staged_[files[done]];
    if (::rename(s.temp.c_str(), s.target.c_str()) != 0) break;
  }
  const int error = errno;
  if (done < files.size()) {  // undo: the old files back, new ones away
    try {  // the journal says so first: a kill during the undo is undone too
      for (auto& j : journals) j->append("abort\n");
      for (auto& j : journals) j->sync();
    } catch (...) {
    }
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
    for (auto& j : journals) j->remove();
    staged_.clear();  // nothing of the set is left to remove but the folders it made
    discard();
    throw_errno(failed, error);
  }
  committed_ = true;
  {  // the files this program noted (note_read) are now the ones it wrote
    const std::lock_guard lock(reads_mutex);
    if (!reads.empty())
      for (const Staged& s : staged_)
        if (!s.temp.empty())
          if (const auto it = reads.find(read_key(s.target)); it != reads.end())
            if (const auto now = read_stamp(s.target)) it->second = *now;
  }
  // The files cmr wrote there last time and this run did not: removed when
  // they are still cmr's (this user's, one link, same inode, size and
  // time), so the folder holds this set.
  for (const Owned& o : owned) {
    const int dirfd = locks.lock(o.folder);
    if (dirfd < 0) continue;
    for (const ManifestEntry& e : o.old)
      if (o.names.count(e.name) == 0) remove_if_still_ours(dirfd, e);
  }
  for (auto& j : journals) j->remove();
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
