#pragma once
/// Lost updates between processes (issue 42 item 6): two editors that opened
/// the same file both save it; the second must not silently replace the
/// first one's work. Kept apart from io/output.hpp so that its users need not
/// be rebuilt.
#include <filesystem>

namespace cmr {

/// Notes the file `path`, which this process has just read and may write
/// back (an editor's spline file or .glif), as it is now (device, inode,
/// size, modification time). Every OutputSet commit that replaces it later
/// checks, under the folder's lock, that it is still that file: when another
/// process (a second editor) has written it since, the commit writes
/// nothing and throws EnvironmentError "PATH: changed on disk since this
/// program read it (another editor or program saved it); not written, so
/// nothing of it is lost" (exit 3). A commit that writes it notes the new
/// file, so the same program may save again. A path that is no file is not
/// noted.
void note_read(const std::filesystem::path& path);

}  // namespace cmr
