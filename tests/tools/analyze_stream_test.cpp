// JsonObjectStream (tools/cli_common.hpp; `cmr analyze` of a space curve)
// prints one member and one element at a time: the text must be byte for
// byte what printing the whole tree gives. `cmr analyze` streams its JSON
// in chunks (report/analyze_json.hpp; tests/report/analyze_json_test.cpp):
// memory must not grow with the JSON (docs/outputs.md, "Limits on work").
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tools/cli_common.hpp"

namespace {

using Json = nlohmann::ordered_json;

std::string streamed(const Json& doc, bool pretty) {
  std::ostringstream text;
  cmr::cli::JsonObjectStream out(text, pretty);
  for (const auto& [key, value] : doc.items()) {
    if (!value.is_array()) {
      out.member(key, value);
      continue;
    }
    out.begin_array(key);
    for (const Json& element : value) out.element(element);
    out.end_array();
  }
  out.finish();
  return text.str();
}

TEST(JsonObjectStream, PrintsWhatTheWholeTreePrints) {
  const Json docs[] = {
      Json::object(),
      {{"segments", Json::array()}, {"joints", Json::array()}, {"spline", {{"cmrwi", "none"}}}},
      {{"segments", {{{"index", 0}, {"interval", {2.0, 3.5}}, {"poles", Json::array()}}, {{"index", 1}}}},
       {"joints", {Json::object(), {{"g", {{"deep", {1, 2, {{"x", "\u00e9"}}}}}}}}},
       {"spline", {{"groups", {{{"segments", {0, 1}}}}}, {"empty", Json::object()}}},
       {"n", 1e-300},
       {"s", "tab\tquote\""}},
      {{"a", {1, 2, 3}}, {"b", Json::array()}, {"c", {Json::array(), Json::object()}}},
  };
  for (const Json& doc : docs)
    for (const bool pretty : {false, true})
      EXPECT_EQ(streamed(doc, pretty), cmr::cli::json_text(doc, pretty)) << doc.dump() << " pretty=" << pretty;
  // A name that is not UTF-8 is written as json_text writes it (U+FFFD).
  const Json bad = {{"file", std::string("a\xff" "b")}, {"list", {std::string("\xc3")}}};
  for (const bool pretty : {false, true}) EXPECT_EQ(streamed(bad, pretty), cmr::cli::json_text(bad, pretty));
}

// Peak resident memory (KiB) of `cmr analyze FILE > /dev/null`.
long analyze_peak_kib(const std::string& file) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::freopen("/dev/null", "w", stdout);
    ::execl(CMR_BINARY, CMR_BINARY, "analyze", file.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  if (::wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return -1;
  return usage.ru_maxrss;
}

TEST(AnalyzeMemory, GrowsByTheAnalysisNotByTheJsonText) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's shadow memory and quarantine dominate the resident size";
#endif
  // Two uniform cubic splines, 2,000 and 20,000 spans. The JSON text of the
  // larger is about 8.5 MB; held as one tree it took about 5.4 KB per span
  // (~110 MB here). Streamed, the growth is the analysis itself (about
  // 0.3 KB per span measured; 1 KB allowed).
  const auto dir = std::filesystem::temp_directory_path() / ("cmr_analyze_mem_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  long peak[2] = {0, 0};
  const int spans[2] = {2000, 20000};
  for (int k = 0; k < 2; ++k) {
    const int points = spans[k] + 3;
    Json doc = {{"degree", 3}, {"knots", Json::array()}, {"points", Json::array()}};
    for (int i = 0; i < points + 2; ++i) doc["knots"].push_back(i);
    for (int i = 0; i < points; ++i) doc["points"].push_back({i, 5.0 * std::sin(0.37 * i) + 0.01 * (i % 7)});
    const std::string file = (dir / (k == 0 ? "small.json" : "large.json")).string();
    std::ofstream(file) << doc.dump();
    peak[k] = analyze_peak_kib(file);
    ASSERT_GT(peak[k], 0) << "cmr analyze " << file << " failed";
  }
  std::filesystem::remove_all(dir);
  const double per_span_kib = static_cast<double>(peak[1] - peak[0]) / (spans[1] - spans[0]);
  EXPECT_LT(per_span_kib, 1.0) << "peak " << peak[0] << " KiB at " << spans[0] << " spans, " << peak[1] << " KiB at "
                               << spans[1];
}

}  // namespace
