#include "io/output.hpp"
#include "io/output_detail.hpp"
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

// The file layer under the output set (output.hpp): output names,
// temporary and hidden files, folder locks, the manifest of an owned folder,
// the commit journal, and the recovery of an interrupted commit. OutputSet
// itself is in output.cpp.

namespace cmr {

using namespace output_detail;  // what the parts share (output_detail.hpp)

namespace output_detail {

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

}  // namespace output_detail

void check_output_path(const std::filesystem::path& path, const std::string& option) {
  check_output_name(path);
  const std::filesystem::path folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(option + " " + path.string() + ": the folder " + folder.string() + " does not exist");
  if (path.filename().empty() || std::filesystem::is_directory(path, ec))
    throw InputError(option + " " + path.string() + ": is a directory");
}

namespace output_detail {

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

}  // namespace output_detail

namespace {

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

}  // namespace

namespace output_detail {

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

}  // namespace output_detail

namespace {

/// Whether process `pid` exists (kill(pid, 0) reaches it or is refused).
bool process_alive(long pid) {
  if (pid <= 0 || pid != static_cast<pid_t>(pid)) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

namespace output_detail {

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

long long mtime_ns(const struct stat& st) {
  return static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
}

}  // namespace output_detail

namespace {

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

}  // namespace

namespace output_detail {

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

}  // namespace output_detail

namespace {

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

}  // namespace

namespace output_detail {

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

}  // namespace output_detail

namespace {

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

}  // namespace

namespace output_detail {

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

}  // namespace output_detail

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

}  // namespace cmr
