// The report's certified fix of each failing gate (report/certified_fix.hpp)
// on every contour of a font's glyphs: per check, how many entries, how many
// found, how many hit the time limit, and the total search time (docs/fix.md,
// "In the report").
//   build/tools/bench/bench_fix_gates [FONT] [GATES] [GLYPHS]
// GATES: a --require list (default the four gates of bench_font);
// GLYPHS: default A-Z,a-z.
#include <cstdio>
#include <fstream>
#include <map>
#include <string>

#include "io/font.hpp"
#include "report/batch.hpp"
#include "report/certified_fix.hpp"

namespace {

std::string processor() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown processor";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cmr;
  const char* path = argc > 1 ? argv[1] : "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  const std::string gates =
      argc > 2 ? argv[2] : "curvature-extrema-at-nodes,max-extrema-per-segment:1,g2-at-smooth-nodes,no-inflection";
  const std::string glyphs = argc > 3 ? argv[3] : "A-Z,a-z";
  try {
    const import::Font f = import::read_font(path, import::parse_glyph_spec(glyphs));
    report::ReportOptions o;
    report::parse_require_list(gates, o);
    o.regions = false;
    std::map<std::string, double> seconds;
    std::map<std::string, int> entries, found, timeouts;
    int contours = 0;
    for (const import::Glyph& g : f.glyphs)
      for (const import::Contour& c : g.contours) {
        ++contours;
        const report::SplineReport r = report::judged_report(c.spline, o);
        for (const report::CertifiedFix& fx : report::certified_fixes(r, o)) {
          seconds[fx.check] += fx.seconds;
          ++entries[fx.check];
          found[fx.check] += fx.found;
          timeouts[fx.check] += fx.reason.find("time limit") != std::string::npos;
        }
      }
    std::printf("bench_fix_gates: %s, glyphs %s, %d contours, %s; each fix 1 thread, %.0f s limit\n\n", path,
                glyphs.c_str(), contours, processor().c_str(), report::kReportFixSeconds);
    std::printf("| check | failing contours | fixed | time limit | total s |\n|---|---|---|---|---|\n");
    for (const auto& [check, s] : seconds)
      std::printf("| %s | %d | %d | %d | %.2f |\n", check.c_str(), entries[check], found[check], timeouts[check], s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_fix_gates: %s\n", e.what());
    return 2;
  }
  return 0;
}
