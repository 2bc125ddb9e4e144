// CI for type repositories (issue 36, item 9): findings name their files
// relative to the folder given or --source-root, so that a baseline does not
// depend on how a path was spelled; SARIF artifact URIs are relative to the
// working folder or --source-root (uriBaseId SRCROOT); the Markdown summary
// for a pull request's comment (report/markdown.hpp) stays under its limit.
// And the gate's new name with its alias (item 8) in a baseline.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <set>

#include <nlohmann/json.hpp>

#include "io/font.hpp"
#include "io/output.hpp"
#include "report/corpus.hpp"
#include "report/gates.hpp"
#include "report/markdown.hpp"
#include "report/sarif.hpp"
#include "tests/cli_util.hpp"
#include "tests/test_util.hpp"

namespace cmr::report {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

BSpline monotone() { return test::class_a_bezier(3, -0.5, 1.5); }
BSpline wavy() { return BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, {{0, 0}, {1, 1.5}, {2, -1}, {3, 1.2}, {4, 0}}); }

/// A checkout: `root/in` holds two spline files and a font.
fs::path checkout(const std::string& name) {
  const fs::path root = fs::weakly_canonical(test::scratch() / name);
  fs::remove_all(root);
  fs::create_directories(root / "in" / "fonts");
  write_spline_file(root / "in" / "monotone.json", monotone());
  write_spline_file(root / "in" / "wavy.json", wavy());
  fs::copy_file(kDejaVu, root / "in" / "fonts" / "DejaVuSans.ttf");
  return root;
}

/// cmr run in folder `cwd`.
test::Outcome run_in(const fs::path& cwd, const std::string& args) {
  return test::run_captured("cd '" + cwd.string() + "' && " + std::string(CMR_BINARY) + " " + args);
}

Json read_json(const fs::path& p) { return Json::parse(test::slurp(p)); }

std::vector<std::string> keys_of(const Json& doc) {
  std::vector<std::string> keys;
  for (const Json& s : doc["splines"])
    for (const Json& f : s.value("findings", Json::array())) keys.push_back(f["key"]);
  std::sort(keys.begin(), keys.end());
  return keys;
}

const std::string kGates = " --glyphs O,o,H --require curvature-extrema-at-nodes,g2-at-smooth-nodes --no-thumbnails";

// The Done-when: a baseline made from an absolute path passes,
// unchanged, when run with the relative path (from the checkout's root),
// and with other spellings of the same folder.
TEST(CiBaseline, ABaselineFromAnAbsolutePathPassesUnchangedWithTheRelativePath) {
  const fs::path root = checkout("spell");
  const test::Outcome accepted = run_in(root, "report " + (root / "in").string() + kGates + " --out acc");
  ASSERT_EQ(accepted.code, 1) << accepted.err;  // the font's O and the wavy spline fail
  const Json acc = read_json(root / "acc" / "report.json");
  const int findings = acc["summary"]["findings"];
  ASSERT_GT(findings, 0);
  // Keys name the file below the folder given, whatever its spelling.
  for (const std::string& k : keys_of(acc))
    EXPECT_TRUE(k.rfind("wavy.json|", 0) == 0 || k.rfind("fonts/DejaVuSans.ttf|", 0) == 0) << k;
  const std::string baseline = test::slurp(root / "acc" / "report.json");
  for (const char* spelling : {"in", "./in/", "in//", "../spell/in"}) {
    // --no-cache: each spelling is its own run (the resume cache keys the
    // path as given, which the page's fix commands print), and its note
    // would be the only line on stderr.
    const test::Outcome r =
        run_in(root, std::string("report ") + spelling + kGates + " --out run --no-cache --baseline acc/report.json");
    EXPECT_EQ(r.code, 0) << spelling << ": " << r.err << r.out;
    EXPECT_EQ(r.err, "") << spelling;
    EXPECT_NE(r.out.find("(baseline: 0 new, 0 fixed, " + std::to_string(findings) + " unchanged)"), std::string::npos)
        << spelling << ": " << r.out;
    EXPECT_EQ(keys_of(read_json(root / "run" / "report.json")), keys_of(acc)) << spelling;
  }
  EXPECT_EQ(test::slurp(root / "acc" / "report.json"), baseline);  // the baseline is used unchanged
  // From another folder: the folder given is still the base.
  const test::Outcome elsewhere = run_in(root / "in" / "fonts", "report ../../in" + kGates + " --out " +
                                                                    (root / "run2").string() + " --baseline " +
                                                                    (root / "acc" / "report.json").string());
  EXPECT_EQ(elsewhere.code, 0) << elsewhere.err << elsewhere.out;
}

// Files named one by one are relative to the working folder, or to
// --source-root, which gives them the folder run's names.
TEST(CiBaseline, FilesAreNamedRelativeToTheWorkingFolderOrTheSourceRoot) {
  const fs::path root = checkout("files");
  const std::string abs = (root / "in" / "wavy.json").string();
  ASSERT_EQ(run_in(root, "report " + abs + kGates + " --out acc").code, 1);
  for (const std::string& k : keys_of(read_json(root / "acc" / "report.json"))) EXPECT_EQ(k.rfind("in/wavy.json|", 0), 0u) << k;
  const test::Outcome rel = run_in(root, "report in/wavy.json" + kGates + " --out run --baseline acc/report.json");
  EXPECT_EQ(rel.code, 0) << rel.err << rel.out;
  EXPECT_NE(rel.out.find("(baseline: 0 new, 0 fixed, "), std::string::npos) << rel.out;
  // --source-root in: the file as the folder run names it, from any working folder.
  ASSERT_EQ(run_in(root, "report in" + kGates + " --out folder").code, 1);
  const test::Outcome rooted = run_in("/", "report " + abs + kGates + " --source-root " + (root / "in").string() +
                                               " --out " + (root / "rooted").string() + " --baseline " +
                                               (root / "folder" / "report.json").string());
  // Only the font's findings are missing from this run: counted as fixed, none new.
  EXPECT_EQ(rooted.code, 0) << rooted.err << rooted.out;
  EXPECT_NE(rooted.out.find("(baseline: 0 new, "), std::string::npos) << rooted.out;
  for (const std::string& k : keys_of(read_json(root / "rooted" / "report.json"))) EXPECT_EQ(k.rfind("wavy.json|", 0), 0u) << k;
  // A folder that is not there is refused at once.
  const test::Outcome bad = run_in(root, "report in --source-root nowhere --out x");
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("nowhere"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(root / "x"));
}

// A file given by itself is named relative to the working folder, so a
// baseline made with its absolute path from another folder names it
// "../../in/wavy.json"; run as "wavy.json" in its own folder, the finding is
// matched to the one baseline file whose path ends the same way, and the
// baseline passes unchanged. Both ways round, and a font with its glyphs.
// Where two baseline files end that way, neither is taken (new findings).
TEST(CiBaseline, AFileGivenByItselfMatchesItsBaselineFromAnyWorkingFolder) {
  const fs::path root = checkout("lone");
  fs::create_directories(root / "elsewhere" / "deeper");
  const std::string wavy = (root / "in" / "wavy.json").string(), font = (root / "in" / "fonts" / "DejaVuSans.ttf").string();
  for (const std::string& file : {wavy, font}) {
    SCOPED_TRACE(file);
    const fs::path from = root / "elsewhere" / "deeper";
    const test::Outcome acc = run_in(from, "report " + file + kGates + " --out acc");
    ASSERT_EQ(acc.code, 1) << acc.err;
    const std::vector<std::string> keys = keys_of(read_json(from / "acc" / "report.json"));
    ASSERT_FALSE(keys.empty());
    EXPECT_EQ(keys.front().rfind("../../in/", 0), 0u) << keys.front();
    const fs::path own = fs::path(file).parent_path();
    const std::string name = fs::path(file).filename().string();
    const test::Outcome rel = run_in(own, "report " + name + kGates + " --no-cache --out " + (root / "rel").string() +
                                              " --baseline " + (from / "acc" / "report.json").string());
    EXPECT_EQ(rel.code, 0) << rel.err << rel.out;
    EXPECT_NE(rel.out.find("(baseline: 0 new, 0 fixed, " + std::to_string(keys.size()) + " unchanged)"), std::string::npos)
        << rel.out;
    // The other way round: the baseline made in the file's folder, the run from elsewhere by its absolute path.
    const test::Outcome back = run_in(from, "report " + file + kGates + " --no-cache --out back --baseline " +
                                                (root / "rel" / "report.json").string());
    EXPECT_EQ(back.code, 0) << back.err << back.out;
  }
  // Two files that end alike in the baseline: a run of one by its name alone matches neither.
  fs::create_directories(root / "a");
  fs::create_directories(root / "b");
  fs::copy_file(wavy, root / "a" / "wavy.json");
  fs::copy_file(wavy, root / "b" / "wavy.json");
  ASSERT_EQ(run_in(root, "report a/wavy.json b/wavy.json" + kGates + " --out two").code, 1);
  const test::Outcome one = run_in(root / "a", "report wavy.json" + kGates + " --no-cache --out " + (root / "one").string() +
                                                   " --baseline " + (root / "two" / "report.json").string());
  EXPECT_EQ(one.code, 1) << one.err << one.out;
  EXPECT_EQ(one.out.find("(baseline: 0 new"), std::string::npos) << one.out;
}

// A baseline accepted before the rename names the gate extrema-at-nodes in
// its keys: it still passes unchanged, and the run writes the new name.
TEST(CiBaseline, ABaselineUnderTheOldGateNamePassesUnchanged) {
  const fs::path root = checkout("alias");
  ASSERT_EQ(run_in(root, "report in" + kGates + " --out acc").code, 1);
  std::string old = test::slurp(root / "acc" / "report.json");
  const std::string now = "curvature-extrema-at-nodes", before = "extrema-at-nodes";
  int renamed = 0;
  for (std::size_t at = old.find(now); at != std::string::npos; at = old.find(now, at)) {
    old.replace(at, now.size(), before);
    ++renamed;
  }
  ASSERT_GT(renamed, 0);
  std::ofstream(root / "old.json") << old;
  const test::Outcome r = run_in(root, "report in --glyphs O,o,H --require extrema-at-nodes,g2-at-smooth-nodes "
                                       "--no-thumbnails --out run --baseline old.json --sarif run.sarif");
  EXPECT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("(baseline: 0 new, 0 fixed, "), std::string::npos) << r.out;
  const Json doc = read_json(root / "run" / "report.json");
  EXPECT_EQ(doc["settings"]["type_gates"][0], now);
  const Json sarif = read_json(root / "run.sarif");
  EXPECT_EQ(sarif["runs"][0]["tool"]["driver"]["rules"][0]["id"], now);
  EXPECT_EQ(test::slurp(root / "run.sarif").find("\"extrema-at-nodes"), std::string::npos);
}

// SARIF: artifact URIs relative to the working folder (or --source-root),
// resolved by uriBaseId SRCROOT through run.originalUriBaseIds; a file
// outside the root keeps an absolute file: URI.
TEST(CiSarif, ArtifactUrisAreRelativeToTheWorkingFolderOrTheSourceRoot) {
  const fs::path root = checkout("sarif");
  const fs::path outside = fs::weakly_canonical(test::scratch()) / "outside wavy.json";
  write_spline_file(outside, wavy());
  ASSERT_EQ(run_in(root, "report in '" + outside.string() + "'" + kGates + " --out o --sarif o.sarif").code, 1);
  const Json doc = read_json(root / "o.sarif");
  const Json& run = doc["runs"][0];
  EXPECT_EQ(run["originalUriBaseIds"]["SRCROOT"]["uri"], "file://" + root.string() + "/");
  std::set<std::string> relative, absolute;
  for (const Json& r : run["results"]) {
    const Json& a = r["locations"][0]["physicalLocation"]["artifactLocation"];
    if (a.contains("uriBaseId")) {
      EXPECT_EQ(a["uriBaseId"], "SRCROOT");
      relative.insert(a["uri"].get<std::string>());
    } else {
      absolute.insert(a["uri"].get<std::string>());
    }
  }
  EXPECT_EQ(relative, (std::set<std::string>{"in/fonts/DejaVuSans.ttf", "in/wavy.json"}));
  EXPECT_EQ(absolute, std::set<std::string>{path_uri(outside.string())});
  EXPECT_NE(path_uri(outside.string()).find("outside%20wavy.json"), std::string::npos);
  // --source-root in: relative to it.
  ASSERT_EQ(run_in(root, "report in" + kGates + " --out o2 --sarif o2.sarif --source-root in").code, 1);
  const Json doc2 = read_json(root / "o2.sarif");
  EXPECT_EQ(doc2["runs"][0]["originalUriBaseIds"]["SRCROOT"]["uri"], "file://" + (root / "in").string() + "/");
  std::set<std::string> uris;
  for (const Json& r : doc2["runs"][0]["results"])
    uris.insert(r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"].get<std::string>());
  EXPECT_EQ(uris, (std::set<std::string>{"fonts/DejaVuSans.ttf", "wavy.json"}));
}

TEST(SourceNames, EverySpellingOfAPathGivesOneName) {
  const fs::path root = checkout("names");
  const std::string cwd = fs::current_path().string();
  fs::current_path(root);
  EXPECT_EQ(source_name("in/wavy.json", "in"), "wavy.json");
  EXPECT_EQ(source_name((root / "in" / "wavy.json").string(), "in"), "wavy.json");
  EXPECT_EQ(source_name("./in//fonts/../wavy.json", (root / "in").string()), "wavy.json");
  EXPECT_EQ(source_name("in/wavy.json", ""), "in/wavy.json");
  EXPECT_EQ(source_name("in/wavy.json", "in/fonts"), "../wavy.json");
  bool relative = false;
  EXPECT_EQ(source_uri("in/fonts/DejaVuSans.ttf", "", &relative), "in/fonts/DejaVuSans.ttf");
  EXPECT_TRUE(relative);
  EXPECT_EQ(source_uri("in/wavy.json", "in/fonts", &relative), path_uri((root / "in" / "wavy.json").string()));
  EXPECT_FALSE(relative);
  EXPECT_EQ(source_uri_base(""), "file://" + root.string() + "/");
  fs::current_path(cwd);
}

// collect_files' bases: one per file, in order; a designspace's masters are
// named relative to the working folder, not claimed by a folder after them.
TEST(SourceNames, EveryFileHasItsBaseADesignspacesMastersTheWorkingFolder) {
  const fs::path root = checkout("bases");
  fs::copy(std::string(CMR_SOURCE_DIR) + "/examples/ufo/Sans.ufo", root / "Sans.ufo", fs::copy_options::recursive);
  std::ofstream(root / "Family.designspace")
      << "<?xml version=\"1.0\"?>\n<designspace format=\"4.1\">\n<axes>\n"
         "<axis tag=\"wght\" name=\"Weight\" minimum=\"400\" maximum=\"400\" default=\"400\"/>\n</axes>\n"
         "<sources>\n<source filename=\"Sans.ufo\"><location><dimension name=\"Weight\" xvalue=\"400\"/>"
         "</location></source>\n</sources>\n</designspace>\n";
  std::vector<std::string> bases;
  const std::vector<std::string> files =
      collect_files({(root / "Family.designspace").string(), (root / "in").string(), (root / "in" / "wavy.json").string()},
                    {}, &bases);
  ASSERT_EQ(bases.size(), files.size());
  ASSERT_GE(files.size(), 5u);  // the master, the folder's three files, the file
  EXPECT_EQ(bases.front(), "") << files.front();
  for (std::size_t i = 1; i + 1 < files.size(); ++i) EXPECT_EQ(bases[i], (root / "in").string()) << files[i];
  EXPECT_EQ(bases.back(), "");
}

// ------------------------------------------------------------ Markdown

FileRecord record(FileKind kind, std::vector<CaseRecord> cases) {
  FileRecord f;
  f.kind = kind;
  f.cases = std::move(cases);
  return f;
}

CaseRecord failing(const std::string& name, const std::string& gate, int findings) {
  CaseRecord c;
  c.name = name;
  c.pass = false;
  for (int i = 0; i < findings; ++i) {
    Finding f;
    f.file = "f";
    f.glyph = name;
    f.node = "p";
    f.node.append(std::to_string(i));
    f.gate = gate;
    f.message = name;
    f.message.append("/c0: finding ").append(std::to_string(i));
    c.findings.push_back(std::move(f));
  }
  return c;
}

CaseRecord passing(const std::string& name) {
  CaseRecord c;
  c.name = name;
  return c;
}

TEST(Markdown, TableCountsPerGateDetailsAndEscaping) {
  ReportOptions o;
  parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o);
  MarkdownSummary md(o);
  md.add(record(FileKind::font, {failing("O", "curvature-extrema-at-nodes", 5), failing("a|b*c<d>", "g2-at-smooth-nodes:0.05", 1),
                                 passing("l")}),
         "fonts/A.ttf", "Sans Book");
  md.add(record(FileKind::spline, {failing("wavy", "curvature-extrema-at-nodes", 1)}), "wavy.json", "");
  CaseRecord bad;
  bad.name = "broken";
  bad.pass = false;
  bad.error = "broken.json: not JSON";
  md.add(record(FileKind::spline, {bad, passing("ok")}), "broken.json", "");
  BatchSummary s;
  s.files = 3;
  s.fonts = 1;
  s.glyphs = 3;
  s.glyphs_fail = 2;
  s.items = 6;
  s.pass = 2;
  s.fail = 3;
  s.invalid = 1;
  s.findings = 7;
  s.exit_code = kExitInvalid;
  const std::string text = md.finish(s, "");
  EXPECT_EQ(text.rfind("## cmr report: 4 glyphs and splines fail", 0), 0u) << text;
  EXPECT_NE(text.find("| file | glyphs / splines | pass | fail | invalid | `curvature-extrema-at-nodes` | "
                      "`g2-at-smooth-nodes:0.05` |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("| `fonts/A.ttf` (Sans Book) | 3 | 1 | 2 | 0 | 1 | 1 |"), std::string::npos) << text;
  EXPECT_NE(text.find("| 2 spline and SVG files | 3 | 1 | 1 | 1 | 1 | 0 |"), std::string::npos) << text;
  EXPECT_NE(text.find("| **all** | 6 | 2 | 3 | 1 | 2 | 1 |"), std::string::npos) << text;
  EXPECT_NE(text.find("<details><summary><code>fonts/A.ttf</code>: 2 failing glyphs</summary>"), std::string::npos) << text;
  // Three findings listed, the others counted; names and messages escaped.
  EXPECT_NE(text.find("- **O** (5 findings): `curvature-extrema-at-nodes` O/c0: finding 0; "), std::string::npos) << text;
  EXPECT_NE(text.find("; and 2 more\n"), std::string::npos) << text;
  EXPECT_NE(text.find("- **a\\|b\\*c&lt;d&gt;** (1 finding)"), std::string::npos) << text;
  EXPECT_NE(text.find("- **broken**: invalid: broken.json: not JSON"), std::string::npos) << text;
  EXPECT_EQ(text.find("Not shown"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n') > 10, true);
  // Every <details> is closed.
  const auto count = [&](const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<details"), 3u);
  EXPECT_EQ(count("</details>"), 3u);
}

/// Failing glyph lines ("- **NAME**") of a summary, and its "N more" count.
std::pair<int, int> shown_and_more(const std::string& text) {
  int shown = 0;
  for (std::size_t at = text.find("\n- **"); at != std::string::npos; at = text.find("\n- **", at + 1)) ++shown;
  std::smatch m;
  const std::regex more("([0-9]+) more failing glyph");
  return {shown, std::regex_search(text, m, more) ? std::stoi(m[1]) : 0};
}

// A whole Latin font with two gates: its failing glyphs do not fit a
// comment; the summary stays under 65,536 characters and says how many it
// leaves out, and the shown and left-out lines add up to the failing glyphs.
// The same with a tiny limit.
TEST(Markdown, AWholeFontStaysUnderTheLimitAndCountsWhatItLeavesOut) {
  for (const std::size_t limit : {kMarkdownLimit, std::size_t{4096}}) {
    const fs::path out = test::scratch() / ("md_" + std::to_string(limit));
    fs::remove_all(out);
    BatchOptions b;
    parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", b.report);
    b.report.regions = false;
    b.codepoints = import::parse_glyph_spec("U+0021-U+017F");
    b.out = out;
    b.markdown = out.string() + ".md";
    b.markdown_limit = limit;
    const BatchSummary s = run_batch({kDejaVu}, b);
    const std::string text = test::slurp(*b.markdown);
    EXPECT_LT(text.size(), limit);
    const auto [shown, more] = shown_and_more(text);
    EXPECT_GT(more, 0) << "the font's failing glyphs fit in " << limit << " bytes: the test needs a larger corpus";
    EXPECT_GT(shown, 0);
    EXPECT_EQ(shown + more, s.glyphs_fail) << text.substr(text.size() - 300);
    EXPECT_NE(text.find("DejaVuSans.ttf` (DejaVu Sans Book) | 318 | "), std::string::npos) << text.substr(0, 800);
    std::size_t open = 0, close = 0;
    for (std::size_t at = text.find("<details"); at != std::string::npos; at = text.find("<details", at + 1)) ++open;
    for (std::size_t at = text.find("</details>"); at != std::string::npos; at = text.find("</details>", at + 1)) ++close;
    EXPECT_EQ(open, close);
    std::cout << "limit " << limit << ": " << text.size() << " bytes, " << shown << " glyphs shown, " << more
              << " more\n";
  }
}

// --markdown through the command, to standard output (the summary line then
// goes to stderr), with a baseline: the new findings first.
TEST(Markdown, TheCommandWritesItWithTheNewFindingsOfABaseline) {
  const fs::path root = checkout("md_cli");
  ASSERT_EQ(run_in(root, "report in" + kGates + " --out acc").code, 1);
  write_spline_file(root / "in" / "new.json", wavy());  // a new file with a wave
  const test::Outcome r = run_in(root, "report in" + kGates + " --out run --baseline acc/report.json --markdown -");
  EXPECT_EQ(r.code, 1) << r.err;  // new.json's findings are new
  EXPECT_EQ(r.out.rfind("## cmr report: ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("Baseline `acc/report.json`: **"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("since the baseline</summary>"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("- `curvature-extrema-at-nodes` new.json: "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("- `curvature-extrema-at-nodes` wavy.json: "), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("; wrote run"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(root / "-"));
}

}  // namespace
}  // namespace cmr::report
