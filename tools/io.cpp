#include "tools/io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "spline/errors.hpp"

namespace cmr {

namespace {

/// The error for a failed system call on `path`: the caller's fault for the
/// errno values a user fixes by choosing another path, the environment's for
/// the rest.
[[noreturn]] void throw_errno(const std::filesystem::path& path, int error) {
  const std::string message = path.string() + ": " + std::strerror(error);
  switch (error) {
    case EISDIR: throw InputError(path.string() + ": is a directory");
    case ENOENT:
    case ENOTDIR:
    case ENAMETOOLONG: throw InputError(message + " (does the folder exist?)");
    default: throw EnvironmentError(message);
  }
}

/// Owns a temporary file: closes it, and removes it unless released.
class TempFile {
 public:
  TempFile(std::filesystem::path path, int fd) : path_(std::move(path)), fd_(fd) {}
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!released_) ::unlink(path_.c_str());
  }
  int fd() const { return fd_; }
  const std::filesystem::path& path() const { return path_; }
  /// Closes the descriptor; errno is set when it returns false.
  bool close() {
    const int fd = fd_;
    fd_ = -1;
    return ::close(fd) == 0;
  }
  void release() { released_ = true; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  bool released_ = false;
};

/// Creates the first free temporary name beside `path`, never following a link.
TempFile create_temp(const std::filesystem::path& path) {
  for (int attempt = 0; attempt < kTempNameAttempts; ++attempt) {
    const std::filesystem::path name = temp_name_for(path, attempt);
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return TempFile(name, fd);
    if (errno != EEXIST) throw_errno(path, errno);
  }
  throw EnvironmentError(path.string() + ": every temporary name beside it is taken (" +
                         temp_name_for(path, 0).filename().string() + " ...)");
}

/// Writes all of `bytes`, retrying short writes and interruptions.
void write_all(const TempFile& file, const std::filesystem::path& path, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(file.fd(), bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_errno(path, errno);
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

/// Flushes the folder's entry for the renamed file; best effort (some file
/// systems refuse fsync on folders, and the data itself is already on disk).
void sync_folder(const std::filesystem::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt) {
  const std::filesystem::path folder = path.parent_path();
  std::string name = ".";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string&&
  name += path.filename().string();
  name += "." + std::to_string(::getpid()) + "-" + std::to_string(attempt) + ".tmp";
  return folder.empty() ? std::filesystem::path(name) : folder / name;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) throw_errno(path, EISDIR);
  if (path.filename().empty()) throw_errno(path, EISDIR);  // "dir/": names a folder
  TempFile file = create_temp(path);
  write_all(file, path, bytes);
  if (::fsync(file.fd()) != 0) throw_errno(path, errno);
  if (!file.close()) throw_errno(path, errno);
  if (::rename(file.path().c_str(), path.c_str()) != 0) throw_errno(path, errno);
  file.release();
  sync_folder(path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path());
}

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace cmr
