#include "io/svg.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <regex>

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

/// SVG arc (endpoint parametrisation, F.6.5) as rational quadratic pieces of
/// at most 90 degrees. Empty when the ends coincide (F.6.2: nothing drawn);
/// one line piece when a radius is zero.
std::vector<Piece> arc_pieces(Vec2 p1, double rx, double ry, double phi_deg, bool large, bool sweep, Vec2 p2) {
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
    return relative ? cur_ + Vec2(x, y) : Vec2(x, y);
  }

  void add(Piece p) {
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
        for (Piece& piece : arc_pieces(cur_, rx, ry, phi, large, sweep, p)) add(std::move(piece));
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
  std::size_t i_ = 0;
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

std::vector<PathSpline> read_svg(const std::filesystem::path& path) {
  const std::string svg = read_input_file(path);  // regular files only, size-limited
  const std::regex element(R"(<path\b([^>]*)>)");
  const std::regex attribute(R"re(\s(d|id)\s*=\s*(?:"([^"]*)"|'([^']*)'))re");
  std::vector<PathSpline> out;
  int index = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), element); it != std::sregex_iterator(); ++it, ++index) {
    const std::string attrs = (*it)[1].str();
    std::string d, id;
    bool has_d = false;
    for (auto a = std::sregex_iterator(attrs.begin(), attrs.end(), attribute); a != std::sregex_iterator(); ++a) {
      const std::string value = (*a)[2].matched ? (*a)[2].str() : (*a)[3].str();
      if ((*a)[1] == "d") d = value, has_d = true;
      else id = value;
    }
    if (!has_d) continue;
    const std::string label = id.empty() ? "path" + std::to_string(index) : id;
    try {
      for (PathSpline& s : parse_path_data(d, path.stem().string() + "/" + label)) out.push_back(std::move(s));
    } catch (const InputError& e) {
      throw InputError(path.string() + ": path " + std::to_string(index) + ", " + e.what());
    }
  }
  if (out.empty()) throw InputError(path.string() + ": no <path> with curve data");
  return out;
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
