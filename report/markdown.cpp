#include "report/markdown.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "io/output.hpp"
#include "io/ufo.hpp"
#include "report/certified_fix.hpp"
#include "report/font_report.hpp"
#include "report/gates.hpp"
#include "report/severity.hpp"
#include "spline/fields.hpp"

namespace cmr::report {

namespace {

constexpr const char* kClose = "\n</details>\n";
/// Findings listed per failing glyph or spline (the others counted).
constexpr std::size_t kFindingsPerCase = 3;

/// A code span, or escaped text where the text holds a backtick (a file name could).
std::string code(const std::string& text) {
  return text.find('`') == std::string::npos ? "`" + text + "`" : markdown_escape(text);
}

/// "12 failing glyphs" / "1 failing spline".
std::string count_text(int n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::string markdown_escape(const std::string& text) {
  // html_escape: & < > " ' as entities, bytes that are no UTF-8 as U+FFFD.
  const std::string safe = html_escape(text);
  std::string out;
  out.reserve(safe.size());
  for (const char c : safe) {
    switch (c) {
      case '\\': case '`': case '*': case '_': case '[': case ']': case '|': case '~': case '#':
        out += '\\';
        out += c;
        break;
      case '\n': case '\r': case '\t': out += ' '; break;
      default: out += c;
    }
  }
  return out;
}

MarkdownSummary::MarkdownSummary(const ReportOptions& options, std::size_t limit)
    : limit_(std::max(limit, kMarkdownMinLimit)) {
  if (options.require) columns_.push_back(to_string(*options.require));
  for (const Gate& g : options.gates) columns_.push_back(to_string(g));
  others_.column_fail.assign(columns_.size(), 0);
  fix_require_ = fixable_require(options);
  fixable_ = fixable_checks(options);
  show_fields_ = options.show_fields;
  // The whole-font fix leaves the glyphs this run passes: the same severity rule.
  char units[32];
  std::snprintf(units, sizeof units, "%g", options.min_severity);
  if (options.strict || (!options.font_severity && options.min_severity < 0))
    fix_severity_.append(" ").append(show_fields_(field("strict")));
  else if (options.min_severity >= 0 && options.min_severity != kDefaultMinSeverity)
    fix_severity_.append(" ").append(show_fields_(field("min_severity"))).append(" ").append(units);
}

void MarkdownSummary::add_row(Row& row, const FileRecord& file) const {
  ++row.files;
  for (const CaseRecord& c : file.cases) {
    ++row.cases;
    if (!c.error.empty()) ++row.invalid;
    else if (c.pass) ++row.pass;
    else ++row.fail;
    for (std::size_t k = 0; k < columns_.size(); ++k)
      if (std::any_of(c.findings.begin(), c.findings.end(), [&](const Finding& f) { return f.gate == columns_[k]; }))
        ++row.column_fail[k];
  }
}

void MarkdownSummary::add(const FileRecord& file, const std::string& name, const std::string& title) {
  const bool font = file.kind == FileKind::font;
  if (font) {
    Row row;
    row.font = true;
    row.label = code(name) + (title.empty() ? "" : " (" + markdown_escape(title) + ")");
    row.column_fail.assign(columns_.size(), 0);
    add_row(row, file);
    fonts_.push_back(std::move(row));
  } else {
    add_row(others_, file);
  }
  int failing = 0;
  for (const CaseRecord& c : file.cases) failing += (!c.error.empty() || !c.pass) ? 1 : 0;
  if (failing == 0) return;
  failing_ += failing;
  if (kept_bytes_ >= limit_) return;  // counted only: finish could not show it
  std::string title_text = "<code>" + html_escape(name) + "</code>: " +
                      count_text(failing, font ? "failing glyph" : "failing spline",
                                 font ? "failing glyphs" : "failing splines");
  // A font source whose glyphs fail a check some move of points fixes (a
  // finding that fails: not info): the command that writes those fixes into
  // it (cmr fix, docs/fix.md).
  const bool fixable = std::any_of(file.cases.begin(), file.cases.end(), [&](const CaseRecord& c) {
    return c.error.empty() && !c.pass && std::any_of(c.findings.begin(), c.findings.end(), [&](const Finding& f) {
             return !f.info && std::find(fixable_.begin(), fixable_.end(), f.gate) != fixable_.end();
           });
  });
  if (font && fixable && import::is_ufo_path(file.path)) {
    const auto flag = [&](const char* f) { return show_fields_(field(f)); };
    const bool ufo = std::filesystem::path(file.path).extension() != ".glif";
    std::string command = "cmr fix " + shell_word(name);
    if (ufo) command.append(" ").append(flag("glyphs")).append(" all").append(fix_severity_);
    command.append(" ").append(flag("require")).append(" ").append(fix_require_).append(" ").append(flag("in_place"));
    title_text += " &mdash; fix on the grid: <code>" + html_escape(command) + "</code>";
  }
  blocks_.push_back(std::move(title_text));
  kept_bytes_ += blocks_.back().size();
  const int block = static_cast<int>(blocks_.size()) - 1;
  for (const CaseRecord& c : file.cases) {
    if (c.error.empty() && c.pass) continue;
    if (kept_bytes_ >= limit_) break;
    std::string line = "- **" + markdown_escape(c.name) + "**";
    if (!c.error.empty()) {
      line += ": invalid: " + markdown_escape(c.error);
    } else {
      line += " (" + count_text(static_cast<int>(c.findings.size()), "finding", "findings") + ")";
      for (std::size_t i = 0; i < c.findings.size() && i < kFindingsPerCase; ++i) {
        const Finding& f = c.findings[i];
        line += (i == 0 ? ": " : "; ") + code(f.gate) + " " + markdown_escape(f.message);
      }
      if (c.findings.size() > kFindingsPerCase)
        line += "; and " + std::to_string(c.findings.size() - kFindingsPerCase) + " more";
    }
    line += '\n';
    kept_bytes_ += line.size();
    items_.push_back({block, std::move(line)});
  }
}

std::string MarkdownSummary::finish(const BatchSummary& s, const std::string& baseline) const {
  int cases = others_.cases;
  for (const Row& r : fonts_) cases += r.cases;
  std::string out = "## cmr report: ";
  if (s.baseline)
    out += s.new_findings == 0 ? "no new findings" : count_text(s.new_findings, "new finding", "new findings");
  else
    out += failing_ == 0 ? "all pass" : count_text(failing_, "glyph or spline fails", "glyphs and splines fail");
  out += s.exit_code == kExitPass ? " \xE2\x9C\x85\n\n" : " \xE2\x9D\x8C\n\n";  // check mark / cross mark
  out += markdown_escape(summary_line(s)) + ".\n\n";
  if (s.baseline)
    out += "Baseline " + code(baseline) + ": **" + std::to_string(s.new_findings) + " new**, " +
           std::to_string(s.fixed) + " fixed, " + std::to_string(s.unchanged) + " unchanged.\n\n";

  // The "more" line's largest form, reserved before anything optional is added.
  const auto more_line = [](int rows, int lines, int news) {
    std::string t = "\n_Not shown here";
    if (news > 0) t += ": " + count_text(news, "new finding", "new findings");
    if (lines > 0) t += std::string(news > 0 ? ", " : ": ") + count_text(lines, "more failing glyph or spline", "more failing glyphs and splines");
    if (rows > 0) t += std::string(news + lines > 0 ? ", " : ": ") + count_text(rows, "more table row", "more table rows");
    return t + " (every finding is in report.json, index.html, the JUnit and SARIF files)._\n";
  };
  const std::size_t reserve =
      more_line(static_cast<int>(fonts_.size()) + 1, failing_, static_cast<int>(s.new_list.size())).size() +
      std::string(kClose).size();
  const auto fits = [&](std::size_t extra) { return out.size() + extra + reserve < limit_; };

  // The table: one row per font, one for the other files, one for all.
  std::string head = "| file | glyphs / splines | pass | fail | invalid |";
  std::string rule = "|---|---:|---:|---:|---:|";
  for (const std::string& c : columns_) {
    head.append(" `").append(c).append("` |");
    rule += "---:|";
  }
  const auto row_text = [&](const Row& r, const std::string& label) {
    std::string t = "| " + label + " | " + std::to_string(r.cases) + " | " + std::to_string(r.pass) + " | " +
                    std::to_string(r.fail) + " | " + std::to_string(r.invalid) + " |";
    for (int n : r.column_fail) t.append(" ").append(std::to_string(n)).append(" |");
    return t + "\n";
  };
  int rows_left = 0;
  if (fits(head.size() + rule.size() + 2)) {
    out += head + "\n" + rule + "\n";
    std::vector<std::string> rows;
    for (const Row& r : fonts_) rows.push_back(row_text(r, r.label));
    if (others_.files > 0)
      rows.push_back(row_text(others_, count_text(others_.files, "spline or SVG file", "spline and SVG files")));
    Row all;
    all.column_fail.assign(columns_.size(), 0);
    const auto sum = [&](const Row& r) {
      all.files += r.files;
      all.cases += r.cases;
      all.pass += r.pass;
      all.fail += r.fail;
      all.invalid += r.invalid;
      for (std::size_t k = 0; k < columns_.size(); ++k) all.column_fail[k] += r.column_fail[k];
    };
    for (const Row& r : fonts_) sum(r);
    sum(others_);
    const std::string total = rows.size() > 1 ? row_text(all, "**all**") : std::string();
    std::size_t shown = 0;
    for (; shown < rows.size() && fits(rows[shown].size() + total.size()); ++shown) out += rows[shown];
    rows_left = static_cast<int>(rows.size() - shown);
    if (fits(total.size())) out += total;
    out += "\nGate columns: glyphs (splines) failing that gate. " + std::to_string(cases) +
           " glyphs and splines in all.\n\n";
  } else {
    rows_left = static_cast<int>(fonts_.size()) + (others_.files > 0 ? 1 : 0);
  }

  // The new findings, then the failing glyphs and splines, in <details> blocks.
  int news_left = static_cast<int>(s.new_list.size());
  int lines_left = failing_;
  bool stopped = false;
  if (!s.new_list.empty()) {
    const std::string open = "<details open><summary>" + count_text(news_left, "new finding", "new findings") +
                             " since the baseline</summary>\n\n";
    if (fits(open.size())) {
      out += open;
      for (const Finding& f : s.new_list) {
        const std::string line = "- " + code(f.gate) + " " + markdown_escape(f.file) + ": " + markdown_escape(f.message) + "\n";
        if (!fits(line.size())) {
          stopped = true;
          break;
        }
        out += line;
        --news_left;
      }
      out += kClose;
      out += "\n";
    } else {
      stopped = true;
    }
  }
  int open_block = -1;
  for (const Item& item : items_) {
    if (stopped) break;
    std::string add;
    if (item.block != open_block)
      add = std::string(open_block >= 0 ? kClose : "") + "\n<details><summary>" + blocks_[item.block] + "</summary>\n\n";
    add += item.line;
    if (!fits(add.size())) break;
    out += add;
    open_block = item.block;
    --lines_left;
  }
  if (open_block >= 0) out += kClose;
  if (rows_left + lines_left + news_left > 0) out += more_line(rows_left, lines_left, news_left);
  if (out.size() >= limit_) {  // only a heading longer than the limit's minimum (a baseline path of kilobytes)
    std::size_t cut = limit_ - 1;
    while (cut > 0 && (static_cast<unsigned char>(out[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
    out.resize(cut);
  }
  return out;
}

}  // namespace cmr::report
