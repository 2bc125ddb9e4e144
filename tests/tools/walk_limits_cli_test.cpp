// Issue 42 E6 and the smaller items, through the cmr binary: a report reruns
// into an output folder inside its input folder; a folder walk lists what it
// skips, and why; a bad file in a folder is one invalid entry, not the end
// of the run; --max-move 0 and an oversized --baseline are refused in one
// line; out of memory while parsing is exit 3, never an abort; an OBJ import
// owns its output folder.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr::test {
namespace {

fs::path fresh(const std::string& name) {
  const fs::path d = scratch() / ("walk_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string uniform() { return slurp(fs::path(CMR_SOURCE_DIR) / "examples/uniform.json"); }

void put(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

/// The "skipped" list of a report.json: path -> reason.
std::map<std::string, std::string> skipped_of(const fs::path& report) {
  std::map<std::string, std::string> out;
  const nlohmann::json doc = nlohmann::json::parse(slurp(report));
  for (const auto& k : doc.at("skipped")) out[k.at("path").get<std::string>()] = k.at("reason").get<std::string>();
  return out;
}

// E6: `cmr report proj --out proj/qa`, twice. The second run does not read
// its own report.json (the folder is the run's own output), a copied
// report.json elsewhere in the tree is a cmr output, and a JSON that is no
// spline file is skipped with a note; none of them fails the run.
TEST(ReportRerun, OutputFolderInsideTheInputFolderRerunsCleanly) {
  const fs::path proj = fresh("proj");
  put(proj / "curve.json", uniform());
  put(proj / "package.json", "{\"name\": \"not a spline\", \"version\": \"1.0\"}");
  const std::string cmd = "report " + proj.string() + " --out " + (proj / "qa").string();
  const Outcome first = run(cmd);
  ASSERT_EQ(first.code, 0) << first.err;
  fs::create_directories(proj / "old");
  fs::copy_file(proj / "qa" / "report.json", proj / "old" / "report.json");
  const Outcome second = run(cmd);
  ASSERT_EQ(second.code, 0) << second.err;
  const nlohmann::json doc = nlohmann::json::parse(slurp(proj / "qa" / "report.json"));
  EXPECT_EQ(doc.at("splines").size(), 1u) << doc.dump();
  EXPECT_EQ(doc.at("summary").at("invalid"), 0);
  const auto skipped = skipped_of(proj / "qa" / "report.json");
  EXPECT_EQ(skipped.size(), 3u) << doc.at("skipped").dump();
  EXPECT_EQ(skipped.at((proj / "qa").string()), "the run's own output folder (--out)");
  EXPECT_EQ(skipped.at((proj / "old" / "report.json").string()), "a cmr output (report.json of an earlier run)");
  EXPECT_EQ(skipped.at((proj / "package.json").string()), "not a spline file (no \"points\")");
  EXPECT_NE(second.err.find("cmr: note: skipped " + (proj / "package.json").string() + ": not a spline file"),
            std::string::npos)
      << second.err;
  EXPECT_NE(slurp(proj / "qa" / "index.html").find("3 skipped"), std::string::npos);
}

// A folder walk lists the FIFOs, dangling and looping links and links to
// folders it does not take, with the reason, and reports the rest (a FIFO is
// never opened: the run does not block).
TEST(FolderWalk, ListsWhatItSkipsWithTheReason) {
  const fs::path d = fresh("special");
  put(d / "curve.json", uniform());
  ASSERT_EQ(::mkfifo((d / "pipe.json").c_str(), 0644), 0);
  fs::create_symlink(d / "gone.json", d / "dangling.json");
  fs::create_symlink(d / "loop_b.json", d / "loop_a.json");
  fs::create_symlink(d / "loop_a.json", d / "loop_b.json");
  fs::create_directories(d / "elsewhere");
  fs::create_symlink(d / "elsewhere", d / "linked_folder");
  const Outcome r = run("report " + d.string() + " --out " + (scratch() / "walk_special_out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto skipped = skipped_of(scratch() / "walk_special_out" / "report.json");
  EXPECT_EQ(skipped.at((d / "pipe.json").string()), "a FIFO (not read: it could block)");
  EXPECT_EQ(skipped.at((d / "dangling.json").string()), "a symbolic link to nothing");
  EXPECT_EQ(skipped.at((d / "loop_a.json").string()), "a symbolic link loop");
  EXPECT_EQ(skipped.at((d / "linked_folder").string()), "a symbolic link to a folder (not followed)");
  std::size_t notes = 0;
  for (std::size_t at = 0; (at = r.err.find("cmr: note: skipped ", at)) != std::string::npos; ++at) ++notes;
  EXPECT_EQ(notes, skipped.size()) << "one line per skipped entry: " << r.err;
}

// An unreadable subfolder is listed, not silently left out (as a user for
// whom it is unreadable: root reads every folder).
TEST(FolderWalk, ListsAnUnreadableSubfolder) {
  if (::geteuid() == 0 && std::system("command -v setpriv >/dev/null") != 0) GTEST_SKIP() << "root without setpriv";
  const fs::path d = fresh("unreadable");
  ::chmod(scratch().c_str(), 0755);
  ::chmod(d.c_str(), 0777);
  put(d / "curve.json", uniform());
  fs::create_directories(d / "locked");
  put(d / "locked" / "hidden_curve.json", uniform());
  ::chmod((d / "locked").c_str(), 0);
  const std::string as = ::geteuid() == 0 ? "setpriv --reuid=nobody --regid=nogroup --clear-groups " : "";
  const fs::path out = d / "qa";
  const Outcome r = run_captured(as + CMR_BINARY + " report " + d.string() + " --out " + out.string());
  ::chmod((d / "locked").c_str(), 0755);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto skipped = skipped_of(out / "report.json");
  EXPECT_EQ(skipped.at((d / "locked").string()), "an unreadable folder: Permission denied");
  EXPECT_NE(r.err.find("cmr: note: skipped " + (d / "locked").string()), std::string::npos) << r.err;
}

// One file mixing [x, y] and [x, y, z] points in a folder is one invalid
// entry of the report; the other files are reported.
TEST(FolderWalk, MixedDimensionFileIsListedAsInvalid) {
  const fs::path d = fresh("mixed");
  put(d / "a_curve.json", uniform());
  put(d / "b_mixed.json",
      "{\"degree\": 3, \"knots\": [0, 1, 2, 3, 4, 5, 6, 7], \"points\": [[0, 0], [1, 1, 1], [2, 0], [3, 1], [4, 0], [5, 1]]}");
  put(d / "c_mixed.json",  // the first point with three coordinates
      "{\"degree\": 3, \"knots\": [0, 1, 2, 3, 4, 5, 6, 7], \"points\": [[0, 0, 0], [1, 1], [2, 0, 1], [3, 1, 1], [4, 0, 1], [5, 1, 1]]}");
  // As a folder, and as files named one by one (a glob the shell expanded).
  for (const std::string& inputs : {d.string(), (d / "a_curve.json").string() + " " + (d / "b_mixed.json").string() +
                                                     " " + (d / "c_mixed.json").string()}) {
    SCOPED_TRACE(inputs);
    const fs::path out = scratch() / "walk_mixed_out";
    fs::remove_all(out);
    const Outcome r = run("report " + inputs + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << "an invalid item: exit 2 (docs/report.md); " << r.err;
    ASSERT_TRUE(fs::exists(out / "report.json")) << r.err;
    const nlohmann::json doc = nlohmann::json::parse(slurp(out / "report.json"));
    ASSERT_EQ(doc.at("splines").size(), 3u) << doc.dump();
    EXPECT_EQ(doc.at("summary").at("invalid"), 2);
    EXPECT_EQ(doc.at("summary").at("pass").get<int>() + doc.at("summary").at("fail").get<int>(), 1);
    EXPECT_NE(r.err.find("c_mixed.json: points["), std::string::npos) << r.err;
  }
}

// --max-move 0 would let no point move; it is refused, not read as "unlimited".
TEST(FixMaxMove, ZeroIsRefusedInOneLine) {
  const std::string f = write("mm.json", uniform());
  for (const std::string v : {"0", "-1", "0.0"}) {
    const Outcome r = run("fix " + f + " --max-move " + v);
    EXPECT_EQ(r.code, 2) << v << ": " << r.err;
    EXPECT_NE(r.err.find("--max-move: " + v + " is not a distance > 0"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

// --baseline is an input file like any other: at most 64 MiB, refused
// before it is read.
TEST(ReportBaseline, LargerThanTheInputLimitIsRefusedBeforeReading) {
  const fs::path big = scratch() / "walk_big_baseline.json";
  ASSERT_EQ(std::system(("truncate -s 65M " + big.string()).c_str()), 0);
  const Outcome r = run("report " + write("bl.json", uniform()) + " --out " + (scratch() / "walk_bl_out").string() +
                        " --baseline " + big.string());
  fs::remove(big);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("larger than the limit of 64 MiB"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(scratch() / "walk_bl_out" / "report.json"));
}

// Out of memory while a large spline file is parsed is exit 3 "out of
// memory", never SIGABRT: nlohmann's destructor of a partly parsed document
// allocated (issue 42: 10^6 knots under ulimit -v 150 MB; before the fix,
// 120 to 200 MB aborted here). Limits from 100 to 400 MB are tried.
TEST(OutOfMemory, ParsingALargeSplineUnderUlimitIsExit3NotAnAbort) {
  if (kSanitizerBuild) GTEST_SKIP() << "a sanitizer build cannot start under ulimit -v (ASan's shadow memory)";
  const fs::path f = scratch() / "walk_million.json";
  {
    std::ofstream out(f);
    const int n = 1000000;
    out << "{\"degree\": 1, \"knots\": [";
    for (int i = 0; i < n; ++i) out << (i ? "," : "") << i;
    out << "], \"points\": [";
    for (int i = 0; i < n; ++i) out << (i ? "," : "") << "[" << i << "," << (i % 7) << "]";
    out << "]}";
  }
  // Degree 1 is refused after the whole document is parsed (exit 2, its
  // line): the run then stops at once, and the parse is what is measured.
  // Below 100 MB the binary does not load its libraries at all.
  int oom = 0;
  for (int mb = 100; mb <= 400; mb += 20) {
    const Outcome r = run_captured("bash -c 'ulimit -v " + std::to_string(mb * 1024) + "; exec " + CMR_BINARY +
                                   " analyze " + f.string() + " >/dev/null'");
    SCOPED_TRACE(std::to_string(mb) + " MB: exit " + std::to_string(r.code) + ", " + r.err);
    EXPECT_TRUE(r.code == 3 || (r.code == 2 && r.err.find("degree: must be between 2 and 30 (got 1)") != std::string::npos))
        << "killed by a signal (134: SIGABRT) or another exit";
    if (r.code == 3) {
      ++oom;
      EXPECT_EQ(r.err, "cmr: out of memory\n");
    }
  }
  EXPECT_GT(oom, 0) << "no limit ran out of memory: the test proves nothing";
  fs::remove(f);
}

// An OBJ import owns its output folder, as the other importers: a second
// import into it removes the files of the first that it does not write.
TEST(ImportObj, OwnsItsOutputFolder) {
  const fs::path d = fresh("obj");
  const fs::path a = d / "first.obj", b = d / "second.obj";
  fs::copy_file(fs::path(CMR_SOURCE_DIR) / "examples/space/curves.obj", a);
  fs::copy_file(fs::path(CMR_SOURCE_DIR) / "examples/space/curves.obj", b);
  const fs::path out = d / "out";
  ASSERT_EQ(run("import " + a.string() + " --out " + out.string()).code, 0);
  put(out / "mine.txt", "a user's file");
  const Outcome r = run("import " + b.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    EXPECT_TRUE(n.rfind("second_", 0) == 0 || n == "mine.txt" || n == ".cmr-manifest") << n << " was left";
  }
  EXPECT_TRUE(fs::exists(out / "mine.txt"));
}

}  // namespace
}  // namespace cmr::test
