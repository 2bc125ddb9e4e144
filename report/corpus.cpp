#include "report/corpus.hpp"
#include "report/corpus_detail.hpp"

#include <dirent.h>
#include <fnmatch.h>
#include <sys/stat.h>
#include <glob.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <fstream>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string_view>

#include "io/font.hpp"
#include "io/output.hpp"
#include "io/svg.hpp"
#include "io/ufo.hpp"
#include "report/baseline.hpp"
#include "report/interpolation.hpp"
#include "report/json_stream.hpp"
#include "report/junit.hpp"
#include "report/markdown.hpp"
#include "report/report_cache.hpp"
#include "report/sarif.hpp"
#include "spline/format.hpp"
#include "report/batch.hpp"
#include "report/severity.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"

// A corpus run (corpus.hpp: run_batch): files in parallel through the
// report, the writers of every output format as files finish, summaries and
// progress. The run's inputs (finding the files, naming them, one file's
// reports and findings) are in corpus_inputs.cpp.

namespace cmr::report {

using namespace corpus_detail;  // what the parts share (corpus_detail.hpp)

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// ------------------------------------------------------------ summaries

std::string summary_line(const BatchSummary& s) {
  std::string line = std::to_string(s.files) + (s.files == 1 ? " file" : " files");
  if (s.fonts > 0)
    line += " (" + std::to_string(s.fonts) + (s.fonts == 1 ? " font, " : " fonts, ") + std::to_string(s.glyphs) +
            " glyphs, " + std::to_string(s.glyphs_fail) + " failing)";
  line += ": " + std::to_string(s.items) + (s.fonts > 0 ? " contours and splines: " : (s.items == 1 ? " spline: " : " splines: ")) +
          std::to_string(s.pass) + " pass, " + std::to_string(s.fail) + " fail, " + std::to_string(s.invalid) +
          " invalid; " + std::to_string(s.findings) + (s.findings == 1 ? " finding" : " findings");
  if (s.baseline)
    line += " (baseline: " + std::to_string(s.new_findings) + " new, " + std::to_string(s.fixed) + " fixed, " +
            std::to_string(s.unchanged) + " unchanged)";
  char t[32];
  std::snprintf(t, sizeof t, "; %.1f s", s.seconds);
  return line + t;
}

namespace {

std::string clock_text(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[32];
  if (s >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

}  // namespace

void select_font_inputs(BatchOptions& batch, const ReportOptions& checks, const std::string& glyphs,
                        const std::string& location, const std::string& between,
                        const std::vector<std::string>& files) {
  const import::GlyphSelection which = import::parse_glyph_selection(glyphs);
  batch.all_glyphs = which.all;
  batch.codepoints = which.codepoints;
  if (!location.empty()) {
    for (const std::string& f : files)
      if (!import::is_font_path(f))
        throw InputFieldError(field("location") + ": for variable fonts (.ttf, .otf), not for " + f);
    batch.location = import::parse_location(location);
  }
  if (!between.empty()) {
    if (std::none_of(checks.gates.begin(), checks.gates.end(), is_interpolation_gate))
      throw InputFieldError(field("between") + ": only with an interpolation gate (" + field("require") +
                            " g1-between-masters)");
    batch.between = import::parse_between(between);
  }
}

BatchProgress terminal_progress(std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  return [&err, start](int done, int total, int items, const std::string& name) {
    constexpr int kWidth = 24;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int filled = total > 0 ? done * kWidth / total : kWidth;
    const double eta = done > 0 ? elapsed * (total - done) / done : 0;
    char rate[48];
    std::snprintf(rate, sizeof rate, "%.0f/s", elapsed > 0 ? items / elapsed : 0.0);
    std::string shown = name.size() > 40 ? "..." + name.substr(name.size() - 37) : name;
    err << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '-') << "] " << done << '/' << total
        << " files, " << items << " splines, " << rate << ", ETA " << clock_text(eta) << ' ' << shown << "\033[K"
        << std::flush;
  };
}

void clear_progress(std::ostream& err) { err << "\r\033[K" << std::flush; }

namespace {

/// Per font, for the summary page.
struct FontRow {
  std::string title, path, page;
  int glyphs = 0, contours = 0, glyphs_fail = 0, contours_fail = 0, invalid = 0;
  std::vector<int> gate_glyphs;  ///< glyphs failing each gate
  /// The glyphs that matter most, at most kWorst: by the largest severity of
  /// their failing findings (--min-severity; none found counts as the most),
  /// then by how many findings they have.
  struct Worst {
    double severity = -1;  ///< -1: not computed
    int findings = 0;
    std::string glyph;
  };
  std::vector<Worst> worst;
  bool cubic = false;
};
constexpr std::size_t kWorst = 8;

/// A processed file with the outputs that need no numbering (Writer::prepare).
struct PreparedFile {
  FileWork work;  ///< a spline or SVG file keeps its reports: its page sections are numbered
  FileRecord rec;
  std::string json;  ///< its spline objects back to back, each with the id "s0"
  std::vector<std::pair<std::size_t, std::size_t>> objects;  ///< per object: its start, the offset of its id's 0
  std::vector<std::string> invalid_messages;
  std::optional<FontRow> font_row;  ///< a font: its summary row (page name set by write)
  std::string font_page;            ///< a font: its page
  std::vector<std::string> sarif;   ///< results in case order, without a baseline state
  std::string junit;                ///< its suite, with the id 0
  /// A part of a file streamed in parts (an SVG's paths, kStreamChunk at a
  /// time), and more parts of it follow: Writer::write writes its splines
  /// and keeps its record until the last part (its JUnit suite, its
  /// Markdown lines and the file count are the whole file's).
  bool more = false;
  /// A font's glyphs taken from the resume cache and judged, and the new
  /// cache's records of its glyphs.
  int reused = 0, judged = 0;
  std::string cache_records;
};

const char* status_class(const SplineReport& r) { return !r.error.empty() ? "invalid" : (r.pass ? "pass" : "fail"); }

std::string badge_html(const char* status) {
  std::string upper = status;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return std::string("<span class=\"badge ") + status + "\">" + upper + "</span>";
}

std::string now_iso8601() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  return buf;
}

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "localhost";
  return buf;
}

/// An SVG file's paths are reported and written this many at a time.
constexpr std::size_t kStreamChunk = 1024;
/// An SVG file larger than this is reported alone (its parts in order),
/// not beside other files in parallel.
constexpr std::uintmax_t kStreamBytes = 256 * 1024;

/// Writes a run's outputs as its files finish, in file order (prepare in
/// the processing threads, write in one thread at a time).
class Writer {
 public:
  Writer(const BatchOptions& options, std::size_t files, std::size_t fonts)
      : options_(options), single_font_(fonts == 1) {
    out_.create_folder(options.out);
    out_.own_folder(options.out);  // a reused folder keeps only this run's files
    if (fonts > 1) out_.create_folder(options.out / "fonts");
    if (options.junit) junit_ = out_.stage_stream(*options.junit);
    if (options.sarif) sarif_ = out_.stage_stream(*options.sarif);
    json_ = out_.stage_stream(options.out / "report.json");
    out_.commit_last(options.out / "report.json");  // renamed last: a new report.json means the whole report is new
    // The resume cache (report/report_cache.hpp): the previous one is read
    // before anything is judged; the new one is one more file of the set.
    if (options.cache && fonts > 0 && !build_id().empty()) {
      const fs::path file = options.out / kReportCacheName;
      old_cache_.open(file, cache_note_);
      summary_.cache_read = old_cache_.usable();
      cache_.emplace();
      cache_->old = &old_cache_;
      cache_->run_prefix = run_key_prefix(options);
      cache_file_ = out_.stage_stream(file);
      cache_file_.write(cache_header());
    }
    sections_.reset(std::tmpfile());
    if (!sections_) throw EnvironmentError("a temporary file for the page: cannot be created");
    if (options.markdown) markdown_.emplace(options.report, options.markdown_limit);
    if (options.baseline) {
      baseline_.emplace(read_baseline(*options.baseline));
      summary_.baseline = true;
    }
    summary_.files = static_cast<int>(files);
    Json settings = report_json({}, options.report)["settings"];
    if (!options.location.empty()) {  // the variable fonts' instance judged (merge and readers tell runs apart)
      Json at = Json::object();
      for (const auto& [tag, value] : options.location) at[tag] = value;
      settings["location"] = at;
    }
    json_.write("{\"schema\":\"" + std::string(kSchema) + "\",\"settings\":" + dump(settings) + ",\"splines\":[");
    if (junit_.is_open()) junit_.write(junit_header());
    if (sarif_.is_open())
      sarif_.write(sarif_header(options.report, source_uri_base(options.source_root ? options.source_root->string() : "")));
    timestamp_ = now_iso8601();
    host_ = host_name();
  }

  int items() const { return summary_.items; }
  /// The resume cache of the run's fonts (nullptr: none).
  const CacheContext* cache() const { return cache_ ? &*cache_ : nullptr; }

  /// Item `i` of `w` as the report writes it (its JSON object with the id "s0").
  CachedItem item_output(const FileWork& w, std::size_t i, const ItemNames& n) const {
    const SplineReport& r = w.reports[i];
    CachedItem it;
    it.findings = findings_of(r, w.name, n, options_.report);
    SplineJsonExtras extras;
    extras.source = &w.path;
    extras.glyph = n.glyph;
    extras.contour = n.contour;
    extras.point_names = n.points;
    extras.findings = &it.findings;
    JsonStream stream(it.json, options_.pretty ? 2 : -1);
    write_spline_json(stream, r, 0, extras);
    it.error = r.error;
    it.pass = r.pass;
    for (const GateResult& g : r.gates) it.gate_pass.push_back(g.pass());
    return it;
  }

  /// The part of a file's outputs that does not depend on the files before
  /// it: its spline objects' JSON text (ids numbered later), findings, cases,
  /// its font page, its SARIF results and JUnit suite. Reads only what the
  /// constructor set, so the threads that process files call it in parallel
  /// and the one writing thread (write) only numbers, counts and writes.
  PreparedFile prepare(FileWork&& w) const {
    PreparedFile p;
    p.json = take_buffer();
    FileRecord& rec = p.rec;
    rec.path = w.path;
    rec.kind = w.kind;
    rec.seconds = w.seconds;
    rec.title = w.font ? w.font->family + " " + w.font->style : w.path;
    std::vector<ItemNames> names(w.reports.size());
    if (w.font) {
      for (const auto& g : w.font->glyphs)
        for (std::size_t c = 0; c < g.items.size(); ++c)
          names[g.items[c]] = {g.name, static_cast<int>(c), &g.joint_names[c], &g.point_names[c], &g.source,
                               c < g.point_lines.size() ? &g.point_lines[c] : nullptr,
                               c < g.joint_lines.size() ? &g.joint_lines[c] : nullptr};
    }
    // Each item as the report writes it: a font's glyph from the resume
    // cache as the cache has it, the others from their reports.
    std::vector<const CachedItem*> item_of(w.reports.size(), nullptr);
    std::vector<CachedGlyph> glyphs;
    if (w.font) {
      glyphs.resize(w.font->glyphs.size());
      for (std::size_t gi = 0; gi < glyphs.size(); ++gi) {
        const auto& g = w.font->glyphs[gi];
        const bool cached = gi < w.cached.size() && w.cached[gi].has_value();
        if (cached) {
          glyphs[gi] = std::move(*w.cached[gi]);
          ++p.reused;
        } else {
          for (std::size_t i : g.items) glyphs[gi].items.push_back(item_output(w, i, names[i]));
          glyphs[gi].html = font_glyph_html(*w.font, 0, gi, w.reports, options_.report);
          ++p.judged;
        }
        if (glyphs[gi].items.size() != g.items.size()) throw std::logic_error("report cache: a glyph's contours differ");
        for (std::size_t c = 0; c < g.items.size(); ++c) item_of[g.items[c]] = &glyphs[gi].items[c];
        // The new cache: every glyph whose output is whole.
        if (gi < w.keys.size() && (cached || (w.store && (glyphs[gi].html.pass || w.store_failing))))
          p.cache_records += cache_record(w.keys[gi], glyphs[gi]);
      }
    }
    std::vector<CachedItem> loose(w.reports.size());  // items of no glyph: spline and SVG files
    for (std::size_t i = 0; i < w.reports.size(); ++i) {
      if (item_of[i] != nullptr) continue;
      const SplineReport& r = w.reports[i];
      if (!w.font) names[i] = {r.name, 0, nullptr, nullptr};
      if (w.font && names[i].glyph.empty()) names[i].glyph = r.name;  // an unreadable font: its one invalid item
      loose[i] = item_output(w, i, names[i]);
      item_of[i] = &loose[i];
    }
    // The file's spline objects as text (report/json_stream.hpp: the same bytes
    // as the tree), each with the id "s0"; write puts in the run's numbers.
    std::vector<std::vector<Finding>> item_findings(w.reports.size());
    for (std::size_t i = 0; i < w.reports.size(); ++i) {
      const CachedItem& it = *item_of[i];
      item_findings[i] = it.findings;
      const std::size_t begin = p.json.size();
      p.json += it.json;
      const std::size_t id = p.json.find("\"s0\"", begin);  // the first member is the id
      if (id == std::string::npos) throw std::logic_error("report.json: a spline object without its id");
      p.objects.push_back({begin, id + 2});
      ++rec.items;
      (!it.error.empty() ? rec.items_invalid : (it.pass ? rec.items_pass : rec.items_fail))++;
      if (!it.error.empty()) p.invalid_messages.push_back(it.error);
    }
    // Cases: one per glyph of a font, else one per spline.
    if (w.font) {
      FontRow& row = p.font_row.emplace();
      row.title = rec.title;
      row.path = w.path;
      row.cubic = w.font->cubic;
      row.gate_glyphs.assign(options_.report.gates.size(), 0);
      for (const auto& g : w.font->glyphs) {
        CaseRecord c;
        c.name = g.name;
        c.contours = static_cast<int>(g.items.size());
        std::vector<bool> gate_fail(options_.report.gates.size(), false);
        for (std::size_t i : g.items) {
          const CachedItem& r = *item_of[i];
          if (!r.error.empty()) c.error += (c.error.empty() ? "" : "; ") + r.error;
          c.pass = c.pass && r.error.empty() && r.pass;
          for (std::size_t k = 0; k < r.gate_pass.size() && k < gate_fail.size(); ++k)
            gate_fail[k] = gate_fail[k] || !r.gate_pass[k];
          for (Finding& f : item_findings[i]) c.findings.push_back(std::move(f));
        }
        ++row.glyphs;
        row.contours += c.contours;
        for (std::size_t i : g.items) row.contours_fail += item_of[i]->error.empty() && item_of[i]->pass ? 0 : 1;
        row.glyphs_fail += c.pass ? 0 : 1;
        row.invalid += c.error.empty() ? 0 : 1;
        for (std::size_t k = 0; k < gate_fail.size(); ++k) row.gate_glyphs[k] += gate_fail[k];
        if (!c.findings.empty()) {
          double severity = -1;
          for (const Finding& f : c.findings)
            if (!f.info && f.severity >= 0) severity = std::max(severity, f.severity);
          row.worst.push_back({severity, static_cast<int>(c.findings.size()), g.name});
        }
        rec.cases.push_back(std::move(c));
      }
      std::stable_sort(row.worst.begin(), row.worst.end(), [](const FontRow::Worst& a, const FontRow::Worst& b) {
        return a.severity != b.severity ? a.severity > b.severity : a.findings > b.findings;
      });
      if (row.worst.size() > kWorst) row.worst.resize(kWorst);
      if (w.font->glyphs.empty() && !w.reports.empty() && !item_of[0]->error.empty()) {
        CaseRecord c;  // an unreadable font
        c.name = fs::path(w.path).filename().string();
        c.error = item_of[0]->error;
        c.pass = false;
        rec.cases.push_back(std::move(c));
        row.invalid = 1;
      }
      std::vector<GlyphHtml> html;
      for (CachedGlyph& g : glyphs) html.push_back(std::move(g.html));
      p.font_page = font_page_html({*w.font}, {std::move(html)}, options_.report);
      w.reports.clear();
      w.reports.shrink_to_fit();
    } else {
      for (std::size_t i = 0; i < w.reports.size(); ++i) {
        const SplineReport& r = w.reports[i];
        CaseRecord c;
        c.name = r.name;
        c.error = r.error;
        c.pass = r.error.empty() && r.pass;
        c.findings = std::move(item_findings[i]);
        rec.cases.push_back(std::move(c));
      }
    }
    // SARIF results without a baseline state (write adds it: the last member).
    if (options_.sarif) {
      for (const CaseRecord& c : rec.cases) {
        if (!c.error.empty()) p.sarif.push_back(sarif_invalid(w.uri, w.uri_relative, c.name, c.error, options_.report));
        for (const Finding& f : c.findings)
          if (f.source.empty()) {
            p.sarif.push_back(sarif_result(f, w.uri, w.uri_relative, options_.report, nullptr));
          } else {  // a font source's finding: its .glif, on the <point>'s line
            bool relative = false;
            const std::string uri =
                source_uri(f.source, options_.source_root ? options_.source_root->string() : std::string(), &relative);
            p.sarif.push_back(sarif_result(f, uri, relative, options_.report, nullptr));
          }
      }
    }
    if (options_.junit) p.junit = junit_suite(rec, 0, timestamp_, host_);
    p.work = std::move(w);
    return p;
  }

  /// Writes a prepared file: numbers its spline objects and its JUnit suite
  /// after the files before it, compares its findings with the baseline and
  /// counts them.
  void write(PreparedFile& p) {
    FileRecord& rec = p.rec;
    FileWork& w = p.work;
    std::string& text = text_;  // the file's objects, written at once
    text.clear();                // (one buffer for the run: its pages are not faulted in again per file)
    for (std::size_t i = 0; i < p.objects.size(); ++i) {
      const auto [begin, digit] = p.objects[i];
      const std::size_t end = i + 1 < p.objects.size() ? p.objects[i + 1].first : p.json.size();
      if (first_ + i != 0) text += ',';
      if (options_.pretty) text += '\n';
      text.append(p.json, begin, digit - begin);
      text += std::to_string(first_ + static_cast<int>(i));
      text.append(p.json, digit + 1, end - digit - 1);
    }
    json_.write(text);
    give_back(std::move(p.json));
    if (cache_file_.is_open() && !p.cache_records.empty()) cache_file_.write(p.cache_records);
    summary_.glyphs_reused += p.reused;
    summary_.glyphs_judged += p.judged;
    for (std::string& m : p.invalid_messages) summary_.invalid_messages.push_back(std::move(m));
    if (p.font_row) {
      FontRow& row = *p.font_row;
      row.page = single_font_ ? "font.html"
                              : "fonts/" + std::to_string(summary_.fonts) + "-" + import::file_stem(fs::path(w.path).stem().string()) + ".html";
      out_.stage(options_.out / row.page, p.font_page);
      rec.page = row.page;
      ++summary_.fonts;
      summary_.glyphs += row.glyphs;
      summary_.glyphs_fail += row.glyphs_fail;
      fonts_.push_back(std::move(row));
    } else {
      for (std::size_t i = 0; i < w.reports.size(); ++i) {
        const SplineReport& r = w.reports[i];
        const int id = first_ + static_cast<int>(i);
        std::string row = "<tr><td>" + std::to_string(id) + "</td><td><a href=\"#s" + std::to_string(id) + "\">" +
                          html_escape(r.name) + "</a></td><td>" + html_escape(r.file) + "</td><td>" +
                          badge_html(status_class(r)) + "</td>";
        // A spline of straight segments only has constant (zero) curvature: "straight", not a direction.
        if (r.error.empty())
          row += "<td>" + verdict_label(r, r.analysis.cmrwi) + "</td><td>" + verdict_label(r, r.analysis.cmr) +
                 "</td><td>" + std::to_string(r.monotone_pieces) + "</td><td>" +
                 std::to_string(rec.cases[i].findings.size()) + "</td></tr>";
        else
          row += "<td colspan=\"4\">invalid input</td></tr>";
        spline_rows_.push_back(std::move(row));
      }
      const std::string html = report_sections_html(w.reports, first_, options_.report);
      if (std::fwrite(html.data(), 1, html.size(), sections_.get()) != html.size())
        throw EnvironmentError("a temporary file for the page: cannot be written");
    }
    first_ += rec.items;
    w.reports.clear();
    w.reports.shrink_to_fit();

    // Findings: counted, compared with the baseline, written to SARIF (the
    // file's results in one write).
    std::string& sarif = text_;  // report.json's text is written already
    sarif.clear();
    std::size_t next_result = 0;
    const auto add_result = [&](const std::string& result) {
      if (sarif_results_++ != 0) sarif += ',';
      sarif += result;
    };
    for (const CaseRecord& c : rec.cases) {
      if (!c.error.empty() && sarif_.is_open()) add_result(p.sarif[next_result++]);
      for (const Finding& f : c.findings) {
        ++summary_.findings;
        const char* state = nullptr;
        if (baseline_) {
          state = baseline_->judge(f);
          if (std::string_view(state) == "new") {
            ++summary_.new_findings;
            summary_.new_list.push_back(f);
          } else {
            ++summary_.unchanged;
          }
        }
        if (sarif_.is_open()) {
          std::string& result = p.sarif[next_result++];
          if (state) {  // sarif_result with the state: "baselineState" is its last member
            result.pop_back();
            result += std::string(",\"baselineState\":\"") + state + "\"}";
          }
          add_result(result);
        }
      }
    }
    if (!sarif.empty()) sarif_.write(sarif);
    const int items = rec.items, items_pass = rec.items_pass, items_fail = rec.items_fail, items_invalid = rec.items_invalid;
    const auto count = [&] {
      summary_.items += items;
      summary_.pass += items_pass;
      summary_.fail += items_fail;
      summary_.invalid += items_invalid;
    };
    if (p.more || part_) {  // a file in parts: its record is the parts' together
      if (!part_) {
        part_ = std::move(rec);
      } else {
        part_->seconds += rec.seconds;
        part_->items += items;
        part_->items_pass += items_pass;
        part_->items_fail += items_fail;
        part_->items_invalid += items_invalid;
        for (CaseRecord& c : rec.cases) part_->cases.push_back(std::move(c));
      }
      if (p.more) return count();
      rec = std::move(*part_);
      part_.reset();
      if (junit_.is_open()) p.junit = junit_suite(rec, 0, timestamp_, host_);
    }
    if (markdown_) markdown_->add(rec, w.name, rec.kind == FileKind::font ? rec.title : std::string());
    if (junit_.is_open()) {  // junit_suite with this file's index as its id
      static constexpr std::string_view kHead = "  <testsuite id=\"0\"";
      if (p.junit.compare(0, kHead.size(), kHead) != 0) throw std::logic_error("JUnit: a suite without its id");
      junit_.write("  <testsuite id=\"" + std::to_string(file_index_) + "\"" + p.junit.substr(kHead.size()));
    }
    ++file_index_;
    count();
  }

  BatchSummary finish(double seconds) {
    summary_.seconds = seconds;
    if (baseline_) summary_.fixed = baseline_->fixed();
    const bool gated = options_.report.require.has_value() || !options_.report.gates.empty();
    summary_.exit_code = summary_.invalid > 0 ? kExitInvalid
                         : baseline_        ? (summary_.new_findings > 0 ? kExitFail : kExitPass)
                         : (gated && summary_.fail > 0) ? kExitFail
                                                        : kExitPass;
    Json s = {{"splines", summary_.items}, {"pass", summary_.pass}, {"fail", summary_.fail},
              {"invalid", summary_.invalid}, {"exit_code", summary_.exit_code}, {"files", summary_.files},
              {"findings", summary_.findings}};
    if (baseline_)
      s["baseline"] = {{"file", options_.baseline->string()}, {"new", summary_.new_findings},
                       {"fixed", summary_.fixed}, {"unchanged", summary_.unchanged}};
    Json skipped = Json::array();
    for (const SkippedPath& k : options_.skipped)
      skipped.push_back({{"path", k.path}, {"reason", options_.report.show_fields(k.reason)}});
    json_.write(std::string(options_.pretty ? "\n" : "") + "],\"skipped\":" + dump(skipped) + ",\"summary\":" + dump(s) +
                "}\n");
    if (markdown_)
      out_.stage(*options_.markdown, markdown_->finish(summary_, options_.baseline ? options_.baseline->string() : ""));
    json_.close();
    if (junit_.is_open()) {
      junit_.write(junit_footer());
      junit_.close();
    }
    if (sarif_.is_open()) {
      sarif_.write(sarif_footer());
      sarif_.close();
    }
    if (cache_file_.is_open()) cache_file_.close();
    summary_.cache_note = cache_note_;
    const std::string damage = old_cache_.damage_note();
    if (!damage.empty()) summary_.cache_note += (summary_.cache_note.empty() ? "" : "; ") + damage;
    write_index();
    summary_.written = out_.paths();
    out_.commit();
    return summary_;
  }

 private:
  std::string text_;  // write's report.json text of one file

  // Buffers for prepare's JSON text, given back by write: a large string
  // reused keeps its pages, where a fresh one per file is regrown and its
  // pages faulted in again (a font's objects are megabytes).
  std::string take_buffer() const {
    const std::lock_guard lock(pool_mutex_);
    if (pool_.empty()) return {};
    std::string b = std::move(pool_.back());
    pool_.pop_back();
    return b;
  }
  void give_back(std::string&& b) {
    b.clear();
    const std::lock_guard lock(pool_mutex_);
    if (pool_.size() < kPooledBuffers) pool_.push_back(std::move(b));
  }
  static constexpr std::size_t kPooledBuffers = 8;
  mutable std::mutex pool_mutex_;
  mutable std::vector<std::string> pool_;

  std::string dump(const Json& j) const {
    return j.dump(options_.pretty ? 2 : -1, ' ', false, nlohmann::json::error_handler_t::replace);
  }

  void write_index() {
    StagedStream page = out_.stage_stream(options_.out / "index.html");
    std::string head = "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>cmr report — " +
                       html_escape(summary_line(summary_)) + "</title><style>" + report_style() +
                       "</style></head><body><h1>cmr report</h1><p>" + html_escape(summary_line(summary_)) +
                       ". Check <b>" + html_escape(to_string(check_of(options_.report))) + "</b>" +
                       (options_.report.require ? " (required)" : " (not required)");
    std::string gates;
    for (const Gate& g : options_.report.gates) gates += (gates.empty() ? "" : ", ") + to_string(g);
    if (!gates.empty()) head += "; gates <b>" + html_escape(gates) + "</b>";
    head += ", depth " + std::to_string(options_.report.max_depth) + ", schema " + kSchema + ".</p>";
    if (summary_.baseline) {
      head += "<p>Baseline " + html_escape(options_.baseline->string()) + ": <b>" + std::to_string(summary_.new_findings) +
              " new</b>, " + std::to_string(summary_.fixed) + " fixed, " + std::to_string(summary_.unchanged) +
              " unchanged.</p>";
      if (!summary_.new_list.empty()) {
        head += "<ul>";
        for (const Finding& f : summary_.new_list)
          head += "<li>" + html_escape(f.file) + ": " + html_escape(f.gate) + ": " + html_escape(f.message) + "</li>";
        head += "</ul>";
      }
    }
    if (!options_.skipped.empty()) {  // what the folder walks left out, and why
      head += "<details><summary>" + std::to_string(options_.skipped.size()) + " skipped</summary><ul>";
      for (const SkippedPath& k : options_.skipped)
        head += "<li>" + html_escape(k.path) + ": " + html_escape(options_.report.show_fields(k.reason)) + "</li>";
      head += "</ul></details>";
    }
    if (!fonts_.empty()) {
      head += "<h2>Fonts</h2><table class=\"index\"><tr><th>font</th><th>file</th><th>outlines</th><th>glyphs</th>"
              "<th>contours</th><th>glyphs failing</th>";
      for (const Gate& g : options_.report.gates) head += "<th>glyphs failing " + html_escape(to_string(g)) + "</th>";
      head += std::string("<th>") +
              (options_.report.min_severity >= 0 || options_.report.font_severity ? "worst glyphs (largest move that one finding needs; findings)"
                                                 : "worst glyphs (findings)") +
              "</th></tr>";
      for (const FontRow& f : fonts_) {
        head += "<tr><td><a href=\"" + html_escape(f.page) + "\">" + html_escape(f.title) + "</a><br>" +
                glyph_count_text(f.glyphs, f.glyphs_fail, f.contours, f.contours_fail) + "</td><td>" +
                html_escape(f.path) + "</td><td>" + (f.cubic ? "cubic (CFF)" : "quadratic (TrueType)") + "</td><td>" +
                std::to_string(f.glyphs) + "</td><td>" + std::to_string(f.contours) + "</td><td>" +
                std::to_string(f.glyphs_fail) + (f.invalid ? " (" + std::to_string(f.invalid) + " invalid)" : "") +
                "</td>";
        for (int n : f.gate_glyphs) head += "<td>" + std::to_string(n) + "</td>";
        std::string worst;
        for (const FontRow::Worst& w : f.worst) {
          std::string why = std::to_string(w.findings);
          if (w.severity >= 0)
            why = (std::isfinite(w.severity) ? format_number(w.severity, 3) + " units" : std::string("no fix found")) + "; " + why;
          worst += (worst.empty() ? "" : ", ") + html_escape(w.glyph) + " (" + why + ")";
        }
        head += "<td>" + worst + "</td></tr>";
      }
      head += "</table>";
    }
    if (!spline_rows_.empty()) {
      head += "<h2>Splines</h2><table class=\"index\"><tr><th>#</th><th>spline</th><th>file</th><th>status</th>"
              "<th>CMRWI</th><th>CMR</th><th>monotone pieces</th><th>findings</th></tr>";
      page.write(head);
      head.clear();
      for (const std::string& row : spline_rows_) page.write(row);
      head += "</table>";
    }
    page.write(head);
    std::rewind(sections_.get());
    char buf[1 << 16];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, sections_.get())) > 0;) page.write({buf, n});
    page.write("</body></html>\n");
    page.close();
  }

  struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };

  const BatchOptions& options_;
  bool single_font_ = false;
  OutputSet out_;
  StagedStream json_, junit_, sarif_;
  ReportCache old_cache_;
  std::optional<CacheContext> cache_;
  StagedStream cache_file_;
  std::string cache_note_;
  std::unique_ptr<std::FILE, FileCloser> sections_;
  std::optional<BaselineComparison> baseline_;
  std::optional<MarkdownSummary> markdown_;
  BatchSummary summary_;
  std::vector<FontRow> fonts_;
  std::vector<std::string> spline_rows_;
  std::string timestamp_, host_;
  int first_ = 0, file_index_ = 0, sarif_results_ = 0;
  std::optional<FileRecord> part_;  // the parts so far of a file written in parts (PreparedFile::more)
};

}  // namespace

// ------------------------------------------------------------ the run

namespace {

/// One `run_batch`: its files read, reported and handed to the Writer in
/// order, one by one or in parallel runs of small files.
class BatchRun {
 public:
  BatchRun(const std::vector<std::string>& files, const BatchOptions& options, const BatchProgress& progress)
      : files_(files),
        options_(options),
        progress_(progress),
        t0_(std::chrono::steady_clock::now()),
        writer_(options, counted_files(files, options), font_files(files)),
        threads_(thread_count(options.report.threads)),
        root_(options.source_root ? options.source_root->string() : std::string()) {
    budget_.start(options.fix_budget);
  }

  BatchSummary run() {
    // Regions (the fix search) render one spline at a time on the backend,
    // which is not shared between threads: with them, files go one by one.
    const bool regions = options_.report.regions && (options_.report.require || options_.report.gates.empty());
    if (threads_ <= 1 || files_.size() < static_cast<std::size_t>(threads_) || regions) {
      for (std::size_t i = 0; i < files_.size(); ++i) one_by_one(i);
    } else {
      for (std::size_t i = 0; i < files_.size();) {  // runs of small files in parallel, a large SVG alone
        if (in_parts(i)) {
          one_by_one(i++);
          continue;
        }
        std::size_t j = i;
        while (j < files_.size() && !in_parts(j)) ++j;
        in_parallel(i, j);
        i = j;
      }
    }
    BatchSummary summary = writer_.finish(seconds_since_start());
    summary.note = budget_.note();
    return summary;
  }

 private:
  /// A sharded run counts the files it owns (report/merge.hpp).
  static std::size_t counted_files(const std::vector<std::string>& files, const BatchOptions& options) {
    if (!options.shard) return files.size();
    return static_cast<std::size_t>(std::count_if(options.shard_positions.begin(), options.shard_positions.end(),
                                                  [&](std::size_t k) { return options.shard->takes(k); }));
  }
  static std::size_t font_files(const std::vector<std::string>& files) {
    return static_cast<std::size_t>(
        std::count_if(files.begin(), files.end(), [](const std::string& f) { return file_kind(f) == FileKind::font; }));
  }
  double seconds_since_start() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }

  /// The run's time limit, checked before each file and each part of a file.
  void check_time() const {
    if (options_.time_limit <= 0 || seconds_since_start() <= options_.time_limit) return;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", options_.time_limit);
    throw InputFieldError(field("time_limit") + ": the report ran past " + buf + " s with " +
                          std::to_string(done_.load()) + " of " + std::to_string(files_.size()) +
                          " files done; nothing written (raise " + field("time_limit") + ", or report fewer files)");
  }

  /// Each file's name in findings and its SARIF URI (independent of how its path was spelled).
  void name(std::size_t i, FileWork& w) const {
    const std::string base = options_.source_root || i >= options_.bases.size() ? root_ : options_.bases[i];
    w.name = source_name(files_[i], base);
    w.uri = source_uri(files_[i], root_, &w.uri_relative);
  }

  FileWork process(std::size_t i, int file_threads) {
    check_time();
    FileWork w;
    w.path = files_[i];
    name(i, w);
    process_file(w, i, options_, file_threads, &budget_, writer_.cache());
    return w;
  }

  void written(const std::string& path) {
    const int n = ++done_;
    if (progress_) progress_(n, static_cast<int>(files_.size()), writer_.items(), path);
  }

  /// An SVG file is reported and written kStreamChunk paths at a time, so
  /// that memory holds one part's reports, never the whole file's (10^5
  /// paths: docs/outputs.md). False when it cannot be read: process_file
  /// then makes it one invalid item.
  bool stream_svg(std::size_t i) {
    check_time();
    std::vector<import::PathSpline> paths;
    try {
      paths = import::read_svg(files_[i]);
    } catch (const InputError&) {
      return false;
    }
    for (std::size_t begin = 0;; begin += kStreamChunk) {
      check_time();
      const auto t1 = std::chrono::steady_clock::now();
      const std::size_t end = std::min(paths.size(), begin + kStreamChunk);
      FileWork w;
      w.path = files_[i];
      w.kind = FileKind::svg;
      name(i, w);
      std::vector<ReportInput> inputs = svg_inputs(files_[i], paths, begin, end);
      for (ReportInput& in : inputs) in.error = options_.report.show_fields(in.error);
      w.reports = report_batch(std::move(inputs), options_.report, {}, &budget_);
      w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      PreparedFile p = writer_.prepare(std::move(w));
      p.more = end < paths.size();
      writer_.write(p);
      if (!p.more) break;
    }
    written(files_[i]);
    return true;
  }

  /// A file written in parts goes alone (its parts in order, its splines in parallel).
  bool in_parts(std::size_t i) const {
    std::error_code ec;
    return file_kind(files_[i]) == FileKind::svg && fs::file_size(files_[i], ec) > kStreamBytes && !ec;
  }

  /// One file, its splines in parallel.
  void one_by_one(std::size_t i) {
    if (file_kind(files_[i]) == FileKind::svg && stream_svg(i)) return;
    PreparedFile p = writer_.prepare(process(i, options_.report.threads));
    writer_.write(p);
    written(p.rec.path);
  }

  /// Files [first, last) in parallel, one thread each; finished files are
  /// written in order by one thread at a time. A file more than `window`
  /// ahead of the next to write waits, so memory holds at most ~window
  /// files' reports.
  void in_parallel(std::size_t first, std::size_t last) {
    const std::size_t window = 2 * static_cast<std::size_t>(threads_);
    std::mutex m;
    std::condition_variable cv;
    std::map<std::size_t, PreparedFile> ready;
    std::size_t next = first;
    bool abort = false, flushing = false;
    parallel_for(last - first, threads_, [&](std::size_t k) {
      const std::size_t i = first + k;
      PreparedFile w;
      try {
        w = writer_.prepare(process(i, 1));
      } catch (...) {
        const std::lock_guard lock(m);
        abort = true;
        cv.notify_all();
        throw;
      }
      std::unique_lock lock(m);
      cv.wait(lock, [&] { return abort || i < next + window; });
      if (abort) return;
      ready.emplace(i, std::move(w));
      if (flushing) return;  // the writing thread takes it
      flushing = true;
      for (auto it = ready.find(next); it != ready.end(); it = ready.find(next)) {
        PreparedFile item = std::move(it->second);
        ready.erase(it);
        lock.unlock();
        try {
          writer_.write(item);
          written(item.rec.path);
        } catch (...) {
          lock.lock();
          abort = true;
          flushing = false;
          cv.notify_all();
          throw;
        }
        lock.lock();
        ++next;
        cv.notify_all();
      }
      flushing = false;
    });
  }

  const std::vector<std::string>& files_;
  const BatchOptions& options_;
  const BatchProgress& progress_;
  const std::chrono::steady_clock::time_point t0_;
  Writer writer_;
  const int threads_;
  const std::string root_;
  FixBudget budget_;
  std::atomic<int> done_{0};
};

}  // namespace

BatchSummary run_batch(const std::vector<std::string>& files, const BatchOptions& options, const BatchProgress& progress) {
  return BatchRun(files, options, progress).run();
}

}  // namespace cmr::report
