// Pipes (issue 40, item 7): every command that reads a spline, points or
// script file reads standard input when given "-" (and FIFOs such as
// /dev/stdin); every command that writes a spline writes it to standard
// output (cmr knots and cmr kcurve by default, cmr fix with --out -). Bad
// input on the pipe is one line and exit 2. Each test spawns the built cmr
// through /bin/sh with a real pipe (spline/spline_json.cpp, read_input_file).
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace {

using cmr::test::Outcome;
using cmr::test::run_captured;
using cmr::test::scratch;
namespace fs = std::filesystem;

const std::string kCmr = CMR_BINARY;
const std::string kSource = CMR_SOURCE_DIR;
const std::string kClamped = kSource + "/examples/clamped.json";  // cubic, knots 0,0,0,1,2,3,3,3
const std::string kSpace = kSource + "/examples/space/fig8b_lifted.json";
const std::string kPoints = kSource + "/examples/kcurve/points.json";

/// One line on stderr, containing `part`.
void expect_one_line(const Outcome& r, const std::string& part, const std::string& label) {
  EXPECT_NE(r.err.find(part), std::string::npos) << label << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << label << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << label << ": " << r.out;
}

/// cmr's analysis JSON without its "file" member (the one thing a pipe changes).
nlohmann::json without_file(const std::string& text) {
  nlohmann::json doc = nlohmann::json::parse(text);
  doc.erase("file");
  return doc;
}

TEST(Pipes, KnotsInsertPipedIntoAnalyzePrintsTheAnalysisOfTheNewSpline) {
  const fs::path written = scratch() / "pipes_inserted.json";
  ASSERT_EQ(run_captured(kCmr + " knots " + kClamped + " insert 1.5 --out " + written.string()).code, 0);
  const Outcome file = run_captured(kCmr + " analyze " + written.string());
  const Outcome piped = run_captured(kCmr + " knots " + kClamped + " insert 1.5 | " + kCmr + " analyze -");
  ASSERT_EQ(file.code, 0) << file.err;
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_TRUE(piped.err.empty()) << piped.err;
  EXPECT_EQ(without_file(piped.out), without_file(file.out));
  EXPECT_EQ(nlohmann::json::parse(piped.out)["segments"].size(), 4u);  // 3 spans, one split at 1.5
}

TEST(Pipes, KnotsThroughKnotsThroughAnalyzeAndDevStdin) {
  const std::string chain = kCmr + " knots " + kClamped + " insert 1.5 | " + kCmr + " knots - insert 2.5 | ";
  for (const char* input : {"-", "/dev/stdin", "/dev/fd/0"}) {
    const Outcome r = run_captured(chain + kCmr + " analyze " + input);
    ASSERT_EQ(r.code, 0) << input << ": " << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["segments"].size(), 5u) << input;
  }
  // A redirected file is standard input too.
  const Outcome redirected = run_captured(kCmr + " analyze - < " + kClamped);
  ASSERT_EQ(redirected.code, 0) << redirected.err;
  EXPECT_EQ(without_file(redirected.out), without_file(run_captured(kCmr + " analyze " + kClamped).out));
}

TEST(Pipes, EveryReadingCommandReadsStandardInput) {
  const fs::path dir = scratch() / "pipes_every";
  fs::remove_all(dir);
  fs::create_directories(dir);
  struct Case {
    std::string command, input;
  };
  const Case cases[] = {
      {"segments -", kClamped},
      {"knots - clamp", kClamped},
      {"region - --point 2 --size 32x32 --backend cpu --png " + (dir / "r.png").string(), kClamped},
      {"fix - --points 3", kClamped},
      {"sweep - --point 2 --knot 3 --from 0.5 --to 1.5 --steps 2 --size 32x32 --backend cpu --out-dir " +
           (dir / "sweep").string(),
       kClamped},
      {"kcurve -", kPoints},
      {"analyze -", kSpace},  // a space curve: the file's dimension is read first, then the curve (stdin kept)
      {"report - --no-thumbnails --out " + (dir / "planar").string(), kClamped},
      {"report - --no-thumbnails --out " + (dir / "space").string(), kSpace},
      {"region - --point 2 --plane xy --size 32x32 --png " + (dir / "s.png").string(), kSpace},
  };
  for (const Case& c : cases) {
    const Outcome piped = run_captured("cat " + c.input + " | " + kCmr + " " + c.command);
    EXPECT_EQ(piped.code, 0) << c.command << ": " << piped.err;
    EXPECT_EQ(piped.err.find("stdin"), std::string::npos) << c.command << ": " << piped.err;
  }
  EXPECT_TRUE(fs::exists(dir / "r.png"));
  EXPECT_TRUE(fs::exists(dir / "s.png"));
  for (const char* run : {"planar", "space"}) {  // one spline each, read from the pipe, its findings naming "-"
    const nlohmann::json doc = nlohmann::json::parse(cmr::test::slurp(dir / run / "report.json"));
    ASSERT_EQ(doc["splines"].size(), 1u) << run;
    EXPECT_NE(doc["splines"][0].value("status", ""), "invalid") << run << ": " << doc["splines"][0].dump();
  }
  fs::remove_all(dir);
}

TEST(Pipes, FixWritesTheFixedSplineToStandardOutputAndItsReportToStderr) {
  const fs::path fix_err = scratch() / "pipes_fix_err";
  const Outcome r = run_captured(kCmr + " fix " + kClamped + " --out - 2>" + fix_err.string() + " | " + kCmr + " analyze -");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json analysis = nlohmann::json::parse(r.out);
  EXPECT_EQ(analysis["spline"]["cmr"], "increasing") << r.out;  // the fixed curve passes the default check
  const nlohmann::json fix = nlohmann::json::parse(cmr::test::slurp(fix_err));  // the fix's own JSON, on stderr
  EXPECT_EQ(fix["fixed"], true);
  EXPECT_EQ(fix["out"], "-");
}

TEST(Pipes, BadInputOnThePipeIsOneLineAndExit2) {
  struct Case {
    std::string command, part;
  };
  const Case cases[] = {
      {"printf '{bad' | CMR analyze -", "stdin: malformed JSON"},
      {"printf '{\"points\": [[0, 0]]}' | CMR knots - clamp", "stdin: points"},
      {"true | CMR analyze -", "stdin: empty (nothing came through the FIFO)"},
      {"CMR analyze - < /dev/null", "stdin: empty (nothing to read)"},
      {"CMR analyze - <&-", "stdin: closed"},
      {"CMR segments - <&-", "stdin: closed"},
      {"true | CMR analyze /dev/stdin", "/dev/stdin: empty (nothing came through the FIFO)"},
      // The upstream command fails: it says why, and the downstream one finds the pipe empty.
      {"CMR knots /nonexistent.json insert 1 2>/dev/null | CMR analyze -", "stdin: empty"},
      {"CMR analyze - < " + kSource, "stdin: not a regular file (a folder)"},
      {"CMR kcurve - < /dev/null", "stdin: empty"},
      // Over the input limit: refused after at most one byte past it.
      {"head -c 67108865 /dev/zero | CMR analyze -", "stdin: larger than the 64 MiB input limit"},
  };
  for (const Case& c : cases) {
    std::string command = c.command;
    for (std::size_t at; (at = command.find("CMR")) != std::string::npos;) command.replace(at, 3, kCmr);
    const Outcome r = run_captured(command);
    EXPECT_EQ(r.code, 2) << c.command << ": " << r.err;
    expect_one_line(r, c.part, c.command);
  }
}

TEST(Pipes, ANamedFifoWithoutAWriterIsRefusedAtOnceAndOneWithAWriterIsRead) {
  const fs::path dir = scratch() / "pipes_fifo";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path fifo = dir / "in.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto t0 = std::chrono::steady_clock::now();
  const Outcome none = run_captured("timeout 20 " + kCmr + " analyze " + fifo.string());
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
  EXPECT_EQ(none.code, 2) << none.err;
  expect_one_line(none, fifo.string() + ": empty (nothing came through the FIFO)", "no writer");
  // A writer that holds the FIFO open (read-write: its open does not wait)
  // before cmr opens it, and writes late: cmr waits for it.
  const Outcome late = run_captured("{ (exec 3<>" + fifo.string() + "; sleep 1; cat " + kClamped +
                                    " >&3) & sleep 0.3; timeout 20 " + kCmr + " analyze " + fifo.string() + "; }");
  EXPECT_EQ(late.code, 0) << late.err;
  EXPECT_FALSE(late.out.empty());
  fs::remove_all(dir);
}

}  // namespace
