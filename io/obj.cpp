#include "io/obj.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "io/output.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/spline_json.hpp"

namespace cmr::import {

namespace {

struct Vertex {
  Vec3 p;
  std::optional<double> w;  ///< the 4th coordinate when given (the weight of rational curves)
  int line = 0;
};

struct Curve {
  int line = 0;
  std::string cstype;
  bool rational = false;
  int degree = -1;
  double u0 = 0, u1 = 0;
  std::vector<int> indices;
  std::vector<double> knots;
  bool has_curv = false;
};

double number(const std::string& s, const std::string& at, const std::string& what) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size() || !std::isfinite(x))
    throw InputError(at + ": " + what + ": '" + s + "' is not a finite number");
  return x;
}

int vertex_index(const std::string& token, std::size_t count, const std::string& at, const std::string& what) {
  const std::string s = token.substr(0, token.find('/'));  // "v/vt" forms of l
  std::size_t used = 0;
  long long k = 0;
  try {
    k = std::stoll(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size()) throw InputError(at + ": " + what + ": '" + token + "' is not a vertex index");
  const long long n = static_cast<long long>(count);
  const long long i = k < 0 ? n + k : k - 1;  // 1-based; -1 is the last vertex so far
  if (k == 0 || i < 0 || i >= n)
    throw InputError(at + ": " + what + ": vertex " + s + " is outside 1.." + std::to_string(n) + " (or -1..-" +
                     std::to_string(n) + ")");
  return static_cast<int>(i);
}

SpaceSpline build(const Curve& c, const std::vector<Vertex>& vs, const std::string& at, const std::string& name) {
  if (c.degree < 1) throw InputError(at + ": curv: no deg statement before it");
  if (c.degree < 2) throw InputError(at + ": deg " + std::to_string(c.degree) + ": cmr needs degree 2 or more");
  std::vector<Vec3> pts;
  std::vector<double> w;
  for (int i : c.indices) {
    const Vertex& v = vs[static_cast<std::size_t>(i)];
    pts.push_back(v.p);
    if (!c.rational) continue;  // w of a non-rational curve's vertices is ignored (the spec)
    const std::string which = "vertex " + std::to_string(i + 1) + " (line " + std::to_string(v.line) + ")";
    const double weight = v.w.value_or(1.0);  // the spec: a vertex's w defaults to 1.0
    if (!(weight > 0)) {
      std::ostringstream o;
      o << at << ": curv: " << which << " has weight " << weight << ": rational curves need positive weights";
      throw InputError(o.str());
    }
    w.push_back(weight);
  }
  // Equal weights are the polynomial curve: written without weights, as before.
  if (std::all_of(w.begin(), w.end(), [&](double x) { return x == w.front(); })) w.clear();
  const int d = c.degree, m = static_cast<int>(pts.size());
  std::vector<double> polar;
  if (c.cstype == "bspline") {
    if (static_cast<int>(c.knots.size()) != m + d + 1)
      throw InputError(at + ": parm u: " + std::to_string(c.knots.size()) + " knots for " + std::to_string(m) +
                       " control points of degree " + std::to_string(d) + " (expected points + degree + 1 = " +
                       std::to_string(m + d + 1) + ")");
    polar.assign(c.knots.begin() + 1, c.knots.end() - 1);  // the full vector's ends do not act on the curve
  } else {  // bezier: breakpoints p_0..p_k, points k d + 1
    std::vector<double> br = c.knots;
    if (br.empty()) br = {c.u0, c.u1};
    const int pieces = static_cast<int>(br.size()) - 1;
    if (pieces < 1 || m != pieces * d + 1)
      throw InputError(at + ": a bezier curve of degree " + std::to_string(d) + " with " + std::to_string(pieces) +
                       " pieces needs " + std::to_string(pieces * d + 1) + " control points (got " + std::to_string(m) +
                       ")");
    for (double b : br)
      for (int r = 0; r < d; ++r) polar.push_back(b);
  }
  SpaceSpline s = [&] {
    try {
      return SpaceSpline::make(d, polar, pts, name, w);
    } catch (const InputError& e) {
      throw InputFieldError(at + ": " + marked_text(e));
    }
  }();
  if (s.domain_begin() != c.u0 || s.domain_end() != c.u1) {
    std::ostringstream o;
    o << at << ": curv: the range [" << c.u0 << ", " << c.u1 << "] is not the curve's domain [" << s.domain_begin()
      << ", " << s.domain_end() << "] (trimmed curves are not supported)";
    throw InputError(o.str());
  }
  return s;
}

std::vector<double> clamped_uniform(int d, int m) {  // polar
  std::vector<double> k;
  for (int i = 0; i < d - 1; ++i) k.push_back(0);
  for (int i = 0; i <= m - d; ++i) k.push_back(i);
  for (int i = 0; i < d - 1; ++i) k.push_back(m - d);
  return k;
}

}  // namespace

std::vector<ObjCurve> parse_obj_curves(const std::string& text, const std::string& where) {
  std::vector<Vertex> vs;
  std::vector<ObjCurve> out;
  std::string cstype;
  bool rational = false;
  int degree = -1;
  std::optional<Curve> cur;
  std::string name;
  std::istringstream in(text);
  std::string raw, line;
  int lineno = 0, start = 0;
  const auto label = [&](const char* kind) { return name.empty() ? std::string(kind) : name; };
  while (std::getline(in, raw)) {
    ++lineno;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    if (line.empty()) start = lineno;
    if (!raw.empty() && raw.back() == '\\') {  // continuation
      line += raw.substr(0, raw.size() - 1) + " ";
      continue;
    }
    line += raw;
    const std::string at = where + ":" + std::to_string(start);
    std::istringstream ls(line.substr(0, line.find('#')));
    line.clear();
    std::string key;
    if (!(ls >> key)) continue;
    std::vector<std::string> args;
    for (std::string t; ls >> t;) args.push_back(t);
    if (key == "v") {
      if (args.size() < 3 || args.size() > 4) throw InputError(at + ": v: expected x y z [w]");
      Vertex v{{number(args[0], at, "v"), number(args[1], at, "v"), number(args[2], at, "v")},
               args.size() == 4 ? std::optional<double>(number(args[3], at, "v")) : std::nullopt, start};
      vs.push_back(v);
    } else if (key == "o" || key == "g") {
      name = args.empty() ? "" : args[0];
      // The name goes into JSON, which holds UTF-8 only (fuzz_obj: a byte
      // 0xFF here ended `cmr import` with "unexpected error", exit 3).
      for (std::string_view rest = name; !rest.empty();) {
        const std::size_t n = utf8_sequence(rest);
        if (n == 0) throw InputError(at + ": " + key + ": the name is not UTF-8");
        rest.remove_prefix(n);
      }
    } else if (key == "cstype") {
      rational = !args.empty() && args[0] == "rat";
      const std::string type = args.empty() ? "" : args.back();
      if (args.empty() || args.size() > 2 || (rational && args.size() != 2) || (!rational && args.size() != 1))
        throw InputError(at + ": cstype: expected [rat] bspline or [rat] bezier");
      if (type != "bspline" && type != "bezier")
        throw InputError(at + ": cstype " + type + ": only bspline and bezier curves are read (not " + type + ")");
      cstype = type;
    } else if (key == "deg") {
      if (args.empty()) throw InputError(at + ": deg: missing");
      const double d = number(args[0], at, "deg");
      if (d != std::floor(d) || d < 1 || d > 30) throw InputError(at + ": deg: '" + args[0] + "' is not a degree 1..30");
      degree = static_cast<int>(d);
    } else if (key == "curv") {
      if (cstype.empty()) throw InputError(at + ": curv: no cstype statement before it");
      if (args.size() < 4) throw InputError(at + ": curv: expected U0 U1 and at least two vertex indices");
      Curve c;
      c.line = start;
      c.cstype = cstype;
      c.rational = rational;
      c.degree = degree;
      c.u0 = number(args[0], at, "curv");
      c.u1 = number(args[1], at, "curv");
      for (std::size_t i = 2; i < args.size(); ++i) c.indices.push_back(vertex_index(args[i], vs.size(), at, "curv"));
      c.has_curv = true;
      cur = c;
    } else if (key == "parm") {
      if (!cur) throw InputError(at + ": parm: no curv statement before it");
      if (args.empty() || args[0] != "u") throw InputError(at + ": parm: curves have 'parm u' only");
      for (std::size_t i = 1; i < args.size(); ++i) cur->knots.push_back(number(args[i], at, "parm u"));
    } else if (key == "end") {
      if (!cur) continue;  // the end of a surface or of nothing: skipped
      const std::string cat = where + ":" + std::to_string(cur->line);
      out.push_back({build(*cur, vs, cat, label("curv")), "curv", cur->line});
      cur.reset();
    } else if (key == "l") {
      std::vector<Vec3> pts;
      for (const std::string& a : args) pts.push_back(vs[static_cast<std::size_t>(vertex_index(a, vs.size(), at, "l"))].p);
      if (pts.size() < 3)
        throw InputError(at + ": l: a polyline needs at least 3 vertices to be a control polygon (got " +
                         std::to_string(pts.size()) + ")");
      const int d = std::min(3, static_cast<int>(pts.size()) - 1);
      try {
        out.push_back({SpaceSpline::make(d, clamped_uniform(d, static_cast<int>(pts.size())), pts, label("l")), "l", start});
      } catch (const InputError& e) {
        throw InputFieldError(at + ": l: " + marked_text(e));
      }
    }
  }
  if (cur) throw InputError(where + ":" + std::to_string(cur->line) + ": curv: no 'end' statement");
  if (out.empty()) throw InputError(where + ": no curves (cstype/curv or l elements)");
  return out;
}

std::vector<ObjCurve> read_obj_curves(const std::filesystem::path& path) {
  return parse_obj_curves(read_input_file(path), path.string());
}

}  // namespace cmr::import
