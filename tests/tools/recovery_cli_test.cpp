// Issue 42 E1 and E2, end to end through the cmr binary: recovery acts only
// on files this user made and a journal names (planted backups and
// manifests, by another user in a sticky folder and by the same user), and
// a commit killed (SIGKILL, strace fault injection) at any rename, link,
// unlink or sync leaves, after the next commit into the folder, one run's
// whole set: never report.json of one run beside index.html of another.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "tests/cli_util.hpp"

namespace cmr::test {
namespace {

/// A fresh folder for one test; `mode` set explicitly (umask aside).
fs::path fresh(const std::string& name, mode_t mode = 0755) {
  const fs::path d = scratch() / ("rec_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  ::chmod(scratch().c_str(), 0755);  // another user must reach it
  ::chmod(d.c_str(), mode);
  return d;
}

/// The pid of a process that has exited (and been reaped).
long dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

std::string spline_file(const std::string& name) {
  const std::string text = slurp(fs::path(CMR_SOURCE_DIR) / "examples/uniform.json");
  return write(name, text);
}

/// Runs `shell` as user nobody (setpriv); false when that is not possible
/// here (not root, no setpriv).
bool as_nobody(const std::string& shell) {
  const std::string cmd = "setpriv --reuid=nobody --regid=nogroup --clear-groups sh -c '" + shell + "'";
  return std::system(cmd.c_str()) == 0;
}

/// How many "cmr: note: " lines `err` holds (other notes, such as the CPU
/// backend's, aside).
int notes(const std::string& err) {
  int n = 0;
  for (std::size_t at = 0; (at = err.find("cmr: note: ", at)) != std::string::npos; ++at) ++n;
  return n;
}

bool can_be_nobody() {
  return ::geteuid() == 0 && std::system("command -v setpriv >/dev/null && id nobody >/dev/null 2>&1") == 0;
}

// E1, the review's reproducer: user nobody plants ".cmr-bak.DEAD.0.cleanup.sh"
// in a sticky, world-writable folder; root's commit into that folder leaves
// root's cleanup.sh as it was and says why in one line.
TEST(RecoveryCli, AnotherUsersPlantedBackupInAStickyFolderIsNeverRolledBack) {
  if (!can_be_nobody()) GTEST_SKIP() << "needs root and setpriv (a second user)";
  const fs::path dir = fresh("sticky_bak", 01777);
  const fs::path victim = dir / "cleanup.sh";
  std::ofstream(victim) << "echo root's own script\n";
  const std::string planted = ".cmr-bak." + std::to_string(dead_pid()) + ".0.cleanup.sh";
  ASSERT_TRUE(as_nobody("echo echo ATTACKER CODE RUNS > " + (dir / planted).string()));
  ASSERT_TRUE(fs::exists(dir / planted));
  const Outcome r = run("knots " + spline_file("u.json") + " clamp --out " + (dir / "out.json").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(victim), "echo root's own script\n") << "a planted backup was renamed over root's file";
  struct stat st {};
  ASSERT_EQ(::stat(victim.c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, 0u);
  EXPECT_TRUE(fs::exists(dir / planted)) << "another user's file was removed";
  EXPECT_NE(r.err.find("cmr: note: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(planted + " (owned by uid"), std::string::npos) << r.err;
  EXPECT_EQ(notes(r.err), 1) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out.json"));
}

// E1: a ".cmr-manifest" planted by another user, naming root's victim.cfg by
// its inode and size (the review's format) or with its exact time as well,
// removes nothing when root reports into that folder.
TEST(RecoveryCli, AnotherUsersPlantedManifestRemovesNothing) {
  if (!can_be_nobody()) GTEST_SKIP() << "needs root and setpriv (a second user)";
  const fs::path dir = fresh("sticky_manifest", 01777);
  const fs::path victim = dir / "victim.cfg";
  std::ofstream(victim) << "root's configuration\n";
  struct stat st {};
  ASSERT_EQ(::stat(victim.c_str(), &st), 0);
  const long long ns = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  const std::string id = std::to_string(st.st_ino) + " " + std::to_string(st.st_size);
  for (const std::string& body : {"cmr output manifest 1\\n" + id + " victim.cfg\\n",
                                  "cmr output manifest 2\\n" + id + " " + std::to_string(ns) + " victim.cfg\\n"}) {
    fs::remove(dir / ".cmr-manifest");  // root's, from the round before
    ASSERT_TRUE(as_nobody("printf \"" + body + "\" > " + (dir / ".cmr-manifest").string()));
    const Outcome r = run("report " + spline_file("m.json") + " --out " + dir.string());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(victim)) << "a planted manifest removed root's file: " << body;
    EXPECT_EQ(slurp(victim), "root's configuration\n");
    EXPECT_NE(r.err.find(".cmr-manifest (owned by uid"), std::string::npos) << r.err;
    EXPECT_EQ(notes(r.err), 1) << r.err;
    fs::remove(dir / "report.json");
    fs::remove(dir / "index.html");
  }
}

// E1, the same user: a backup no journal names (planted, or left by a cmr
// older than the journal) is never renamed over its NAME either.
TEST(RecoveryCli, SameUsersUnjournaledBackupIsNeverRolledBack) {
  const fs::path dir = fresh("same_user_bak");
  const fs::path victim = dir / "settings.ini";
  std::ofstream(victim) << "mine\n";
  const std::string planted = ".cmr-bak." + std::to_string(dead_pid()) + ".0.settings.ini";
  std::ofstream(dir / planted) << "planted\n";
  const Outcome r = run("knots " + spline_file("v.json") + " clamp --out " + (dir / "out.json").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(victim), "mine\n");
  EXPECT_NE(r.err.find(planted + " (no journal of an interrupted commit names it)"), std::string::npos) << r.err;
}

/// Which run's spline a report file names: "old", "new", "both" or "none".
std::string run_of(const fs::path& file) {
  const std::string text = slurp(file);
  const bool o = text.find("old_spline") != std::string::npos, n = text.find("new_spline") != std::string::npos;
  return o && n ? "both" : o ? "old" : n ? "new" : "none";
}

/// Names of cmr's hidden work files left in `dir` (temporaries, backups, journals).
std::vector<std::string> hidden_left(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(".cmr-", 0) == 0 && n != ".cmr-manifest") out.push_back(n);
  }
  return out;
}

/// Whether a journal of a commit past its commit point is in `dir`.
bool journal_committed(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(".cmr-journal.", 0) == 0 && slurp(e.path()).find("\ncommit\n") != std::string::npos)
      return true;
  return false;
}

bool strace_works() {
  return std::system("strace -f -qq -o /dev/null -e trace=getpid true >/dev/null 2>&1") == 0;
}

// E2: `cmr report new --out R` over an old report, killed at the Nth call
// of each syscall that changes or flushes the folder (every N until a run
// is not killed). After the kill, report.json and index.html are one run's,
// unless the killed commit had passed its commit point (its journal says
// "commit"): then the next commit into the folder finishes it. After an
// unrelated commit (`cmr knots ... --out R/other.json`) they are always one
// run's, the new one exactly when the commit point was passed, and no
// temporary, backup or journal is left.
TEST(CommitKill, ReportKilledAtEveryRenameLinkUnlinkAndSyncLeavesOneRun) {
  if (!strace_works()) GTEST_SKIP() << "strace cannot trace here";
  const std::string old_spline = spline_file("old_spline.json"), new_spline = spline_file("new_spline.json");
  int kills = 0, pending = 0;
  for (const std::string sys : {"rename", "renameat", "renameat2", "link", "linkat", "unlink", "unlinkat", "fsync",
                                "fdatasync", "syncfs"}) {
    for (int n = 1; n < 200; ++n) {
      SCOPED_TRACE(sys + " #" + std::to_string(n));
      const fs::path dir = fresh("kill");
      const fs::path rep = dir / "R";
      ASSERT_EQ(run("report " + old_spline + " --out " + rep.string()).code, 0);
      ASSERT_EQ(run_of(rep / "report.json"), "old");
      const Outcome k = run_captured(traced_env() + "strace -f -qq -o /dev/null -e trace=" + sys + " -e inject=" + sys +
                                     ":signal=KILL:when=" + std::to_string(n) + " " + CMR_BINARY + " report " +
                                     new_spline + " --out " + rep.string());
      if (k.code == 0) break;  // fewer than n calls: every kill point of this syscall was tried
      ASSERT_EQ(k.code, 128 + SIGKILL) << k.err;
      ++kills;
      const std::string j = run_of(rep / "report.json"), h = run_of(rep / "index.html");
      const bool committed = journal_committed(rep);
      pending += committed;
      if (!committed) {
        EXPECT_EQ(j, h) << "mixed right after the kill, and no journal to finish it";
      }
      const Outcome u = run("knots " + old_spline + " clamp --out " + (rep / "other.json").string());
      ASSERT_EQ(u.code, 0) << u.err;
      EXPECT_EQ(u.err, "");
      const std::string j2 = run_of(rep / "report.json"), h2 = run_of(rep / "index.html");
      EXPECT_EQ(j2, h2) << "mixed after the next commit (right after the kill: " << j << "/" << h << ")";
      EXPECT_EQ(j2, committed ? "new" : j) << "recovery went the wrong way";
      EXPECT_EQ(hidden_left(rep), std::vector<std::string>{});
    }
  }
  EXPECT_GT(kills, 5) << "the injection never hit the commit";
  EXPECT_GT(pending, 0) << "no kill fell between the commit point and the last rename";
  std::cout << "[ stats    ] " << kills << " kills, " << pending << " after the commit point\n";
}


/// Which of two reference sets the files `names` in `dir` equal byte for
/// byte: "old", "new", "mixed" (some of each), or "other".
std::string set_of(const fs::path& dir, const fs::path& old_ref, const fs::path& new_ref,
                   const std::vector<std::string>& names) {
  int o = 0, n = 0;
  for (const std::string& name : names) {
    const std::string text = slurp(dir / name);
    if (text == slurp(old_ref / name)) ++o;
    else if (text == slurp(new_ref / name)) ++n;
    else return "other (" + name + ")";
  }
  const int all = static_cast<int>(names.size());
  return o == all ? "old" : n == all ? "new" : "mixed";
}

// E2 for `region` with several outputs in one folder (picture, label map,
// depth map): killed at every rename, link, unlink and sync of its commit,
// then an unrelated commit: the three files are byte for byte one run's.
TEST(CommitKill, RegionWithSeveralOutputsKilledAtEveryStepLeavesOneRun) {
  if (!strace_works()) GTEST_SKIP() << "strace cannot trace here";
  const std::string old_spline = fs::path(CMR_SOURCE_DIR).string() + "/examples/uniform.json";
  const std::string new_spline = fs::path(CMR_SOURCE_DIR).string() + "/examples/clamped.json";
  const std::vector<std::string> names{"r.png", "r.pgm", "d.pgm"};
  const auto args = [](const std::string& spline, const fs::path& d) {
    return " region " + spline + " --point 2 --size 48x48 --depth 6 --view=-8,-11,4,1 --png " + (d / "r.png").string() +
           " --labels " + (d / "r.pgm").string() + " --depth-map " + (d / "d.pgm").string();
  };
  const fs::path old_ref = fresh("region_old"), new_ref = fresh("region_new");
  ASSERT_EQ(run(args(old_spline, old_ref)).code, 0);
  ASSERT_EQ(run(args(new_spline, new_ref)).code, 0);
  ASSERT_NE(slurp(old_ref / "r.pgm"), slurp(new_ref / "r.pgm")) << "the two runs must differ";
  int kills = 0;
  for (const std::string sys : {"rename", "renameat", "renameat2", "link", "linkat", "unlink", "unlinkat", "fsync",
                                "fdatasync", "syncfs"}) {
    for (int n = 1; n < 200; ++n) {
      SCOPED_TRACE(sys + " #" + std::to_string(n));
      const fs::path dir = fresh("region_kill");
      ASSERT_EQ(run(args(old_spline, dir)).code, 0);
      const Outcome k = run_captured(traced_env() + "strace -f -qq -o /dev/null -e trace=" + sys + " -e inject=" + sys +
                                     ":signal=KILL:when=" + std::to_string(n) + " " + CMR_BINARY + args(new_spline, dir));
      if (k.code == 0) break;
      ASSERT_EQ(k.code, 128 + SIGKILL) << k.err;
      ++kills;
      const std::string after_kill = set_of(dir, old_ref, new_ref, names);
      const bool committed = journal_committed(dir);
      if (!committed) {
        EXPECT_NE(after_kill, "mixed") << "no journal to finish it";
      }
      const Outcome u = run("knots " + old_spline + " clamp --out " + (dir / "other.json").string());
      ASSERT_EQ(u.code, 0) << u.err;
      EXPECT_EQ(u.err, "");
      EXPECT_EQ(set_of(dir, old_ref, new_ref, names), committed ? "new" : after_kill) << "right after the kill: " << after_kill;
      EXPECT_EQ(hidden_left(dir), std::vector<std::string>{});
    }
  }
  EXPECT_GT(kills, 5) << "the injection never hit the commit";
}


/// The visible files of `dir` (not hidden; `other.json` of the unrelated
/// commit aside) with their bytes.
std::map<std::string, std::string> visible_files(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n[0] != '.' && n != "other.json") out[n] = slurp(e.path());
  }
  return out;
}

// E2 for `import` into an owned folder: an SVG of three paths imported over
// by one of two paths (same stem), killed at every step of the second
// import's commit. After the next commit into the folder it holds exactly
// the first import's three files or the second's two (the third removed by
// the manifest, also when a kill fell between the renames and that removal).
TEST(CommitKill, ImportIntoAnOwnedFolderKilledAtEveryStepLeavesOneImport) {
  if (!strace_works()) GTEST_SKIP() << "strace cannot trace here";
  const fs::path src = fresh("import_src");
  fs::create_directories(src / "old");
  fs::create_directories(src / "new");
  std::ofstream(src / "old" / "drawing.svg")
      << "<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0 C1 2 3 2 4 0\"/><path d=\"M0 0 C1 3 3 3 4 0\"/>"
         "<path d=\"M0 0 C1 4 3 4 4 0\"/></svg>";
  std::ofstream(src / "new" / "drawing.svg")
      << "<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0 C2 2 3 2 5 0\"/><path d=\"M0 0 C2 3 3 3 5 0\"/></svg>";
  const fs::path old_ref = fresh("import_old"), new_ref = fresh("import_new");
  ASSERT_EQ(run("import " + (src / "old" / "drawing.svg").string() + " --out " + old_ref.string()).code, 0);
  ASSERT_EQ(run("import " + (src / "new" / "drawing.svg").string() + " --out " + new_ref.string()).code, 0);
  const auto old_set = visible_files(old_ref), new_set = visible_files(new_ref);
  ASSERT_EQ(old_set.size(), 3u);
  ASSERT_EQ(new_set.size(), 2u);
  int kills = 0;
  for (const std::string sys : {"rename", "renameat", "renameat2", "link", "linkat", "unlink", "unlinkat", "fsync",
                                "fdatasync", "syncfs"}) {
    for (int n = 1; n < 200; ++n) {
      SCOPED_TRACE(sys + " #" + std::to_string(n));
      const fs::path dir = fresh("import_kill");
      ASSERT_EQ(run("import " + (src / "old" / "drawing.svg").string() + " --out " + dir.string()).code, 0);
      const Outcome k = run_captured(traced_env() + "strace -f -qq -o /dev/null -e trace=" + sys + " -e inject=" + sys +
                                     ":signal=KILL:when=" + std::to_string(n) + " " + CMR_BINARY + " import " +
                                     (src / "new" / "drawing.svg").string() + " --out " + dir.string());
      if (k.code == 0) break;
      ASSERT_EQ(k.code, 128 + SIGKILL) << k.err;
      ++kills;
      const bool committed = journal_committed(dir);
      const auto after_kill = visible_files(dir);
      if (!committed) {
        EXPECT_TRUE(after_kill == old_set || after_kill == new_set) << "no journal to finish it";
      }
      const Outcome u = run("knots " + std::string(CMR_SOURCE_DIR) + "/examples/uniform.json clamp --out " +
                            (dir / "other.json").string());
      ASSERT_EQ(u.code, 0) << u.err;
      const auto after = visible_files(dir);
      if (committed) {
        EXPECT_TRUE(after == new_set) << after.size() << " files after the next commit";
      } else {
        EXPECT_TRUE(after == after_kill) << after.size() << " files after the next commit";
      }
      EXPECT_EQ(hidden_left(dir), std::vector<std::string>{});
    }
  }
  EXPECT_GT(kills, 5) << "the injection never hit the commit";
}


// E2 for `fix --out F.json --png F.png`: killed at every rename, link,
// unlink and sync of its commit, then an unrelated commit: the fixed spline
// and its picture are byte for byte one run's.
TEST(CommitKill, FixWithOutAndPngKilledAtEveryStepLeavesOneRun) {
  if (!strace_works()) GTEST_SKIP() << "strace cannot trace here";
  const std::string old_spline = fs::path(CMR_SOURCE_DIR).string() + "/examples/uniform.json";
  const std::string new_spline = fs::path(CMR_SOURCE_DIR).string() + "/examples/clamped.json";
  const std::vector<std::string> names{"f.json", "f.png"};
  const auto args = [](const std::string& spline, const fs::path& d) {
    return " fix " + spline + " --out " + (d / "f.json").string() + " --png " + (d / "f.png").string() + " >/dev/null";
  };
  const fs::path old_ref = fresh("fix_old"), new_ref = fresh("fix_new");
  ASSERT_EQ(run(args(old_spline, old_ref)).code, 0);
  ASSERT_EQ(run(args(new_spline, new_ref)).code, 0);
  ASSERT_NE(slurp(old_ref / "f.json"), slurp(new_ref / "f.json")) << "the two runs must differ";
  int kills = 0;
  for (const std::string sys : {"rename", "renameat", "renameat2", "link", "linkat", "unlink", "unlinkat", "fsync",
                                "fdatasync", "syncfs"}) {
    for (int n = 1; n < 200; ++n) {
      SCOPED_TRACE(sys + " #" + std::to_string(n));
      const fs::path dir = fresh("fix_kill");
      ASSERT_EQ(run(args(old_spline, dir)).code, 0);
      const Outcome k = run_captured(traced_env() + "strace -f -qq -o /dev/null -e trace=" + sys + " -e inject=" + sys +
                                     ":signal=KILL:when=" + std::to_string(n) + " " + CMR_BINARY + args(new_spline, dir));
      if (k.code == 0) break;
      ASSERT_EQ(k.code, 128 + SIGKILL) << k.err;
      ++kills;
      const std::string after_kill = set_of(dir, old_ref, new_ref, names);
      const bool committed = journal_committed(dir);
      if (!committed) {
        EXPECT_NE(after_kill, "mixed") << "no journal to finish it";
      }
      const Outcome u = run("knots " + old_spline + " clamp --out " + (dir / "other.json").string());
      ASSERT_EQ(u.code, 0) << u.err;
      EXPECT_EQ(u.err, "");
      EXPECT_EQ(set_of(dir, old_ref, new_ref, names), committed ? "new" : after_kill) << "right after the kill: " << after_kill;
      EXPECT_EQ(hidden_left(dir), std::vector<std::string>{});
    }
  }
  EXPECT_GT(kills, 3) << "the injection never hit the commit";
}

}  // namespace
}  // namespace cmr::test
