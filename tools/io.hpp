#pragma once
/// Output helpers shared by the cmr libraries and the command: the
/// environment error type, the one atomic file writer, and HTML escaping.
/// Nothing here depends on the command line (CLI11).
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cmr {

/// An environment failure: no Vulkan device, a full disk, an I/O error, a
/// permission the process lacks. The command maps it to exit code 3 (bad
/// user data is cmr::InputError, exit code 2).
class EnvironmentError : public std::runtime_error {
 public:
  explicit EnvironmentError(const std::string& message) : std::runtime_error(message) {}
};

/// How many temporary names write_file_atomic tries before it gives up.
inline constexpr int kTempNameAttempts = 100;

/// The temporary name write_file_atomic tries on its `attempt`-th try for
/// `path`: a hidden file beside it, ".NAME.PID-ATTEMPT.tmp", so that the
/// rename stays inside one file system.
std::filesystem::path temp_name_for(const std::filesystem::path& path, int attempt);

/// Writes `bytes` to `path` so that readers see the old file or the whole new
/// one, never a part: the bytes go to a new temporary file beside `path`
/// (created with O_CREAT | O_EXCL | O_NOFOLLOW, so an existing file or a
/// symbolic link at a temporary name is never opened; taken names are
/// skipped), which is flushed to disk (fsync) and then renamed over `path`.
/// On any failure the temporary file is removed and `path` is left as it was.
/// Throws
///  - InputError "PATH: is a directory" when `path` is a directory;
///  - InputError when `path`'s folder does not exist or is not a folder;
///  - EnvironmentError "PATH: <strerror>" for every other failure (no space,
///    I/O error, permission, every temporary name taken).
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

/// Text made safe for HTML element content and attribute values.
std::string html_escape(std::string_view text);

}  // namespace cmr
