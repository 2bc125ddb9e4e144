#pragma once
// Internal to cmr::io: what the output set (output.cpp) and its file layer
// (output_files.cpp) share. Not for users of the library (io/output.hpp).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace cmr::output_detail {

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

/// What keep_old found at an output path before the commit.
struct Kept {
  bool existed = false;
  std::filesystem::path link;  ///< hard link to the old file; empty when none could be made
};

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

// Defined in output_files.cpp:
void check_output_name(const std::filesystem::path& path);
void check_shared_link(const std::filesystem::path& path, const struct stat& link);
[[noreturn]] void throw_errno(const std::filesystem::path& path, int error);
std::pair<std::filesystem::path, int> create_temp(const std::filesystem::path& path);
bool write_all(int fd, std::string_view bytes);
std::filesystem::path folder_of(const std::filesystem::path& path);
void sync_folder(const std::filesystem::path& folder);
Kept keep_old(const std::filesystem::path& path);
bool is_stdout_alias(const std::filesystem::path& path);
bool copy_spool(int from, int to);
long long mtime_ns(const struct stat& st);
std::string hex_of(std::string_view s);
std::vector<ManifestEntry> read_manifest(int dirfd, std::vector<std::string>& refused);
void remove_if_still_ours(int dirfd, const ManifestEntry& e);
unsigned long long process_start(long pid);
std::size_t recover_folder(int dirfd, const std::filesystem::path& folder);

}  // namespace cmr::output_detail
