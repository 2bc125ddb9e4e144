#include "spline/spline_json.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <new>
#include <optional>

#include <nlohmann/json.hpp>

#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/limits.hpp"
#include "spline/space.hpp"

namespace cmr {
namespace {

using nlohmann::json;

double number(const json& v, const std::string& where) {
  if (!v.is_number()) throw InputError(where + " is not a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw InputError(where + " is not a finite number");
  return x;
}

/// Drops the two end knots of a conventional knot vector (options.conventional),
/// or refuses a conventional vector read as polar form, naming the counts.
void apply_knot_convention(std::vector<double>& knots, std::size_t points, int degree, const ReadOptions& options) {
  const std::size_t polar = points + static_cast<std::size_t>(degree) - 1, full = polar + 2;
  const std::string counts = std::to_string(points) + " points of degree " + std::to_string(degree);
  if (options.conventional) {
    if (knots.size() != full)
      throw InputFieldError("knots: " + field("conventional") +
                            " expects the full vector of points + degree + 1 = " + std::to_string(full) +
                            " values for " + counts + " (got " + std::to_string(knots.size()) + ")");
    knots.erase(knots.begin());
    knots.pop_back();
  } else if (knots.size() == full && points > 0) {
    throw InputFieldError("knots: " + std::to_string(knots.size()) +
                          " values is the conventional (full) knot vector for " + counts +
                          "; drop the first and the last knot (cmr uses polar form), or convert the file with "
                          "`cmr knots FILE " +
                          field("conventional") + " clamp` (any knots operation takes " + field("conventional") + ")");
  }
}

}  // namespace

BSpline spline_from_json(const json& doc, const ReadOptions& options) {
  if (!doc.is_object()) throw InputError("the document is not a JSON object with \"points\"");
  for (const auto& [key, value] : doc.items()) {
    (void)value;
    if (key != "degree" && key != "knots" && key != "points" && key != "name" && key != "weights" && key != "closed" &&
        key != "point_names")
      throw InputError("unknown field \"" + key + "\" (expected degree, knots, points, name, weights, closed, point_names)");
  }
  if (!doc.contains("points")) throw InputError("points: missing");
  const json& pts = doc["points"];
  if (!pts.is_array()) throw InputError("points: not an array of [x, y] pairs");
  std::vector<Vec2> points;
  points.reserve(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "]";
    if (!pts[i].is_array() || pts[i].size() != 2) {
      if (pts[i].is_array() && pts[i].size() == 3) spline_dimension(doc);  // mixed [x, y] and [x, y, z]: that says so
      throw InputError(where + " is not an [x, y] pair");
    }
    points.emplace_back(number(pts[i][0], where + "[0]"), number(pts[i][1], where + "[1]"));
  }
  std::vector<double> weights;
  if (doc.contains("weights")) {
    const json& ws = doc["weights"];
    if (!ws.is_array()) throw InputError("weights: not an array of numbers");
    for (std::size_t i = 0; i < ws.size(); ++i) weights.push_back(number(ws[i], "weights[" + std::to_string(i) + "]"));
  }  // count and sign: BSpline::make
  std::string name;
  if (doc.contains("name")) {
    if (!doc["name"].is_string()) throw InputError("name: not a string");
    name = doc["name"].get<std::string>();
  }
  if (doc.contains("point_names")) {  // informational (importers' node names); checked, not kept
    const json& names = doc["point_names"];
    if (!names.is_array() || names.size() != pts.size())
      throw InputError("point_names: not an array of one string per point");
    for (std::size_t i = 0; i < names.size(); ++i)
      if (!names[i].is_string()) throw InputError("point_names[" + std::to_string(i) + "] is not a string");
  }
  bool closed = false;
  if (doc.contains("closed")) {
    if (!doc["closed"].is_boolean()) throw InputError("closed: not true or false");
    closed = doc["closed"].get<bool>();
  }
  int degree = -1;
  if (doc.contains("degree")) {
    const json& d = doc["degree"];
    if (!d.is_number_integer()) throw InputError("degree: not an integer");
    const auto v = d.get<long long>();
    if (v < 2 || v > kMaxDegree)
      throw InputError("degree: must be between 2 and " + std::to_string(kMaxDegree) + " (got " + std::to_string(v) + ")");
    degree = static_cast<int>(v);
  }
  if (closed) {
    if (degree < 0) throw InputError("degree: missing (required for a closed spline)");
    std::vector<double> knots;
    if (doc.contains("knots")) {
      const json& ks = doc["knots"];
      if (!ks.is_array()) throw InputError("knots: not an array of numbers");
      for (std::size_t i = 0; i < ks.size(); ++i) knots.push_back(number(ks[i], "knots[" + std::to_string(i) + "]"));
    } else {
      for (std::size_t i = 0; i <= points.size(); ++i) knots.push_back(static_cast<double>(i));  // uniform
    }
    return BSpline::make_closed(degree, std::move(knots), std::move(points), std::move(name), std::move(weights));
  }
  if (!doc.contains("knots")) {
    const int n = static_cast<int>(points.size()) - 1;
    if (degree >= 0 && degree != n)
      throw InputError("degree: a Bezier curve (no \"knots\") with " + std::to_string(points.size()) +
                       " points has degree " + std::to_string(n) + ", not " + std::to_string(degree));
    return BSpline::bezier(std::move(points), std::move(name), std::move(weights));
  }
  if (degree < 0) throw InputError("degree: missing (required when \"knots\" is given)");
  const json& ks = doc["knots"];
  if (!ks.is_array()) throw InputError("knots: not an array of numbers");
  std::vector<double> knots;
  knots.reserve(ks.size());
  for (std::size_t i = 0; i < ks.size(); ++i) knots.push_back(number(ks[i], "knots[" + std::to_string(i) + "]"));
  apply_knot_convention(knots, points.size(), degree, options);
  return BSpline::make(degree, std::move(knots), std::move(points), std::move(name), std::move(weights));
}

namespace {

std::atomic<bool> g_stdin_closed{false};

/// Reads `fd` (a pipe, a FIFO, a socket, a character device such as
/// /dev/null) to its end, at most kMaxInputBytes. A descriptor in
/// non-blocking mode (a FIFO opened with O_NONBLOCK, or a standard input
/// left so) is waited on with poll in steps of 100 ms, then read again: a
/// FIFO's read returns 0 (its end) once no writer holds it, even where poll
/// would not report the hang-up (a FIFO reopened through /dev/stdin after
/// its writer has gone), so no wait outlives the writers.
std::string read_stream(int fd, const std::string& name, const std::string& too_large) {
  std::string text(4096, '\0');
  std::size_t used = 0;
  for (;;) {
    if (used == text.size()) {
      if (text.size() > kMaxInputBytes) throw InputError(too_large);
      text.resize(std::min<std::size_t>(2 * text.size(), kMaxInputBytes + 1));
    }
    const ssize_t n = ::read(fd, text.data() + used, text.size() - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{fd, POLLIN, 0};
      (void)::poll(&p, 1, 100);
      continue;
    }
    if (n < 0) throw InputError(name + ": cannot read the file (" + std::strerror(errno) + ")");
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  if (used > kMaxInputBytes) throw InputError(too_large);
  text.resize(used);
  return text;
}

/// What standard input held when it was first read: cmr reads it once, and
/// a command that reads its input twice (the dimension of a spline file,
/// then the file) gets the same text again.
std::optional<std::string>& stdin_text() {
  static std::optional<std::string> text;
  return text;
}

}  // namespace

std::string input_name(const std::filesystem::path& path) {
  return path == kStdinPath ? std::string("stdin") : path.string();
}

void note_stdin_closed() noexcept { g_stdin_closed = true; }

void forget_stdin() noexcept {
  stdin_text().reset();
  g_stdin_closed = false;
}

std::string read_input_file(const std::filesystem::path& path) {
  const bool from_stdin = path == kStdinPath;
  const std::string name = input_name(path);
  if (from_stdin && stdin_text()) return *stdin_text();
  if (from_stdin && g_stdin_closed) throw InputError("stdin: closed (nothing to read; pipe a spline file in, or name one)");
  const int fd = from_stdin ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) throw InputError(name + ": cannot open the file (" + std::strerror(errno) + ")");
  struct Closer {
    int fd;
    bool own;
    ~Closer() {
      if (own) ::close(fd);
    }
  } closer{fd, !from_stdin};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    if (from_stdin && errno == EBADF) throw InputError("stdin: closed (nothing to read; pipe a spline file in, or name one)");
    throw InputError(name + ": cannot read the file (" + std::strerror(errno) + ")");
  }
  const std::string too_large =
      name + ": larger than the " + std::to_string(kMaxInputBytes >> 20) + " MiB input limit";
  // Standard input may be anything but a folder or a terminal; a named path
  // a regular file or a FIFO (a pipe: /dev/stdin, /dev/fd/N, mkfifo's).
  const bool terminal = from_stdin && ::isatty(fd) == 1;
  const bool stream = S_ISFIFO(st.st_mode) || (from_stdin && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode) && !terminal);
  if (!S_ISREG(st.st_mode) && !stream) {
    if (terminal) throw InputError("stdin: a terminal (pipe a spline file in: cmr knots FILE insert U | cmr analyze -)");
    const char* kind = S_ISDIR(st.st_mode)    ? "a folder"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a plain file";
    throw InputError(name + ": not a regular file (" + kind + ")");
  }
  if (stream) {
    std::string text = read_stream(fd, name, too_large);
    if (text.empty())
      throw InputError(name + (S_ISFIFO(st.st_mode) ? ": empty (nothing came through the FIFO)"
                                                    : ": empty (nothing to read)"));
    if (from_stdin) stdin_text() = text;
    return text;
  }
  if (static_cast<std::uint64_t>(st.st_size) > kMaxInputBytes) throw InputError(too_large);
  std::string text(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t used = 0;
  for (;;) {  // the file may have grown since fstat: read to its end, within the limit
    if (used == text.size()) {
      if (text.size() > kMaxInputBytes) throw InputError(too_large);
      text.resize(std::min<std::size_t>(std::max<std::size_t>(2 * text.size(), 4096), kMaxInputBytes + 1));
    }
    const ssize_t n = ::read(fd, text.data() + used, text.size() - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(name + ": cannot read the file (" + std::strerror(errno) + ")");
    if (n == 0) break;
    used += static_cast<std::size_t>(n);
  }
  if (used > kMaxInputBytes) throw InputError(too_large);
  text.resize(used);
  if (from_stdin && text.empty()) throw InputError("stdin: empty (nothing to read)");
  if (from_stdin) stdin_text() = text;
  return text;
}

namespace {

/// What a file that is not JSON looks like, when cmr import reads that kind:
/// an XML/SVG document (first non-blank byte '<') or a font (its magic bytes).
const char* foreign_kind(std::string_view text) {
  std::string_view t = text;
  if (t.substr(0, 3) == "\xEF\xBB\xBF") t.remove_prefix(3);  // UTF-8 byte order mark
  while (!t.empty() && (t[0] == ' ' || t[0] == '\t' || t[0] == '\n' || t[0] == '\r')) t.remove_prefix(1);
  if (!t.empty() && t[0] == '<') return "an SVG/XML document";
  const std::string_view head = text.substr(0, 4);
  using namespace std::string_view_literals;
  const bool sfnt = head == "\0\1\0\0"sv || head == "OTTO" || head == "true" || head == "ttcf";
  if ((sfnt && text.size() >= 12 && text[4] == '\0') || head == "wOFF" || head == "wOF2" ||
      text.substr(0, 14) == "%!PS-AdobeFont" || text.substr(0, 11) == "%!FontType1" || text.substr(0, 2) == "\x80\x01")
    return "a font file";
  return nullptr;
}

}  // namespace

BSpline read_spline_file(const std::filesystem::path& path, const ReadOptions& options) {
  return spline_from_document(read_spline_document(path), path, options);
}

void release_json(json& root) noexcept {
  // Walks down the last children that are non-empty containers, removing
  // leaves and empty containers from the back (no allocation: a removed
  // value holds nothing). The way back up is kept for 64 levels; deeper,
  // the walk restarts from the nearest level kept (still correct).
  constexpr int kKept = 64;
  json* up[kKept];
  int depth = 0;
  json* cur = &root;
  const auto last_child = [](json* j) -> json* {
    if (j->is_array() && !j->empty()) return &j->get_ref<json::array_t&>().back();
    if (j->is_object() && !j->empty()) return &std::prev(j->get_ref<json::object_t&>().end())->second;
    return nullptr;
  };
  for (;;) {
    json* last = last_child(cur);
    if (last == nullptr) {
      if (cur == &root) return;
      cur = depth > 0 ? up[--depth] : &root;
      continue;
    }
    if ((last->is_array() || last->is_object()) && !last->empty()) {
      if (depth < kKept) up[depth++] = cur;
      cur = last;
      continue;
    }
    if (cur->is_array()) cur->get_ref<json::array_t&>().pop_back();
    else cur->get_ref<json::object_t&>().erase(std::prev(cur->get_ref<json::object_t&>().end()));
  }
}

json read_spline_document(const std::filesystem::path& path) {
  const std::string text = read_input_file(path);
  try {
    // Parsed into a document of our own (json::parse would destroy a
    // partial one itself, allocating: an abort when memory ran out).
    json doc;
    try {
      nlohmann::detail::json_sax_dom_parser<json> builder(doc, true);
      json::sax_parse(text, &builder);
    } catch (const std::bad_alloc&) {
      release_json(doc);
      throw;
    }
    return doc;
  } catch (const json::exception& e) {
    if (const char* kind = foreign_kind(text))  // an SVG or font given where a spline file belongs
      throw InputFieldError(input_name(path) + ": " + kind + ", not a spline file (run `cmr import " + path.string() +
                            " " + field("out") + " DIR` to convert it to spline files)");
    // nlohmann's message starts with "[json.exception.parse_error.101] parse error at line L, column C: ..."
    // (or out_of_range.406 "number overflow parsing '1e999'").
    std::string what = e.what();
    const auto pos = what.find("] ");
    if (pos != std::string::npos) what = what.substr(pos + 2);
    throw InputError(input_name(path) + ": malformed JSON: " + what);
  }
}

BSpline spline_from_document(const json& doc, const std::filesystem::path& path, const ReadOptions& options) {
  try {
    return spline_from_json(doc, options);
  } catch (const InputError& e) {
    throw InputFieldError(input_name(path) + ": " + marked_text(e));
  }
}

json spline_to_json(const BSpline& spline) {
  json doc;
  if (!spline.name().empty()) doc["name"] = spline.name();
  doc["degree"] = spline.degree();
  if (spline.closed()) doc["closed"] = true;
  doc["knots"] = spline.period_knots();
  json pts = json::array();
  for (int k = 0; k < spline.unique_point_count(); ++k) pts.push_back({spline.points()[k].x, spline.points()[k].y});
  doc["points"] = pts;
  if (spline.is_rational())
    doc["weights"] = std::vector<double>(spline.weights().begin(), spline.weights().begin() + spline.unique_point_count());
  return doc;
}

}  // namespace cmr
