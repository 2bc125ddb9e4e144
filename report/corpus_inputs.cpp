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
#include "report/sarif.hpp"
#include "spline/fields.hpp"
#include "spline/format.hpp"
#include "report/batch.hpp"
#include "report/severity.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"

// The inputs of a corpus run (corpus.hpp): finding the files (collect_files,
// file_kind), naming them (source_name, source_uri), and one file's reports
// and findings (process_file, findings_of). The run itself is in corpus.cpp.

namespace cmr::report {

namespace fs = std::filesystem;

using namespace corpus_detail;  // what the parts share (corpus_detail.hpp)

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
        skip(p, "the run's own output folder (" + field("out") + ")");
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

std::vector<std::string> collect_run_files(const std::vector<std::string>& args, const FileFilter& filter,
                                           bool whole_designspaces, std::vector<std::string>* bases,
                                           std::vector<SkippedPath>* skipped, const std::vector<fs::path>& skip_folders) {
  if (!whole_designspaces) return collect_files(args, filter, bases, skipped, skip_folders);
  std::vector<std::string> walked, whole, files;
  for (const std::string& f : args) (import::is_designspace_path(f) ? whole : walked).push_back(f);
  if (!walked.empty()) files = collect_files(walked, filter, bases, skipped, skip_folders);
  for (const std::string& f : whole) {
    files.push_back(f);
    if (bases) bases->push_back("");
  }
  return files;
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
      if (out.size() == before)
        throw InputFieldError(a + ": no font, SVG or spline file in this folder (with " + field("include") + "/" +
                              field("exclude") + ")");
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

// ------------------------------------------------------------ one file

namespace corpus_detail {

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
      in.error = in.file + ": " + marked_text(e);  // as the subpath is named
    }
    inputs.push_back(std::move(in));
  }
  return inputs;
}

/// Whether a font's report items are its glyphs' contours in order (every
/// item in one glyph, glyph after glyph): what the cache's keys assume.
bool items_in_glyph_order(const FontInfo& font, std::size_t items) {
  std::size_t next = 0;
  for (const auto& g : font.glyphs)
    for (std::size_t i : g.items)
      if (i != next++) return false;
  return next == items;
}

/// Processes w.path (w.name and w.uri set) into `w`.
void process_file(FileWork& w, std::size_t index, const BatchOptions& options, int threads, FixBudget* budget,
                  const CacheContext* cache) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string& path = w.path;
  w.kind = file_kind(path);
  ReportOptions o = options.report;
  o.threads = threads;
  std::vector<ReportInput> inputs;
  try {
    switch (w.kind) {
      case FileKind::font:
        if (std::any_of(o.gates.begin(), o.gates.end(), is_interpolation_gate)) {
          // The masters and the pieces between them (report/interpolation.hpp).
          w.font = interpolation_inputs(path, {options.all_glyphs, options.codepoints, {}}, options.between, inputs,
                                        options.shard, options.shard ? options.shard_positions.at(index) : 0);
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
    if (options.shard && !options.shard->takes(options.shard_positions.at(index))) return;  // its owner part says it
    ReportInput in;
    in.file = path;
    in.error = marked_text(e);
    inputs.push_back(std::move(in));
  }
  for (ReportInput& in : inputs)
    in.error = o.show_fields(in.error);  // the fields its message names, as the run names them
  // A font's glyphs found in the resume cache are not judged: their items
  // stay empty reports; the others are judged together, as without a cache.
  if (cache && w.font && items_in_glyph_order(*w.font, inputs.size())) {
    const std::string prefix = file_key_prefix(cache->run_prefix, w.path, w.name, w.uri, w.uri_relative, *w.font);
    std::vector<bool> skip(inputs.size(), false);
    for (const auto& g : w.font->glyphs) {
      w.keys.push_back(glyph_key(prefix, g, inputs));
      w.cached.push_back(cache->old ? cache->old->find(w.keys.back()) : std::nullopt);
      if (w.cached.back())
        for (std::size_t i : g.items) skip[i] = true;
    }
    std::vector<ReportInput> judged;
    std::vector<std::size_t> where;
    for (std::size_t i = 0; i < inputs.size(); ++i)
      if (!skip[i]) judged.push_back(std::move(inputs[i])), where.push_back(i);
    std::vector<SplineReport> reports = report_batch(std::move(judged), o, {}, budget);
    w.reports.resize(inputs.size());
    for (std::size_t k = 0; k < where.size(); ++k) w.reports[where[k]] = std::move(reports[k]);
    // A failing glyph judged once the fix budget was spent may lack its
    // fixes: it is not kept.
    w.store = true;
    w.store_failing = !o.regions || budget == nullptr || (budget->skipped.load() == 0 && !budget->spent());
  } else {
    w.reports = report_batch(std::move(inputs), o, {}, budget);
  }
  w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace corpus_detail

namespace {

/// "O/c0/p3" -> "p3".
std::string node_of(const std::string& name) {
  const std::size_t slash = name.rfind('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

}  // namespace

namespace corpus_detail {

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

}  // namespace corpus_detail

}  // namespace cmr::report
