// io/output: the atomic file writer (whole file or nothing, no links followed,
// typed errors) and HTML escaping.
#include "io/output.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "spline/errors.hpp"

namespace cmr {
namespace {

namespace fs = std::filesystem;

/// A fresh, empty folder for one test (tests run as separate processes).
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cmr_io_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(WriteFileAtomic, WritesAndReplacesLeavingNoTemporary) {
  const fs::path dir = scratch("replace");
  const fs::path out = dir / "a.json";
  write_file_atomic(out, "first");
  EXPECT_EQ(read(out), "first");
  const std::string binary("\0\x01\xff tail", 8);
  write_file_atomic(out, binary);
  EXPECT_EQ(read(out), binary) << "bytes after a NUL are written too";
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"a.json"});
}

// A file written in pieces (report/corpus.hpp streams report.json): nothing
// shows until commit, the pieces arrive in order, an uncommitted set leaves
// nothing, and a path staged twice is refused as for stage().
TEST(OutputSet, StagedStreamWritesPiecesThatAppearOnlyAtCommit) {
  const fs::path dir = scratch("stream");
  {
    OutputSet set;
    StagedStream s = set.stage_stream(dir / "big.json");
    s.write("[1,");
    s.write("2]");
    s.close();
    EXPECT_FALSE(fs::exists(dir / "big.json"));
    EXPECT_THROW(set.stage(dir / "big.json", "x"), InputError);
    set.commit();
  }
  EXPECT_EQ(read(dir / "big.json"), "[1,2]");
  {
    OutputSet set;
    StagedStream s = set.stage_stream(dir / "gone.json");
    s.write("half");
  }  // no commit: the temporary goes with the set
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"big.json"});
}

TEST(WriteFileAtomic, DirectoryAsOutputIsAnInputErrorSayingSo) {
  const fs::path dir = scratch("directory");
  const fs::path target = dir / "out";
  fs::create_directory(target);
  try {
    write_file_atomic(target, "x");
    FAIL() << "no error for a directory as output";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), target.string() + ": is a directory");
  }
  EXPECT_TRUE(fs::is_directory(target));
  EXPECT_TRUE(fs::is_empty(target));
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"out"}) << "no temporary left beside it";
}

TEST(WriteFileAtomic, MissingFolderIsAnInputError) {
  const fs::path dir = scratch("missing") / "no_such_folder";
  EXPECT_THROW(write_file_atomic(dir / "x.png", "x"), InputError);
  EXPECT_FALSE(fs::exists(dir));
}

TEST(WriteFileAtomic, SymlinksAtTemporaryNamesAreNotFollowed) {
  const fs::path dir = scratch("symlink");
  const fs::path out = dir / "report.html", victim = dir / "victim.txt", absent = dir / "absent.txt";
  put(victim, "precious");
  // The first temporary names the writer would try: two links to an existing
  // file and one dangling link (O_CREAT through it would create `absent`).
  fs::create_symlink(victim, temp_name_for(out, 0));
  fs::create_symlink(victim, temp_name_for(out, 1));
  fs::create_symlink(absent, temp_name_for(out, 2));
  write_file_atomic(out, "new contents");
  EXPECT_EQ(read(out), "new contents");
  EXPECT_EQ(read(victim), "precious") << "a link at a temporary name was followed";
  EXPECT_FALSE(fs::exists(absent)) << "a dangling link at a temporary name was followed";
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(fs::is_symlink(temp_name_for(out, k))) << "attempt " << k;
  EXPECT_FALSE(fs::is_symlink(out));
}

TEST(WriteFileAtomic, ExistingFileIsUntouchedWhenTheWriteFails) {
  const fs::path dir = scratch("fails");
  const fs::path out = dir / "labels.pgm";
  put(out, "old");
  // A file size limit makes write() fail with EFBIG half way (SIGXFSZ ignored).
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  rlimit small = before;
  small.rlim_cur = 1000;
  auto* old_handler = std::signal(SIGXFSZ, SIG_IGN);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  std::string message;
  bool environment = false;
  try {
    write_file_atomic(out, std::string(5000, 'x'));
  } catch (const EnvironmentError& e) {
    environment = true;
    message = e.what();
  } catch (const std::exception& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_TRUE(environment) << "got: " << message;
  EXPECT_EQ(message, out.string() + ": " + std::strerror(EFBIG));
  EXPECT_EQ(read(out), "old");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"labels.pgm"}) << "the temporary was not removed";
}

TEST(WriteFileAtomic, EveryTemporaryNameTakenIsAnEnvironmentErrorAndChangesNothing) {
  const fs::path dir = scratch("taken");
  const fs::path out = dir / "fig8.png";
  put(out, "old");
  for (int k = 0; k < kTempNameAttempts; ++k) fs::create_directory(temp_name_for(out, k));
  EXPECT_THROW(write_file_atomic(out, "new"), EnvironmentError);
  EXPECT_EQ(read(out), "old");
  EXPECT_EQ(names_in(dir).size(), static_cast<std::size_t>(kTempNameAttempts) + 1);
}

TEST(TempNameFor, IsAHiddenSiblingThatDiffersPerAttempt) {
  const fs::path out = fs::path("some") / "dir" / "x.png";
  const fs::path a = temp_name_for(out, 0), b = temp_name_for(out, 1);
  EXPECT_EQ(a.parent_path(), out.parent_path());
  EXPECT_EQ(a.filename().string().front(), '.');
  EXPECT_NE(a, b);
  EXPECT_EQ(temp_name_for("x.png", 0).parent_path(), fs::path()) << "a bare name stays in the current folder";
}

TEST(HtmlEscape, EscapesTheFiveSpecialsOnly) {
  EXPECT_EQ(html_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&#39;");
  EXPECT_EQ(html_escape("κ plain €𝄞"), "κ plain €𝄞") << "well-formed UTF-8 passes unchanged";
}

TEST(HtmlEscape, BytesThatAreNotUtf8BecomeReplacementCharacters) {
  const std::string fffd = "\xEF\xBF\xBD";
  EXPECT_EQ(html_escape("caf\xe9.json"), "caf" + fffd + ".json") << "Latin-1 e-acute";
  EXPECT_EQ(html_escape("\xC0\xAF"), fffd + fffd) << "overlong '/'";
  EXPECT_EQ(html_escape("\xED\xA0\x80"), fffd + fffd + fffd) << "UTF-16 surrogate";
  EXPECT_EQ(html_escape("\xF4\x90\x80\x80"), fffd + fffd + fffd + fffd) << "above U+10FFFF";
  EXPECT_EQ(html_escape("a\xE2\x82"), "a" + fffd + fffd) << "truncated sequence at the end";
  EXPECT_EQ(html_escape("\xff<"), fffd + "&lt;");
}

// OutputSet: staged files appear together at commit, or not at all.
TEST(OutputSet, NothingChangesUntilCommitAndNothingIsLeftWithoutIt) {
  const fs::path dir = scratch("set_abandoned");
  put(dir / "a.pgm", "old a");
  {
    OutputSet set;
    set.stage(dir / "a.pgm", "new a");
    set.stage(dir / "b.png", "new b");
    EXPECT_EQ(read(dir / "a.pgm"), "old a") << "staging replaced a file";
    EXPECT_FALSE(fs::exists(dir / "b.png"));
  }  // destroyed without commit: an exception on the way
  EXPECT_EQ(read(dir / "a.pgm"), "old a");
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"a.pgm"}) << "temporaries left";
}

TEST(OutputSet, CommitPutsEveryFileInPlaceAndLeavesNoTemporaryOrBackup) {
  const fs::path dir = scratch("set_commit");
  put(dir / "a.pgm", "old a");
  OutputSet set;
  set.stage(dir / "a.pgm", "new a");
  set.stage(dir / "b.png", "new b");
  set.commit();
  EXPECT_EQ(read(dir / "a.pgm"), "new a");
  EXPECT_EQ(read(dir / "b.png"), "new b");
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"a.pgm", "b.png"}));
  EXPECT_EQ(set.paths(), (std::vector<fs::path>{dir / "a.pgm", dir / "b.png"}));
}

TEST(OutputSet, AFailedRenameRestoresTheFilesAlreadyRenamed) {
  const fs::path dir = scratch("set_undo");
  put(dir / "a.pgm", "old a");
  put(dir / "c.pgm", "old c");
  OutputSet set;
  set.stage(dir / "a.pgm", "new a");
  set.stage(dir / "n.pgm", "new n");  // did not exist before
  set.stage(dir / "b.png", "new b");
  set.stage(dir / "c.pgm", "new c");
  // After staging, b.png becomes a non-empty folder: its rename fails (EISDIR).
  fs::create_directory(dir / "b.png");
  put(dir / "b.png" / "inside", "x");
  EXPECT_THROW(set.commit(), InputError);
  EXPECT_EQ(read(dir / "a.pgm"), "old a") << "the first file was not restored";
  EXPECT_FALSE(fs::exists(dir / "n.pgm")) << "a new file of a failed set was left";
  EXPECT_EQ(read(dir / "c.pgm"), "old c");
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"a.pgm", "b.png", "c.pgm"})) << "temporaries or backups left";
}

TEST(OutputSet, CommitWaitsForTheFolderLockOfAnotherCommit) {
  const fs::path dir = scratch("set_lock");
  put(dir / "a.pgm", "old");
  // Another commit holds the folder (flock locks belong to an open file
  // description, so a second open in this process contends like a process).
  const int held = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX), 0);
  OutputSet set;
  set.stage(dir / "a.pgm", "new");
  std::thread committer([&] { set.commit(); });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(read(dir / "a.pgm"), "old") << "the commit did not wait for the folder lock";
  ::flock(held, LOCK_UN);
  ::close(held);
  committer.join();
  EXPECT_EQ(read(dir / "a.pgm"), "new");
}

TEST(OutputSet, FoldersItCreatedAreRemovedWhenNotCommitted) {
  const fs::path dir = scratch("set_folders");
  {
    OutputSet set;
    set.create_folder(dir / "x" / "y");
    set.stage(dir / "x" / "y" / "index.html", "page");
    EXPECT_TRUE(fs::is_directory(dir / "x" / "y"));
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "a created folder was left";
  OutputSet kept;
  kept.create_folder(dir / "x" / "y");
  kept.stage(dir / "x" / "y" / "index.html", "page");
  kept.commit();
  EXPECT_EQ(read(dir / "x" / "y" / "index.html"), "page");
}

TEST(OutputSet, APathStagedTwiceOrAFileAsFolderIsAnInputError) {
  const fs::path dir = scratch("set_twice");
  OutputSet set;
  set.stage(dir / "a.pgm", "1");
  EXPECT_THROW(set.stage(dir / "." / "a.pgm", "2"), InputError);
  put(dir / "file", "x");
  EXPECT_THROW(set.create_folder(dir / "file" / "sub"), InputError);
}

}  // namespace
}  // namespace cmr
