#include "report/merge.hpp"
#include "report/report_cache.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "io/output.hpp"
#include "report/corpus.hpp"
#include "report/junit.hpp"
#include "report/markdown.hpp"
#include "report/report.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr::report {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Shard parse_shard(const std::string& text) {
  const auto bad = [&](const std::string& why) { return InputFieldError(field("shard") + " " + text + ": " + why); };
  const std::size_t slash = text.find('/');
  const auto number = [&](const std::string& s) {
    if (s.empty() || s.size() > 9 || !std::all_of(s.begin(), s.end(), [](unsigned char c) { return c >= '0' && c <= '9'; }))
      throw bad("not i/N with whole numbers 1 <= i <= N");
    return std::stoi(s);
  };
  if (slash == std::string::npos) throw bad("not i/N with whole numbers 1 <= i <= N");
  Shard s;
  s.index = number(text.substr(0, slash));
  s.count = number(text.substr(slash + 1));
  if (s.count < 1) throw bad("N must be at least 1");
  if (s.index < 1 || s.index > s.count) throw bad("i must be between 1 and N");
  return s;
}

std::vector<std::size_t> keep_shard(const Shard& shard, std::vector<std::string>& files, std::vector<std::string>& bases) {
  const bool with_bases = bases.size() == files.size();
  std::vector<std::size_t> positions;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < files.size(); ++k)
    if (shard.takes(k) || file_kind(files[k]) == FileKind::font) {
      positions.push_back(k);
      if (kept != k) {  // (a self-move would empty the string)
        files[kept] = std::move(files[k]);
        if (with_bases) bases[kept] = std::move(bases[k]);
      }
      ++kept;
    }
  files.resize(kept);
  if (with_bases) bases.resize(kept);
  return positions;
}

namespace {

std::string read_text(const fs::path& path, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": no " + what + " (not a cmr report part?)");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in) throw InputError(path.string() + ": cannot be read");
  return s.str();
}

Json read_json(const fs::path& path, const std::string& what) {
  try {
    return Json::parse(read_text(path, what));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not JSON (" + e.what() + ")");
  }
}

int count(const Json& summary, const char* key) {
  const auto it = summary.find(key);
  return it != summary.end() && it->is_number_integer() ? it->get<int>() : 0;
}

/// The parts' folder names under DIR/parts: each part's own name, made unique.
std::vector<std::string> part_names(const std::vector<fs::path>& parts) {
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    fs::path p = parts[i].lexically_normal();
    std::string name = (p.has_filename() ? p.filename() : p.parent_path().filename()).string();
    if (name.empty() || name == "." || name == "..") name = "part";
    std::string unique = name;
    for (int k = 2; taken.count(unique); ++k) unique = name + "-" + std::to_string(k);
    taken.insert(unique);
    names.push_back(unique);
  }
  return names;
}

/// Stages every file of `from` (hidden entries skipped: cmr's manifest and
/// temporaries; and the part's resume cache, report/report_cache.hpp) under `to`.
void copy_folder(OutputSet& out, const fs::path& from, const fs::path& to) {
  out.create_folder(to);
  std::error_code ec;
  std::vector<fs::path> files;
  fs::recursive_directory_iterator it(from, ec), end;
  if (ec) throw InputError(from.string() + ": " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw InputError(from.string() + ": " + ec.message());
    const std::string name = it->path().filename().string();
    if (!name.empty() && name[0] == '.') {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (it->is_symlink(ec)) continue;  // a part's outputs are regular files
    if (name == kReportCacheName && it->path().parent_path() == from) continue;  // the part's resume cache: its own
    if (it->is_directory(ec)) out.create_folder(to / it->path().lexically_relative(from));
    else if (it->is_regular_file(ec)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) out.stage(to / f.lexically_relative(from), read_text(f, "file"));
}

std::string junit_suites(const fs::path& path, int& next_id) {
  const std::string text = read_text(path, "JUnit file " + path.filename().string());
  const std::size_t open = text.find("<testsuites");
  const std::size_t body = open == std::string::npos ? open : text.find('>', open);
  const std::size_t close = text.rfind("</testsuites>");
  if (body == std::string::npos || close == std::string::npos || close < body)
    throw InputError(path.string() + ": not a JUnit file of cmr report (no <testsuites>)");
  std::string suites = text.substr(body + 1, close - body - 1);
  if (!suites.empty() && suites.front() == '\n') suites.erase(0, 1);
  std::string out;
  static constexpr std::string_view kSuite = "<testsuite id=\"";
  std::size_t at = 0;
  for (std::size_t s; (s = suites.find(kSuite, at)) != std::string::npos;) {
    const std::size_t digits = s + kSuite.size();
    const std::size_t quote = suites.find('"', digits);
    if (quote == std::string::npos) throw InputError(path.string() + ": a <testsuite> without its id");
    out.append(suites, at, digits - at);
    out += std::to_string(next_id++);
    at = quote;
  }
  out.append(suites, at, std::string::npos);
  return out;
}

}  // namespace

namespace {

/// Part i's CI file of the same name as the merged one (JUnit, SARIF, Markdown).
fs::path part_file(const MergeOptions& options, std::size_t i, const fs::path& name) {
  return options.parts[i] / name.filename();
}

/// The parts' report.json, each checked (a cmr report of this schema, the
/// same settings unless mixed, the same baseline) before anything is written.
std::vector<Json> read_parts(const MergeOptions& options) {
  if (options.parts.empty()) throw InputFieldError(field("parts") + ": name the parts' report folders");
  const std::string dash = field("parts") + " ";
  std::error_code ec;
  const fs::path out_abs = fs::weakly_canonical(fs::absolute(options.out), ec);
  for (const fs::path& p : options.parts) {
    const fs::path part = fs::weakly_canonical(fs::absolute(p), ec);
    const fs::path rel = out_abs.lexically_relative(part);
    if (!rel.empty() && *rel.begin() != "..")
      throw InputFieldError(dash + p.string() + ": the output folder " + options.out.string() +
                            " is (inside) this part");
  }

  // report.json of each part: checked before anything is written.
  std::vector<Json> reports;
  for (const fs::path& p : options.parts) {
    Json r = read_json(p / "report.json", "report.json");
    if (!r.is_object() || !r.contains("schema") || !r["schema"].is_string() || !r.contains("splines") ||
        !r["splines"].is_array() || !r.contains("summary") || !r["summary"].is_object())
      throw InputError((p / "report.json").string() + ": not a cmr report");
    if (r["schema"] != kSchema)
      throw InputError((p / "report.json").string() + ": schema " + r["schema"].get<std::string>() + ", not " + kSchema);
    if (!reports.empty() && !options.mixed && r["settings"] != reports.front()["settings"])
      throw InputFieldError(dash + p.string() + ": its settings (gates, check, options) differ from " +
                            options.parts.front().string() + "'s: the parts are not one run");
    const bool baseline = r["summary"].contains("baseline");
    if (!reports.empty() && baseline != reports.front()["summary"].contains("baseline"))
      throw InputFieldError(dash + p.string() + ": one part was compared with a baseline and another was not");
    if (baseline && !reports.empty() && r["summary"]["baseline"]["file"] != reports.front()["summary"]["baseline"]["file"])
      throw InputFieldError(dash + p.string() + ": its baseline differs from " + options.parts.front().string() + "'s");
    reports.push_back(std::move(r));
  }
  return reports;
}

/// One SARIF file of the parts' same-named files: the first part's run with
/// every part's results (the tools and source roots must agree).
std::string merged_sarif(const MergeOptions& options) {
  Json doc;
  Json results = Json::array();
  for (std::size_t i = 0; i < options.parts.size(); ++i) {
    const fs::path f = part_file(options, i, *options.sarif);
    Json s = read_json(f, "SARIF file " + options.sarif->filename().string());
    if (!s.is_object() || !s.contains("runs") || !s["runs"].is_array() || s["runs"].size() != 1 ||
        !s["runs"][0].contains("results") || !s["runs"][0]["results"].is_array())
      throw InputError(f.string() + ": not a SARIF file of cmr report (one run with results)");
    Json& run = s["runs"][0];
    if (i > 0 && run["tool"] != doc["runs"][0]["tool"])
      throw InputError(f.string() + ": its tool (cmr version, rules) differs from the first part's");
    if (i > 0 && run.value("originalUriBaseIds", Json()) != doc["runs"][0].value("originalUriBaseIds", Json()))
      throw InputFieldError(f.string() +
                            ": its source root differs from the first part's (run the parts from one folder, "
                            "or give " +
                            field("source_root") + ")");
    for (Json& r : run["results"]) results.push_back(std::move(r));
    if (i == 0) doc = std::move(s);
  }
  doc["runs"][0]["results"] = std::move(results);
  return doc.dump(options.pretty ? 2 : -1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

/// The merged Markdown summary: the run's line, then each part's own file
/// with its headings a level down, cut to a GitHub comment's limit.
std::string merged_markdown(const MergeOptions& options, const MergeSummary& m,
                            const std::function<std::string(std::size_t)>& shown) {
  std::string text = std::string(m.exit_code == kExitPass ? "## cmr report: pass" : "## cmr report: fail") + "\n\n" +
                     m.line + ".\n";
  for (std::size_t i = 0; i < options.parts.size(); ++i) {
    std::string part = read_text(part_file(options, i, *options.markdown), "Markdown file " + options.markdown->filename().string());
    std::string demoted;  // the part's headings one level down, under the merged one
    std::istringstream lines(part);
    for (std::string l; std::getline(lines, l);) demoted += (!l.empty() && l[0] == '#' ? "#" + l : l) + "\n";
    text += "\n### Part " + std::to_string(i + 1) + ": " + shown(i) + "\n\n" + demoted;
  }
  if (text.size() >= kMarkdownLimit) {  // a GitHub comment's limit (report/markdown.hpp)
    const std::string tail = "\n… the parts' summaries are cut here (see the merged report) …\n";
    std::size_t cut = text.rfind('\n', kMarkdownLimit - tail.size() - 1);
    text.resize(cut == std::string::npos ? 0 : cut);
    text += tail;
  }
  return text;
}

}  // namespace

MergeSummary merge_reports(const MergeOptions& options) {
  std::vector<Json> reports = read_parts(options);

  MergeSummary m;
  m.parts = static_cast<int>(reports.size());
  Json splines = Json::array(), skipped = Json::array();
  std::set<std::string> skipped_paths;
  int new_findings = 0, unchanged = 0, baseline_total = -1;
  bool any_fail_exit = false, any_invalid_exit = false;
  std::vector<std::string> part_counts;  // index.html's table
  for (Json& r : reports) {
    for (Json& s : r["splines"]) {
      if (s.is_object() && s.contains("id")) s["id"] = "s" + std::to_string(splines.size());
      splines.push_back(std::move(s));
    }
    if (r.contains("skipped") && r["skipped"].is_array())
      for (Json& k : r["skipped"])
        if (skipped_paths.insert(k.value("path", std::string())).second) skipped.push_back(std::move(k));
    const Json& s = r["summary"];
    part_counts.push_back(std::to_string(count(s, "files")) + "</td><td>" + std::to_string(count(s, "splines")) +
                          "</td><td>" + std::to_string(count(s, "pass")) + "</td><td>" + std::to_string(count(s, "fail")) +
                          "</td><td>" + std::to_string(count(s, "invalid")) + "</td><td>" +
                          std::to_string(count(s, "findings")) + "</td><td>" + std::to_string(count(s, "exit_code")));
    m.files += count(s, "files");
    m.splines += count(s, "splines");
    m.pass += count(s, "pass");
    m.fail += count(s, "fail");
    m.invalid += count(s, "invalid");
    m.findings += count(s, "findings");
    any_invalid_exit = any_invalid_exit || count(s, "exit_code") == kExitInvalid;
    any_fail_exit = any_fail_exit || count(s, "exit_code") == kExitFail;
    if (s.contains("baseline")) {
      new_findings += count(s["baseline"], "new");
      unchanged += count(s["baseline"], "unchanged");
      // Each part matched its findings against the whole baseline: its
      // unchanged + fixed is the baseline's size.
      baseline_total = count(s["baseline"], "unchanged") + count(s["baseline"], "fixed");
    }
  }
  m.exit_code = any_invalid_exit ? kExitInvalid : any_fail_exit ? kExitFail : kExitPass;
  Json summary = {{"splines", m.splines}, {"pass", m.pass},         {"fail", m.fail},       {"invalid", m.invalid},
                  {"exit_code", m.exit_code}, {"files", m.files}, {"findings", m.findings}};
  if (baseline_total >= 0)
    summary["baseline"] = {{"file", reports.front()["summary"]["baseline"]["file"]},
                           {"new", new_findings},
                           {"fixed", std::max(0, baseline_total - unchanged)},
                           {"unchanged", unchanged}};
  summary["parts"] = m.parts;
  Json merged = {{"schema", kSchema},
                 {"settings", reports.front().contains("settings") ? reports.front()["settings"] : Json::object()},
                 {"splines", std::move(splines)},
                 {"skipped", std::move(skipped)},
                 {"summary", summary}};
  reports.clear();

  BatchSummary line;
  line.files = m.files;
  line.items = m.splines;
  line.pass = m.pass;
  line.fail = m.fail;
  line.invalid = m.invalid;
  line.findings = m.findings;
  if (baseline_total >= 0) {
    line.baseline = true;
    line.new_findings = new_findings;
    line.unchanged = unchanged;
    line.fixed = std::max(0, baseline_total - unchanged);
  }
  m.line = (options.mixed ? std::string("planar and space inputs: ")
                           : "merged " + std::to_string(m.parts) + (m.parts == 1 ? " part: " : " parts: ")) +
           summary_line(line);
  m.line.erase(m.line.rfind("; "));  // no run time: the parts' times are theirs

  OutputSet out;
  out.create_folder(options.out);
  out.own_folder(options.out);

  // A part as the merged outputs name it: its folder (a mixed run's: the
  // private folder's name, planar or space).
  const std::vector<std::string> names = part_names(options.parts);
  const auto shown = [&](std::size_t i) { return options.mixed ? names[i] : options.parts[i].string(); };
  // CI files, each from the same-named file of every part (part_file).
  if (options.junit) {
    std::string text = junit_header();
    int id = 0;
    for (std::size_t i = 0; i < options.parts.size(); ++i) text += junit_suites(part_file(options, i, *options.junit), id);
    out.stage(*options.junit, text + junit_footer());
  }
  if (options.sarif) out.stage(*options.sarif, merged_sarif(options));
  if (options.markdown) out.stage(*options.markdown, merged_markdown(options, m, shown));

  // The parts' own pages, copied, and the merged index.
  for (std::size_t i = 0; i < options.parts.size(); ++i) copy_folder(out, options.parts[i], options.out / "parts" / names[i]);
  std::string page = "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>cmr report — " +
                     html_escape(m.line) + "</title><style>" + report_style() +
                     "</style></head><body><h1>cmr report</h1><p>" + html_escape(m.line) + ", schema " + kSchema +
                     ".</p><h2>Parts</h2><table class=\"index\"><tr><th>part</th><th>folder</th><th>files</th><th>splines and "
                     "contours</th><th>pass</th><th>fail</th><th>invalid</th><th>findings</th><th>exit code</th></tr>";
  for (std::size_t i = 0; i < options.parts.size(); ++i)
    page += "<tr><td><a href=\"parts/" + html_escape(names[i]) + "/index.html\">" + html_escape(names[i]) + "</a></td><td>" +
            html_escape(shown(i)) + "</td><td>" + part_counts[i] + "</td></tr>";
  page += "</table></body></html>\n";
  out.stage(options.out / "index.html", page);
  out.stage(options.out / "report.json",
            merged.dump(options.pretty ? 2 : -1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  out.commit_last(options.out / "report.json");
  out.commit();
  return m;
}

}  // namespace cmr::report
