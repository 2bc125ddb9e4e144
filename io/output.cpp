#include "io/output.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

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

/// What keep_old found at an output path before the commit.
struct Kept {
  bool existed = false;
  std::filesystem::path link;  ///< hard link to the old file; empty when none could be made
};

/// Keeps the file now at `path` (if any) as a hard link under a free
/// temporary name, so that a failed commit can put it back. File systems
/// without hard links give no link (the commit goes on without the undo).
Kept keep_old(const std::filesystem::path& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {};
  for (int attempt = 0; attempt < kTempNameAttempts; ++attempt) {
    std::filesystem::path name = temp_name_for(path, attempt);
    if (::link(path.c_str(), name.c_str()) == 0) return {true, std::move(name)};
    if (errno != EEXIST) break;
  }
  return {true, {}};
}

}  // namespace

std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt) {
  const std::filesystem::path folder = path.parent_path();
  std::string name = ".";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string&&
  name += path.filename().string();
  name += '.';
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(attempt);
  name += ".tmp";
  return folder.empty() ? std::filesystem::path(name) : folder / name;
}

OutputSet::~OutputSet() { discard(); }

void OutputSet::discard() noexcept {
  if (committed_) return;
  for (const Staged& s : staged_) ::unlink(s.temp.c_str());
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

void OutputSet::stage(const std::filesystem::path& path, std::string_view bytes) {
  CMR_CHECK(!committed_);
  struct stat st {};
  if (path.filename().empty() || (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))) throw_errno(path, EISDIR);
  const std::filesystem::path key = std::filesystem::absolute(path).lexically_normal();
  for (const Staged& s : staged_)
    if (std::filesystem::absolute(s.path).lexically_normal() == key) throw InputError(path.string() + ": named twice");
  auto [temp, fd] = create_temp(path);
  staged_.push_back({path, std::move(temp)});
  const bool ok = write_all(fd, bytes) && ::fsync(fd) == 0;
  const int error = errno;
  if (::close(fd) != 0 && ok) throw_errno(path, errno);
  if (!ok) throw_errno(path, error);
}

StagedStream OutputSet::stage_stream(const std::filesystem::path& path) {
  CMR_CHECK(!committed_);
  struct stat st {};
  if (path.filename().empty() || (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))) throw_errno(path, EISDIR);
  const std::filesystem::path key = std::filesystem::absolute(path).lexically_normal();
  for (const Staged& s : staged_)
    if (std::filesystem::absolute(s.path).lexically_normal() == key) throw InputError(path.string() + ": named twice");
  auto [temp, fd] = create_temp(path);
  staged_.push_back({path, std::move(temp)});
  return StagedStream(path, fd);
}

StagedStream& StagedStream::operator=(StagedStream&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(o.path_);
    fd_ = o.fd_;
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
}

void StagedStream::close() {
  CMR_CHECK(fd_ >= 0);
  const bool ok = ::fsync(fd_) == 0;
  const int error = errno;
  const int rc = ::close(fd_);
  fd_ = -1;
  if (!ok) throw_errno(path_, error);
  if (rc != 0) throw_errno(path_, errno);
}

void OutputSet::commit() {
  CMR_CHECK(!committed_);
  FolderLocks locks;
  for (const Staged& s : staged_) locks.lock(folder_of(s.path));
  std::vector<Kept> kept;
  kept.reserve(staged_.size());
  for (const Staged& s : staged_) kept.push_back(keep_old(s.path));
  std::size_t done = 0;
  for (; done < staged_.size(); ++done) {
    if (::rename(staged_[done].temp.c_str(), staged_[done].path.c_str()) != 0) break;
  }
  const int error = errno;
  if (done < staged_.size()) {  // undo: the old files back, new ones away
    for (std::size_t i = 0; i < done; ++i) {
      if (!kept[i].link.empty()) ::rename(kept[i].link.c_str(), staged_[i].path.c_str());
      else if (!kept[i].existed) ::unlink(staged_[i].path.c_str());
    }
  }
  for (std::size_t i = done < staged_.size() ? done : 0; i < kept.size(); ++i)
    if (!kept[i].link.empty()) ::unlink(kept[i].link.c_str());
  if (done < staged_.size()) {
    const std::filesystem::path failed = staged_[done].path;
    for (std::size_t i = done; i < staged_.size(); ++i) ::unlink(staged_[i].temp.c_str());
    staged_.clear();  // nothing of the set is left to remove but the folders it made
    discard();
    throw_errno(failed, error);
  }
  committed_ = true;
  for (const Staged& s : staged_) sync_folder(folder_of(s.path));
}

std::vector<std::filesystem::path> OutputSet::paths() const {
  std::vector<std::filesystem::path> out;
  for (const Staged& s : staged_) out.push_back(s.path);
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

}  // namespace cmr
