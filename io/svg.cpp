#include "io/svg.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <utility>

#include <pugixml.hpp>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "io/chain.hpp"

namespace cmr::import {
namespace {

/// A Bezier piece with homogeneous weights (all 1 unless it comes from an arc).
struct Piece {
  std::vector<Vec2> p;
  std::vector<double> w;
  int degree() const { return static_cast<int>(p.size()) - 1; }
  bool rational() const {
    return std::any_of(w.begin(), w.end(), [](double x) { return x != 1.0; });
  }
};

Piece polynomial(std::vector<Vec2> p) {
  std::vector<double> w(p.size(), 1.0);
  return {std::move(p), std::move(w)};
}

/// Degree elevation by one on (w P, w): H'_i = i/(n+1) H_{i-1} + (1 - i/(n+1)) H_i.
Piece elevate(const Piece& a) {
  const int n = a.degree();
  Piece b;
  for (int i = 0; i <= n + 1; ++i) {
    const double s = static_cast<double>(i) / (n + 1);
    Vec2 h(0.0);
    double w = 0;
    if (i > 0) h += s * a.w[i - 1] * a.p[i - 1], w += s * a.w[i - 1];
    if (i <= n) h += (1 - s) * a.w[i] * a.p[i], w += (1 - s) * a.w[i];
    b.p.push_back(h / w);
    b.w.push_back(w);
  }
  // The ends are the original points exactly (the sums above have one term there).
  b.p.front() = a.p.front();
  b.p.back() = a.p.back();
  return b;
}

bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

/// SVG arc (endpoint parametrisation, F.6.5) as rational quadratic pieces of
/// at most 90 degrees. Empty when the ends coincide (F.6.2: nothing drawn);
/// one line piece when a radius is zero. `ok` is false (and nothing is
/// returned) when the centre parametrisation overflows.
std::vector<Piece> arc_pieces(Vec2 p1, double rx, double ry, double phi_deg, bool large, bool sweep, Vec2 p2, bool& ok) {
  ok = true;
  if (p1 == p2) return {};
  rx = std::abs(rx), ry = std::abs(ry);
  if (rx == 0 || ry == 0) return {polynomial({p1, p2})};
  const double phi = phi_deg * std::numbers::pi / 180, c = std::cos(phi), s = std::sin(phi);
  const double dx = (p1.x - p2.x) / 2, dy = (p1.y - p2.y) / 2;
  const double x1 = c * dx + s * dy, y1 = -s * dx + c * dy;
  const double lambda = x1 * x1 / (rx * rx) + y1 * y1 / (ry * ry);
  if (lambda > 1) rx *= std::sqrt(lambda), ry *= std::sqrt(lambda);  // F.6.6: radii too small
  const double num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1;
  const double den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
  const double coef = (large != sweep ? 1.0 : -1.0) * std::sqrt(std::max(0.0, num / den));
  const double cx1 = coef * rx * y1 / ry, cy1 = -coef * ry * x1 / rx;
  const Vec2 centre(c * cx1 - s * cy1 + (p1.x + p2.x) / 2, s * cx1 + c * cy1 + (p1.y + p2.y) / 2);
  auto angle = [](double ux, double uy, double vx, double vy) { return std::atan2(ux * vy - uy * vx, ux * vx + uy * vy); };
  const double theta1 = angle(1, 0, (x1 - cx1) / rx, (y1 - cy1) / ry);
  double delta = angle((x1 - cx1) / rx, (y1 - cy1) / ry, (-x1 - cx1) / rx, (-y1 - cy1) / ry);
  if (!sweep && delta > 0) delta -= 2 * std::numbers::pi;
  if (sweep && delta < 0) delta += 2 * std::numbers::pi;
  if (!finite(centre) || !std::isfinite(rx) || !std::isfinite(ry) || !std::isfinite(theta1) || !std::isfinite(delta)) {
    ok = false;  // e.g. rx*rx overflows: no arc to draw, and no NaN cast to int below
    return {};
  }
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(delta) / (std::numbers::pi / 2) - 1e-12)));
  const double h = delta / n;
  auto on_ellipse = [&](double t, double scale) {
    const double ex = rx * std::cos(t) * scale, ey = ry * std::sin(t) * scale;
    return centre + Vec2(c * ex - s * ey, s * ex + c * ey);
  };
  std::vector<Piece> out;
  Vec2 from = p1;
  for (int k = 0; k < n; ++k) {
    const double a = theta1 + k * h, b = theta1 + (k + 1) * h;
    const Vec2 to = k + 1 == n ? p2 : on_ellipse(b, 1.0);
    // The end tangents meet at the mid angle, 1/cos(h/2) out from the centre.
    out.push_back({{from, on_ellipse((a + b) / 2, 1.0 / std::cos(h / 2)), to}, {1.0, std::cos(h / 2), 1.0}});
    from = to;
  }
  return out;
}

class Parser {
 public:
  Parser(const std::string& d, std::string prefix) : d_(d), prefix_(std::move(prefix)) {}

  std::vector<PathSpline> run() {
    char cmd = 0;
    while (true) {
      skip();
      if (i_ >= d_.size()) break;
      start_of_command_ = i_;
      if (std::isalpha(static_cast<unsigned char>(d_[i_]))) {
        if (std::string("MmLlHhVvCcSsQqTtAaZz").find(d_[i_]) == std::string::npos)
          fail("unknown command '" + std::string(1, d_[i_]) + "'");
        if (cmd == 0 && d_[i_] != 'M' && d_[i_] != 'm') fail("path data must start with M or m");
        cmd = d_[i_];
        ++i_;
      } else if (cmd == 0) {
        fail("path data must start with M or m");
      } else if (cmd == 'Z' || cmd == 'z') {
        fail("numbers after Z");
      } else if (cmd == 'M') {
        cmd = 'L';
      } else if (cmd == 'm') {
        cmd = 'l';
      }
      command(cmd);
    }
    finish(false);
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("d[" + std::to_string(i_) + "]: " + what);
  }
  void skip() {
    while (i_ < d_.size() && (std::isspace(static_cast<unsigned char>(d_[i_])) || d_[i_] == ',')) ++i_;
  }
  double number() {
    skip();
    const std::size_t start = i_;
    std::size_t j = i_;
    if (j < d_.size() && (d_[j] == '+' || d_[j] == '-')) ++j;
    const std::size_t digits_from = j;
    while (j < d_.size() && std::isdigit(static_cast<unsigned char>(d_[j]))) ++j;
    if (j < d_.size() && d_[j] == '.') {
      ++j;
      while (j < d_.size() && std::isdigit(static_cast<unsigned char>(d_[j]))) ++j;
    }
    if (j == digits_from || (j == digits_from + 1 && d_[digits_from] == '.')) fail("expected a number");
    if (j < d_.size() && (d_[j] == 'e' || d_[j] == 'E')) {
      std::size_t k = j + 1;
      if (k < d_.size() && (d_[k] == '+' || d_[k] == '-')) ++k;
      if (k < d_.size() && std::isdigit(static_cast<unsigned char>(d_[k]))) {
        while (k < d_.size() && std::isdigit(static_cast<unsigned char>(d_[k]))) ++k;
        j = k;
      }
    }
    std::string token = d_.substr(start, j - start);
    if (token[0] == '+') token.erase(0, 1);
    double v = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
    if (ec != std::errc() || end != token.data() + token.size() || !std::isfinite(v)) fail("'" + token + "' is not a finite number");
    i_ = j;
    return v;
  }
  bool flag() {
    skip();
    if (i_ < d_.size() && (d_[i_] == '0' || d_[i_] == '1')) return d_[i_++] == '1';
    fail("expected an arc flag 0 or 1");
  }
  Vec2 point(bool relative) {
    const double x = number(), y = number();
    const Vec2 p = relative ? cur_ + Vec2(x, y) : Vec2(x, y);
    if (!finite(p)) not_finite();
    return p;
  }
  /// A sum of relative moves, an arc's centre or a reflected control point
  /// overflowed: named at the start of the command's numbers.
  [[noreturn]] void not_finite() const {
    throw InputError("d[" + std::to_string(start_of_command_) + "]: the command's coordinates are not finite (they overflow)");
  }

  void add(Piece p) {
    for (std::size_t k = 0; k < p.p.size(); ++k)
      if (!finite(p.p[k]) || !std::isfinite(p.w[k])) not_finite();
    if (!open_) {  // a command after Z without M starts at the last subpath's start
      open_ = true;
      start_ = cur_;
    }
    pieces_.push_back(std::move(p));
  }

  void command(char cmd) {
    const bool rel = std::islower(static_cast<unsigned char>(cmd));
    const char up = static_cast<char>(std::toupper(static_cast<unsigned char>(cmd)));
    const char before = last_;
    last_ = up;
    switch (up) {
      case 'M':
        finish(false);
        cur_ = start_ = point(rel);
        open_ = true;
        return;
      case 'Z':
        if (open_) {
          if (cur_ != start_) add(polynomial({cur_, start_}));
          cur_ = start_;
          finish(true);
        }
        return;
      case 'L': {
        const Vec2 p = point(rel);
        add(polynomial({cur_, p}));
        cur_ = p;
        return;
      }
      case 'H': case 'V': {
        const double v = number();
        Vec2 p = cur_;
        (up == 'H' ? p.x : p.y) = rel ? (up == 'H' ? cur_.x : cur_.y) + v : v;
        if (!finite(p)) not_finite();
        add(polynomial({cur_, p}));
        cur_ = p;
        return;
      }
      case 'C': case 'S': {
        Vec2 c1 = cur_;
        if (up == 'S') {
          if (before == 'C' || before == 'S') c1 = 2.0 * cur_ - ctrl_;
        } else {
          c1 = point(rel);
        }
        const Vec2 c2 = point(rel), p = point(rel);
        add(polynomial({cur_, c1, c2, p}));
        ctrl_ = c2, cur_ = p;
        return;
      }
      case 'Q': case 'T': {
        Vec2 c1 = cur_;
        if (up == 'T') {
          if (before == 'Q' || before == 'T') c1 = 2.0 * cur_ - ctrl_;
        } else {
          c1 = point(rel);
        }
        const Vec2 p = point(rel);
        add(polynomial({cur_, c1, p}));
        ctrl_ = c1, cur_ = p;
        return;
      }
      case 'A': {
        const double rx = number(), ry = number(), phi = number();
        const bool large = flag(), sweep = flag();
        const Vec2 p = point(rel);
        bool ok = true;
        std::vector<Piece> pieces = arc_pieces(cur_, rx, ry, phi, large, sweep, p, ok);
        if (!ok) not_finite();
        for (Piece& piece : pieces) add(std::move(piece));
        cur_ = p;
        return;
      }
      default:
        fail("unknown command");
    }
  }

  /// Ends the current subpath: its pieces at one degree, as one spline.
  void finish(bool closed) {
    if (pieces_.empty()) {
      open_ = false;
      return;
    }
    int D = 2;
    for (const Piece& p : pieces_) D = std::max(D, p.degree());
    PathSpline s;
    s.name = prefix_ + "/s" + std::to_string(out_.size());
    s.degree = D;
    s.closed = closed;
    bool rational = false;
    std::vector<double> w;
    for (std::size_t k = 0; k < pieces_.size(); ++k) {
      Piece p = pieces_[k];
      while (p.degree() < D) p = elevate(p);
      rational = rational || p.rational();
      for (int i = k == 0 ? 0 : 1; i <= D; ++i) s.points.push_back(p.p[i]), w.push_back(p.w[i]);
    }
    const int N = static_cast<int>(pieces_.size());
    if (closed) {
      s.points.pop_back();  // the last node is the first
      w.pop_back();
      std::vector<bool> inc(s.points.size());
      for (std::size_t k = 0; k < inc.size(); ++k) inc[k] = k % D == 1;  // a piece's first inner point
      s.knots = chain_knots(inc);
    } else {
      for (int k = 0; k <= N; ++k)
        for (int r = 0; r < D; ++r) s.knots.push_back(k);
    }
    if (rational) s.weights = std::move(w);
    out_.push_back(std::move(s));
    pieces_.clear();
    open_ = false;
  }

  const std::string& d_;
  std::string prefix_;
  std::size_t i_ = 0, start_of_command_ = 0;
  Vec2 cur_{0.0}, start_{0.0}, ctrl_{0.0};
  char last_ = 0;
  bool open_ = false;
  std::vector<Piece> pieces_;
  std::vector<PathSpline> out_;
};

}  // namespace

std::vector<PathSpline> parse_path_data(const std::string& d, const std::string& prefix) {
  return Parser(d, prefix).run();
}

Affine operator*(const Affine& o, const Affine& i) {
  return {o.a * i.a + o.c * i.b, o.b * i.a + o.d * i.b, o.a * i.c + o.c * i.d,
          o.b * i.c + o.d * i.d, o.a * i.e + o.c * i.f + o.e, o.b * i.e + o.d * i.f + o.f};
}

Affine parse_transform(const std::string& t) {
  std::size_t i = 0;
  auto fail = [&](const std::string& what) -> void {
    throw InputError("transform[" + std::to_string(i) + "]: " + what);
  };
  auto space = [&](bool comma) {
    while (i < t.size() && (std::isspace(static_cast<unsigned char>(t[i])) || (comma && t[i] == ','))) ++i;
  };
  auto number = [&]() {
    space(false);
    std::size_t j = i;
    if (j < t.size() && (t[j] == '+' || t[j] == '-')) ++j;
    const std::size_t digits = j;
    while (j < t.size() && (std::isdigit(static_cast<unsigned char>(t[j])) || t[j] == '.')) ++j;
    if (j == digits) fail("expected a number");
    if (j < t.size() && (t[j] == 'e' || t[j] == 'E')) {
      std::size_t k = j + 1;
      if (k < t.size() && (t[k] == '+' || t[k] == '-')) ++k;
      if (k < t.size() && std::isdigit(static_cast<unsigned char>(t[k]))) {
        while (k < t.size() && std::isdigit(static_cast<unsigned char>(t[k]))) ++k;
        j = k;
      }
    }
    const std::size_t from = t[i] == '+' ? i + 1 : i;
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data() + from, t.data() + j, v);
    if (ec != std::errc() || end != t.data() + j || !std::isfinite(v)) fail("'" + t.substr(i, j - i) + "' is not a finite number");
    i = j;
    return v;
  };
  Affine m;
  space(true);
  while (i < t.size()) {
    const std::size_t name_at = i;
    while (i < t.size() && std::isalpha(static_cast<unsigned char>(t[i]))) ++i;
    const std::string name = t.substr(name_at, i - name_at);
    const std::size_t args_at = i;
    std::size_t arity[2] = {0, 0};  // allowed argument counts
    if (name == "matrix") arity[0] = arity[1] = 6;
    else if (name == "translate" || name == "scale") arity[0] = 1, arity[1] = 2;
    else if (name == "rotate") arity[0] = 1, arity[1] = 3;
    else if (name == "skewX" || name == "skewY") arity[0] = arity[1] = 1;
    else {
      i = name_at;
      fail(name.empty() ? "expected a transform (matrix, translate, scale, rotate, skewX, skewY)"
                        : "unknown transform '" + name + "'");
    }
    space(false);
    if (i >= t.size() || t[i] != '(') fail("expected '(' after " + name);
    ++i;
    std::vector<double> v;
    space(false);
    while (i < t.size() && t[i] != ')') {
      if (v.size() == 6) fail("too many numbers for " + name);
      v.push_back(number());
      space(true);
    }
    if (i >= t.size()) fail("expected ')' after " + name + "'s numbers");
    ++i;
    if (v.size() < arity[0] || v.size() > arity[1] || (name == "rotate" && v.size() == 2)) {
      i = args_at;
      fail(name + " takes " + (name == "rotate" ? std::string("1 or 3") : arity[0] == arity[1] ? std::to_string(arity[0])
                                                                          : "1 or 2") +
           " numbers, not " + std::to_string(v.size()));
    }
    const double deg = std::numbers::pi / 180;
    Affine step;
    if (name == "matrix") step = {v[0], v[1], v[2], v[3], v[4], v[5]};
    else if (name == "translate") step = {1, 0, 0, 1, v[0], v.size() > 1 ? v[1] : 0.0};
    else if (name == "scale") step = {v[0], 0, 0, v.size() > 1 ? v[1] : v[0], 0, 0};
    else if (name == "skewX") step = {1, 0, std::tan(v[0] * deg), 1, 0, 0};
    else if (name == "skewY") step = {1, std::tan(v[0] * deg), 0, 1, 0, 0};
    else {  // rotate(a [cx cy]) = translate(cx cy) rotate(a) translate(-cx -cy)
      const double c = std::cos(v[0] * deg), s = std::sin(v[0] * deg);
      step = {c, s, -s, c, 0, 0};
      if (v.size() == 3) step = Affine{1, 0, 0, 1, v[1], v[2]} * step * Affine{1, 0, 0, 1, -v[1], -v[2]};
    }
    m = m * step;
    space(true);
  }
  return m;
}

namespace {

/// Whether `s` is UTF-8 that JSON can hold (a spline's name is written to JSON).
bool valid_utf8(const std::string& s) {
  try {
    (void)nlohmann::json(s).dump();
    return true;
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

/// The element name without a namespace prefix ("svg:path" -> "path").
std::string_view local_name(const char* name) {
  std::string_view n(name);
  const auto colon = n.rfind(':');
  return colon == std::string_view::npos ? n : n.substr(colon + 1);
}

}  // namespace

std::vector<PathSpline> read_svg_text(const std::string& text, const std::string& name, const std::string& stem,
                                      const SvgOptions& options) {
  pugi::xml_document doc;
  // parse_default: elements, attributes (whitespace normalised), CDATA as
  // text, the predefined entities and character references expanded. No
  // comments, processing instructions or DOCTYPE nodes; pugixml never
  // expands an entity a DOCTYPE declares and never fetches anything.
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed)
    throw InputError(name + ": not well-formed XML at byte " + std::to_string(parsed.offset) + ": " +
                     parsed.description());
  const Affine flip = options.flip_y ? Affine{1, 0, 0, -1, 0, 0} : Affine{};
  std::vector<PathSpline> out;
  int index = 0;
  std::vector<std::pair<pugi::xml_node, Affine>> stack;  // explicit: deep nesting cannot overflow the call stack
  for (pugi::xml_node top = doc.last_child(); top; top = top.previous_sibling())
    if (top.type() == pugi::node_element) stack.emplace_back(top, flip);
  while (!stack.empty()) {
    auto [node, outer] = stack.back();
    stack.pop_back();
    Affine m = outer;
    const pugi::xml_attribute transform = node.attribute("transform");
    const bool is_path = local_name(node.name()) == "path";
    std::string where = "path " + std::to_string(index);
    if (!is_path) {  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string&&
      where = "<";
      where += node.name();
      where += '>';
    }
    if (transform) {
      try {
        m = outer * parse_transform(transform.value());
      } catch (const InputError& e) {
        throw InputError(name + ": " + where + " (byte " + std::to_string(node.offset_debug()) + "), " + e.what());
      }
    }
    if (is_path) {
      const int this_index = index++;
      const pugi::xml_attribute d = node.attribute("d");
      if (d) {
        const std::string id = node.attribute("id").value();
        std::string label = id.empty() ? "path" + std::to_string(this_index) : id;
        if (!valid_utf8(stem + "/" + label)) label = "path" + std::to_string(this_index);  // found by fuzz_svg_document
        const std::string prefix = valid_utf8(stem + "/" + label) ? stem + "/" + label : "svg/" + label;
        std::vector<PathSpline> subpaths;
        try {
          subpaths = parse_path_data(d.value(), prefix);
        } catch (const InputError& e) {
          throw InputError(name + ": " + where + ", " + e.what());
        }
        for (PathSpline& s : subpaths) {
          for (Vec2& p : s.points) {
            p = m(p);
            if (!finite(p))
              throw InputError(name + ": " + where + ": a coordinate is not finite after the transform");
          }
          out.push_back(std::move(s));
        }
      }
    }
    std::size_t first = stack.size();
    for (pugi::xml_node child = node.first_child(); child; child = child.next_sibling())
      if (child.type() == pugi::node_element) stack.emplace_back(child, m);
    std::reverse(stack.begin() + static_cast<std::ptrdiff_t>(first), stack.end());  // document order
  }
  if (out.empty()) throw InputError(name + ": no <path> with curve data");
  return out;
}

std::vector<PathSpline> read_svg(const std::filesystem::path& path, const SvgOptions& options) {
  const std::string svg = read_input_file(path);  // regular files only, size-limited
  return read_svg_text(svg, path.string(), path.stem().string(), options);
}

bool is_svg_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".svg";
}

nlohmann::json path_json(const PathSpline& s) {
  nlohmann::json doc;
  doc["name"] = s.name;
  doc["degree"] = s.degree;
  if (s.closed) doc["closed"] = true;
  doc["knots"] = s.knots;
  nlohmann::json pts = nlohmann::json::array();
  for (const Vec2& p : s.points) pts.push_back({p.x, p.y});
  doc["points"] = pts;
  if (s.rational()) doc["weights"] = s.weights;
  return doc;
}

BSpline to_bspline(const PathSpline& s) {
  if (s.closed) return BSpline::make_closed(s.degree, s.knots, s.points, s.name, s.weights);
  return BSpline::make(s.degree, s.knots, s.points, s.name, s.weights);
}

Vec2 rational_bezier_point(const std::vector<Vec2>& points, const std::vector<double>& weights, double t) {
  std::vector<Vec2> h;
  std::vector<double> w = weights;
  for (std::size_t i = 0; i < points.size(); ++i) h.push_back(w[i] * points[i]);
  for (std::size_t r = 1; r < points.size(); ++r)
    for (std::size_t i = 0; i + r < points.size(); ++i) {
      h[i] = (1 - t) * h[i] + t * h[i + 1];
      w[i] = (1 - t) * w[i] + t * w[i + 1];
    }
  return h[0] / w[0];
}

}  // namespace cmr::import
