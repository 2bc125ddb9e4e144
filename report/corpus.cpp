#include "report/corpus.hpp"

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
#include "report/sarif.hpp"
#include "spline/format.hpp"
#include "report/batch.hpp"
#include "report/severity.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"

namespace cmr::report {
namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// ------------------------------------------------------------ finding files

namespace {

bool has_glob(const std::string& s) { return s.find_first_of("*?[") != std::string::npos; }

bool match(const std::string& pattern, const std::string& rel, const std::string& name) {
  std::string p;  // ** is * (which crosses '/' without FNM_PATHNAME)
  for (const char c : pattern)
    if (c != '*' || p.empty() || p.back() != '*') p.push_back(c);
  return ::fnmatch(p.c_str(), rel.c_str(), 0) == 0 || ::fnmatch(p.c_str(), name.c_str(), 0) == 0;
}

bool wanted(const fs::path& file, const std::string& rel, const FileFilter& f) {
  const std::string name = file.filename().string();
  if (f.include.empty()) {
    const FileKind k = file_kind(file.string());
    const std::string ext = file.extension().string();
    if (k == FileKind::spline && ext != ".json" && ext != ".JSON") return false;
    if (import::is_designspace_path(file)) return false;  // a folder's UFOs are its masters, walked as such
  } else if (std::none_of(f.include.begin(), f.include.end(), [&](const std::string& p) { return match(p, rel, name); })) {
    return false;
  }
  return std::none_of(f.exclude.begin(), f.exclude.end(), [&](const std::string& p) { return match(p, rel, name); });
}

/// What a walked .json file is, from its top-level keys (a SAX pass that
/// stops at the first key that decides): "" for a spline file (it has
/// "points"; also a file that does not parse: that is reported as invalid),
/// else why it is skipped.
std::string json_not_a_spline(const fs::path& file) {
  struct Keys : nlohmann::json_sax<nlohmann::json> {
    int depth = 0;
    std::string verdict = "not a spline file (no \"points\")";
    bool key(string_t& k) override {
      if (depth != 1) return true;
      if (k == "points") verdict.clear();
      else if (k == "schema") verdict = "a cmr output (report.json of an earlier run)";
      else if (k == "$schema") verdict = "a SARIF or other schema'd JSON, not a spline file";
      else return true;
      return false;  // decided: stop reading
    }
    bool start_object(std::size_t) override { return ++depth, true; }
    bool end_object() override { return --depth, true; }
    bool start_array(std::size_t) override { return ++depth, true; }
    bool end_array() override { return --depth, true; }
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
      verdict.clear();  // not JSON: the report says why, as for any broken spline file
      return false;
    }
  } keys;
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  const int first = in.peek();
  if (first == std::char_traits<char>::eof()) return {};
  try {
    nlohmann::json::sax_parse(in, &keys);
  } catch (const std::exception&) {
    return {};
  }
  return keys.verdict;
}

/// Why a walk does not take the entry `p` of kind `st` ("" when it is not
/// a special file).
std::string special_kind(const fs::file_status& st) {
  switch (st.type()) {
    case fs::file_type::fifo: return "a FIFO (not read: it could block)";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::block: return "a block device";
    case fs::file_type::character: return "a character device";
    default: return "not a regular file";
  }
}

void walk(const fs::path& folder, const FileFilter& filter, std::vector<std::string>& out,
          std::vector<SkippedPath>* skipped, const std::vector<fs::path>& skip_folders) {
  std::vector<std::string> found;
  std::vector<SkippedPath> left;
  const auto skip = [&](const fs::path& p, std::string reason) { left.push_back({p.string(), std::move(reason)}); };
  std::vector<std::pair<dev_t, ino_t>> never;  // skip_folders, by identity
  for (const fs::path& f : skip_folders) {
    struct stat st {};
    if (::stat(f.c_str(), &st) == 0) never.emplace_back(st.st_dev, st.st_ino);
  }
  std::error_code ec;
  fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
  if (ec) throw InputError(folder.string() + ": " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw InputError(folder.string() + ": " + ec.message());
    const std::string name = it->path().filename().string();
    if (!name.empty() && name[0] == '.') {  // hidden: skipped, folders with all they hold
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    const fs::path& p = it->path();
    if (it->is_symlink(ec)) {  // links to files are taken; the rest is said
      std::error_code lec;
      const fs::file_status target = fs::status(p, lec);
      if (lec) {
        skip(p, lec.value() == ELOOP ? "a symbolic link loop" : lec.value() == ENOENT ? "a symbolic link to nothing"
                                                                                      : "a symbolic link: " + lec.message());
        continue;
      }
      if (fs::is_directory(target)) {
        skip(p, "a symbolic link to a folder (not followed)");
        continue;
      }
    } else if (it->is_directory(ec)) {
      if (import::is_ufo_path(p)) {  // a UFO is one input, its .glif files its glyphs
        it.disable_recursion_pending();
        if (wanted(p, p.lexically_relative(folder).generic_string(), filter)) found.push_back(p.string());
        continue;
      }
      struct stat st {};
      if (::stat(p.c_str(), &st) == 0 &&
          std::find(never.begin(), never.end(), std::make_pair(st.st_dev, st.st_ino)) != never.end()) {
        skip(p, "the run's own output folder (--out)");
        it.disable_recursion_pending();
        continue;
      }
      if (DIR* d = ::opendir(p.c_str())) {
        ::closedir(d);
      } else {
        skip(p, std::string("an unreadable folder: ") + std::strerror(errno));
        it.disable_recursion_pending();
      }
      continue;
    }
    const fs::file_status st = it->status(ec);
    if (!fs::is_regular_file(st)) {
      skip(p, special_kind(st));
      continue;
    }
    const std::string rel = p.lexically_relative(folder).generic_string();
    if (!wanted(p, rel, filter)) continue;
    const std::string ext = p.extension().string();
    if (file_kind(p.string()) == FileKind::spline && (ext == ".json" || ext == ".JSON")) {
      std::string why = json_not_a_spline(p);
      if (!why.empty()) {
        skip(p, std::move(why));
        continue;
      }
    }
    found.push_back(p.string());
  }
  std::sort(found.begin(), found.end());
  out.insert(out.end(), found.begin(), found.end());
  std::sort(left.begin(), left.end(), [](const SkippedPath& a, const SkippedPath& b) { return a.path < b.path; });
  if (skipped != nullptr) skipped->insert(skipped->end(), left.begin(), left.end());
}

}  // namespace

FileKind file_kind(const std::string& path) {
  if (import::is_font_path(path) || import::is_source_path(path)) return FileKind::font;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".svg" ? FileKind::svg : FileKind::spline;
}

std::vector<std::string> collect_files(const std::vector<std::string>& args, const FileFilter& filter,
                                       std::vector<std::string>* bases, std::vector<SkippedPath>* skipped,
                                       const std::vector<fs::path>& skip_folders) {
  std::vector<std::string> out;
  for (const std::string& a : args) {
    std::error_code ec;
    const auto st = fs::status(a, ec);
    if (import::is_designspace_path(a) && fs::exists(st)) {  // its sources (masters), each a font
      for (const import::Designspace::Source& src : import::read_designspace(a).sources) out.push_back(src.path.string());
      if (bases) bases->resize(out.size(), "");  // named relative to the working folder (a later folder must not claim them)
      continue;
    }
    if (fs::is_directory(st) && !import::is_ufo_path(a)) {
      const std::size_t before = out.size();
      walk(a, filter, out, skipped, skip_folders);
      if (out.size() == before) throw InputError(a + ": no font, SVG or spline file in this folder (with --include/--exclude)");
      if (bases) bases->resize(out.size(), a);
      continue;
    }
    if (fs::exists(st) || !has_glob(a)) {
      out.push_back(a);  // a file, or a name that is not there: reported as an invalid input
      if (bases) bases->resize(out.size(), "");
      continue;
    }
    glob_t g{};
    const int rc = ::glob(a.c_str(), 0, nullptr, &g);
    std::vector<std::string> matched;
    if (rc == 0)
      for (std::size_t i = 0; i < g.gl_pathc; ++i) matched.emplace_back(g.gl_pathv[i]);
    ::globfree(&g);
    const std::size_t before = out.size();
    for (const std::string& m : matched) {
      if (fs::is_directory(m, ec)) walk(m, filter, out, skipped, skip_folders);
      else if (wanted(m, fs::path(m).filename().string(), filter)) out.push_back(m);
      if (bases) bases->resize(out.size(), fs::is_directory(m, ec) ? m : "");
    }
    if (out.size() == before) throw InputError(a + ": matches no file");
  }
  return out;
}

// ------------------------------------------------------------ names

namespace {

/// `p` absolute and normal, its folder's symbolic links resolved (not its
/// own: a font that is a link keeps its name).
fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p.empty() ? fs::path(".") : p, ec).lexically_normal();
  if (ec) return p;
  if (!a.has_filename()) a = a.parent_path();  // "in/" names the folder in
  fs::path folder = fs::weakly_canonical(a.parent_path(), ec);
  if (ec) folder = a.parent_path();
  return (folder / a.filename()).lexically_normal();
}

fs::path resolved_folder(const std::string& folder) {
  std::error_code ec;
  fs::path a = fs::weakly_canonical(fs::absolute(folder.empty() ? fs::path(".") : fs::path(folder), ec), ec);
  return ec ? fs::absolute(folder.empty() ? fs::path(".") : fs::path(folder)).lexically_normal() : a;
}

}  // namespace

std::string source_name(const std::string& file, const std::string& base) {
  const fs::path rel = resolved(file).lexically_relative(resolved_folder(base));
  return rel.empty() ? file : rel.generic_string();
}

std::string source_uri(const std::string& file, const std::string& root, bool* relative) {
  const fs::path abs = resolved(file);
  const fs::path rel = abs.lexically_relative(resolved_folder(root));
  const bool inside = !rel.empty() && *rel.begin() != "..";
  if (relative) *relative = inside;
  return path_uri(inside ? rel.generic_string() : abs.generic_string());
}

std::string source_uri_base(const std::string& root) {
  std::string uri = path_uri(resolved_folder(root).generic_string());  // "file:///abs/root"
  if (uri.back() != '/') uri += '/';
  return uri;
}

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

// ------------------------------------------------------------ one file

namespace {

/// A file's reports while they are written (then dropped).
struct FileWork {
  std::string path;
  std::string name;  ///< its findings' file name (source_name)
  std::string uri;   ///< its SARIF artifact URI (source_uri)
  bool uri_relative = false;
  FileKind kind = FileKind::spline;
  std::optional<FontInfo> font;
  std::vector<SplineReport> reports;
  double seconds = 0;
};

/// The report inputs of an SVG file's paths [begin, end): one spline each,
/// named FILE:PATH; a path that is no spline is that input's error.
std::vector<ReportInput> svg_inputs(const std::string& path, const std::vector<import::PathSpline>& paths,
                                    std::size_t begin, std::size_t end) {
  std::vector<ReportInput> inputs;
  for (std::size_t i = begin; i < end; ++i) {
    const import::PathSpline& p = paths[i];
    ReportInput in;
    in.file = path + ":" + p.name;
    try {
      in.spline = import::to_bspline(p);
    } catch (const InputError& e) {
      in.error = in.file + ": " + e.what();  // as the subpath is named
    }
    inputs.push_back(std::move(in));
  }
  return inputs;
}

FileWork process_file(const std::string& path, std::size_t index, const BatchOptions& options, int threads,
                      FixBudget* budget) {
  const auto t0 = std::chrono::steady_clock::now();
  FileWork w;
  w.path = path;
  w.kind = file_kind(path);
  ReportOptions o = options.report;
  o.threads = threads;
  std::vector<ReportInput> inputs;
  try {
    switch (w.kind) {
      case FileKind::font:
        if (std::any_of(o.gates.begin(), o.gates.end(), is_interpolation_gate)) {
          // The masters and the pieces between them (report/interpolation.hpp).
          w.font = interpolation_inputs(path, {options.all_glyphs, options.codepoints, {}}, options.between, inputs);
          o.certified_fixes = options.fixes;
          break;
        }
        {
          import::Font font = import::is_ufo_path(path)
                                  ? import::read_ufo(path, {options.all_glyphs, options.codepoints, {}})
                                  : import::read_font(path, options.codepoints, options.location);
          if (options.shard) keep_shard_glyphs(*options.shard, options.shard_positions.at(index), font.glyphs);
          w.font = font_inputs(font, inputs);
        }
        o.certified_fixes = options.fixes;
        if (o.font_severity && o.min_severity < 0) o.min_severity = kDefaultMinSeverity;
        break;
      case FileKind::svg: {
        const std::vector<import::PathSpline> paths = import::read_svg(path);
        inputs = svg_inputs(path, paths, 0, paths.size());
        break;
      }
      case FileKind::spline: inputs.push_back(read_input(path)); break;
    }
  } catch (const InputError& e) {  // the whole file is unreadable: one invalid item
    inputs.clear();
    w.font.reset();
    if (options.shard && !options.shard->takes(options.shard_positions.at(index))) return w;  // its owner part says it
    ReportInput in;
    in.file = path;
    in.error = e.what();
    inputs.push_back(std::move(in));
  }
  w.reports = report_batch(std::move(inputs), o, {}, budget);
  w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return w;
}

/// "O/c0/p3" -> "p3".
std::string node_of(const std::string& name) {
  const std::size_t slash = name.rfind('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

struct ItemNames {
  std::string glyph;
  int contour = 0;
  const std::vector<std::string>* joints = nullptr;  ///< font: node starting each segment
  const std::vector<std::string>* points = nullptr;  ///< font: each control point's name
  const std::string* source = nullptr;                ///< font source: the glyph's .glif
  const std::vector<int>* point_lines = nullptr;      ///< font source: each control point's <point> line
  const std::vector<int>* joint_lines = nullptr;      ///< font source: each segment's starting node's line
};

std::vector<Finding> findings_of(const SplineReport& r, const std::string& file, const ItemNames& n,
                                 const ReportOptions& options) {
  std::vector<Finding> out;
  if (!r.error.empty()) return out;
  if (options.require && !r.requirement_pass) {
    Finding f{file, n.glyph, n.contour, "", to_string(*options.require), "", "", 0, -1, false, ""};
    f.message = n.glyph + ": fails the " + f.gate + " check";
    if (!options.require->split)
      f.message += std::string(" (verdict ") + to_string(options.require->mode == Mode::cmrwi ? r.analysis.cmrwi : r.analysis.cmr) + ")";
    if (n.source && !n.source->empty()) {  // the contour: its first node's line
      f.source = *n.source;
      f.line = n.joint_lines && !n.joint_lines->empty() ? n.joint_lines->front() : 0;
    }
    out.push_back(std::move(f));
  }
  const int N = r.spline ? r.spline->segment_count() : 0;
  for (const GateResult& g : r.gates)
    for (const GateViolation& v : g.violations) {
      Finding f{file, n.glyph, n.contour, "", to_string(g.gate), "", "", 0, v.severity, v.info,
                severity_note(v.severity_outcome)};
      std::string where;
      if (n.joints && N > 0 && static_cast<int>(n.joints->size()) == N) {
        if (v.segment >= 0) {
          f.node = node_of((*n.joints)[v.segment]) + "-" + node_of((*n.joints)[(v.segment + 1) % N]);
          where = "between nodes " + f.node;
        } else if (v.joint >= 0) {
          f.node = node_of((*n.joints)[v.joint % N]);
          where = "at " + f.node;
        }
      } else if (v.segment >= 0) {
        f.node = "segment " + std::to_string(v.segment);
      } else if (v.joint >= 0) {
        f.node = "joint " + std::to_string(v.joint);
      }
      const std::string prefix = n.points ? n.glyph + "/c" + std::to_string(n.contour) : n.glyph;
      f.message = prefix + (where.empty() ? "" : " " + where) + ": " + v.message;
      if (n.source && !n.source->empty()) {
        f.source = *n.source;
        auto at = [](const std::vector<int>* lines, int k) {
          return lines && k >= 0 && k < static_cast<int>(lines->size()) ? (*lines)[k] : 0;
        };
        f.line = !v.handles.empty() ? at(n.point_lines, v.handles.front())
                 : v.segment >= 0   ? at(n.joint_lines, v.segment)
                 : v.joint >= 0 && N > 0 ? at(n.joint_lines, v.joint % N)
                                         : 0;
      }
      if (n.points && !v.handles.empty()) {
        std::string names;
        for (int h : v.handles)
          if (h >= 0 && h < static_cast<int>(n.points->size()))
            names += (names.empty() ? "" : ", ") + node_of((*n.points)[h]);
        f.message += " (the font's " + names + ")";
      }
      out.push_back(std::move(f));
    }
  return out;
}

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
    sections_.reset(std::tmpfile());
    if (!sections_) throw EnvironmentError("a temporary file for the page: cannot be created");
    if (options.markdown) markdown_.emplace(options.report, options.markdown_limit);
    if (options.baseline) {
      baseline_.emplace(read_baseline(*options.baseline));
      summary_.baseline = true;
    }
    summary_.files = static_cast<int>(files);
    Json settings = report_json({}, options.report)["settings"];
    json_.write("{\"schema\":\"" + std::string(kSchema) + "\",\"settings\":" + dump(settings) + ",\"splines\":[");
    if (junit_.is_open()) junit_.write(junit_header());
    if (sarif_.is_open())
      sarif_.write(sarif_header(options.report, source_uri_base(options.source_root ? options.source_root->string() : "")));
    timestamp_ = now_iso8601();
    host_ = host_name();
  }

  int items() const { return summary_.items; }

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
    // The file's spline objects as text (report/json_stream.hpp: the same bytes
    // as the tree), each with the id "s0"; write puts in the run's numbers.
    std::vector<std::vector<Finding>> item_findings(w.reports.size());
    for (std::size_t i = 0; i < w.reports.size(); ++i) {
      const SplineReport& r = w.reports[i];
      if (!w.font) names[i] = {r.name, 0, nullptr, nullptr};
      if (w.font && names[i].glyph.empty()) names[i].glyph = r.name;  // an unreadable font: its one invalid item
      item_findings[i] = findings_of(r, w.name, names[i], options_.report);
      SplineJsonExtras extras;
      extras.source = &w.path;
      extras.glyph = names[i].glyph;
      extras.contour = names[i].contour;
      extras.point_names = names[i].points;
      extras.findings = &item_findings[i];
      const std::size_t begin = p.json.size();
      JsonStream stream(p.json, options_.pretty ? 2 : -1);
      write_spline_json(stream, r, 0, extras);
      const std::size_t id = p.json.find("\"s0\"", begin);  // the first member is the id
      if (id == std::string::npos) throw std::logic_error("report.json: a spline object without its id");
      p.objects.push_back({begin, id + 2});
      ++rec.items;
      (!r.error.empty() ? rec.items_invalid : (r.pass ? rec.items_pass : rec.items_fail))++;
      if (!r.error.empty()) p.invalid_messages.push_back(r.error);
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
          const SplineReport& r = w.reports[i];
          if (!r.error.empty()) c.error += (c.error.empty() ? "" : "; ") + r.error;
          c.pass = c.pass && r.error.empty() && r.pass;
          for (std::size_t k = 0; k < r.gates.size() && k < gate_fail.size(); ++k)
            gate_fail[k] = gate_fail[k] || !r.gates[k].pass();
          for (Finding& f : item_findings[i]) c.findings.push_back(std::move(f));
        }
        ++row.glyphs;
        row.contours += c.contours;
        for (std::size_t i : g.items) row.contours_fail += w.reports[i].error.empty() && w.reports[i].pass ? 0 : 1;
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
      if (w.font->glyphs.empty() && !w.reports.empty() && !w.reports[0].error.empty()) {
        CaseRecord c;  // an unreadable font
        c.name = fs::path(w.path).filename().string();
        c.error = w.reports[0].error;
        c.pass = false;
        rec.cases.push_back(std::move(c));
        row.invalid = 1;
      }
      p.font_page = font_report_html({*w.font}, w.reports, options_.report);
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
    for (const SkippedPath& k : options_.skipped) skipped.push_back({{"path", k.path}, {"reason", k.reason}});
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
        head += "<li>" + html_escape(k.path) + ": " + html_escape(k.reason) + "</li>";
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

BatchSummary run_batch(const std::vector<std::string>& files, const BatchOptions& options, const BatchProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t fonts =
      static_cast<std::size_t>(std::count_if(files.begin(), files.end(), [](const std::string& f) { return file_kind(f) == FileKind::font; }));
  std::size_t counted = files.size();  // a sharded run counts the files it owns (report/merge.hpp)
  if (options.shard)
    counted = static_cast<std::size_t>(std::count_if(options.shard_positions.begin(), options.shard_positions.end(),
                                                     [&](std::size_t k) { return options.shard->takes(k); }));
  Writer writer(options, counted, fonts);
  const int threads = thread_count(options.report.threads);
  FixBudget budget;
  budget.start(options.fix_budget);
  std::atomic<int> done{0};
  // The run's time limit, checked before each file and each part of a file.
  const auto check_time = [&] {
    if (options.time_limit <= 0 ||
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() <= options.time_limit)
      return;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", options.time_limit);
    throw InputError(std::string("--time-limit: the report ran past ") + buf + " s with " + std::to_string(done.load()) +
                     " of " + std::to_string(files.size()) + " files done; nothing written (raise --time-limit, or "
                     "report fewer files)");
  };
  // Each file's name in findings and its SARIF URI (independent of how its path was spelled).
  const std::string root = options.source_root ? options.source_root->string() : std::string();
  const auto named = [&](std::size_t i, FileWork& w) {
    const std::string base = options.source_root || i >= options.bases.size() ? root : options.bases[i];
    w.name = source_name(files[i], base);
    w.uri = source_uri(files[i], root, &w.uri_relative);
  };
  const auto process = [&](std::size_t i, int file_threads) {
    check_time();
    FileWork w = process_file(files[i], i, options, file_threads, &budget);
    named(i, w);
    return w;
  };
  auto written = [&](const std::string& path) {
    const int n = ++done;
    if (progress) progress(n, static_cast<int>(files.size()), writer.items(), path);
  };
  // An SVG file is reported and written kStreamChunk paths at a time, so
  // that memory holds one part's reports, never the whole file's (10^5
  // paths: docs/outputs.md). False when it cannot be read: process_file
  // then makes it one invalid item.
  const auto stream_svg = [&](std::size_t i) {
    check_time();
    std::vector<import::PathSpline> paths;
    try {
      paths = import::read_svg(files[i]);
    } catch (const InputError&) {
      return false;
    }
    for (std::size_t begin = 0;; begin += kStreamChunk) {
      check_time();
      const auto t1 = std::chrono::steady_clock::now();
      const std::size_t end = std::min(paths.size(), begin + kStreamChunk);
      FileWork w;
      w.path = files[i];
      w.kind = FileKind::svg;
      named(i, w);
      w.reports = report_batch(svg_inputs(files[i], paths, begin, end), options.report, {}, &budget);
      w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      PreparedFile p = writer.prepare(std::move(w));
      p.more = end < paths.size();
      writer.write(p);
      if (!p.more) break;
    }
    written(files[i]);
    return true;
  };
  // A file written in parts goes alone (its parts in order, its splines in parallel).
  const auto in_parts = [&](std::size_t i) {
    std::error_code ec;
    return file_kind(files[i]) == FileKind::svg && fs::file_size(files[i], ec) > kStreamBytes && !ec;
  };
  const auto one_by_one = [&](std::size_t i) {  // one file, its splines in parallel
    if (file_kind(files[i]) == FileKind::svg && stream_svg(i)) return;
    PreparedFile p = writer.prepare(process(i, options.report.threads));
    writer.write(p);
    written(p.rec.path);
  };
  // Files [first, last) in parallel, one thread each; finished files are
  // written in order by one thread at a time. A file more than `window`
  // ahead of the next to write waits, so memory holds at most ~window
  // files' reports.
  const auto in_parallel = [&](std::size_t first, std::size_t last) {
    const std::size_t window = 2 * static_cast<std::size_t>(threads);
    std::mutex m;
    std::condition_variable cv;
    std::map<std::size_t, PreparedFile> ready;
    std::size_t next = first;
    bool abort = false, flushing = false;
    parallel_for(last - first, threads, [&](std::size_t k) {
      const std::size_t i = first + k;
      PreparedFile w;
      try {
        w = writer.prepare(process(i, 1));
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
          writer.write(item);
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
  };
  // Regions (the fix search) render one spline at a time on the backend,
  // which is not shared between threads: with them, files go one by one.
  const bool regions = options.report.regions && (options.report.require || options.report.gates.empty());
  if (threads <= 1 || files.size() < static_cast<std::size_t>(threads) || regions) {
    for (std::size_t i = 0; i < files.size(); ++i) one_by_one(i);
  } else {
    for (std::size_t i = 0; i < files.size();) {  // runs of small files in parallel, a large SVG alone
      if (in_parts(i)) {
        one_by_one(i++);
        continue;
      }
      std::size_t j = i;
      while (j < files.size() && !in_parts(j)) ++j;
      in_parallel(i, j);
      i = j;
    }
  }
  BatchSummary summary = writer.finish(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  summary.note = budget.note();
  return summary;
}

}  // namespace cmr::report
