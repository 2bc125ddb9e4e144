#include "spline/space.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "spline/blossom.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/format.hpp"

namespace cmr {

namespace {

std::vector<Vec2> shadow_points(const std::vector<Vec3>& points) {
  std::vector<Vec2> xy;
  xy.reserve(points.size());
  for (const Vec3& p : points) xy.emplace_back(p.x, p.y);
  return xy;
}

std::vector<double> z_of(const std::vector<Vec3>& points) {
  std::vector<double> z;
  z.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i].z)) throw InputError("points[" + std::to_string(i) + "][2] is not a finite number");
    z.push_back(points[i].z);
  }
  return z;
}

/// Space curves need W > 0 everywhere: every weight positive. Non-finite
/// values are left to BSpline's message.
void check_positive(const std::vector<double>& weights) {
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (std::isfinite(weights[i]) && !(weights[i] > 0))
      throw InputError("weights[" + std::to_string(i) + "] is " + format_number(weights[i]) +
                       ": rational space curves need positive weights");
}

}  // namespace

SpaceSpline::SpaceSpline(BSpline shadow, std::vector<Vec3> points)
    : shadow_(std::move(shadow)), points_(std::move(points)) {
  hpoints_.reserve(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const double w = shadow_.weight(static_cast<int>(i));
    hpoints_.emplace_back(w * points_[i].x, w * points_[i].y, w * points_[i].z, w);
  }
}

SpaceSpline SpaceSpline::from_shadow(BSpline shadow, const std::vector<double>& z) {
  // Unrolled points of a closed spline repeat P_0..P_{d-1}: index k mod m.
  const int m = shadow.unique_point_count();
  std::vector<Vec3> pts;
  pts.reserve(shadow.points().size());
  for (int k = 0; k < shadow.point_count(); ++k) {
    const Vec2 p = shadow.points()[k];
    pts.emplace_back(p.x, p.y, z[static_cast<std::size_t>(k % m)]);
  }
  return SpaceSpline(std::move(shadow), std::move(pts));
}

SpaceSpline SpaceSpline::make(int degree, std::vector<double> knots, std::vector<Vec3> points, std::string name,
                              std::vector<double> weights) {
  const std::vector<double> z = z_of(points);
  check_positive(weights);
  return from_shadow(
      BSpline::make(degree, std::move(knots), shadow_points(points), std::move(name), std::move(weights)), z);
}

SpaceSpline SpaceSpline::bezier(std::vector<Vec3> points, std::string name, std::vector<double> weights) {
  const std::vector<double> z = z_of(points);
  check_positive(weights);
  return from_shadow(BSpline::bezier(shadow_points(points), std::move(name), std::move(weights)), z);
}

SpaceSpline SpaceSpline::make_closed(int degree, std::vector<double> knots, std::vector<Vec3> points,
                                     std::string name, std::vector<double> weights) {
  const std::vector<double> z = z_of(points);
  check_positive(weights);
  return from_shadow(
      BSpline::make_closed(degree, std::move(knots), shadow_points(points), std::move(name), std::move(weights)), z);
}

SpaceSpline SpaceSpline::embed(const BSpline& planar) {
  check_positive(planar.weights());
  return from_shadow(planar, std::vector<double>(static_cast<std::size_t>(planar.unique_point_count()), 0.0));
}

SpaceSpline SpaceSpline::with_point(int k, Vec3 p) const {
  if (!std::isfinite(p.z)) throw InputError("point " + std::to_string(k) + " is not finite");
  SpaceSpline s(shadow_.with_point(k, {p.x, p.y}), points_);
  const auto put = [&](int i) {
    const double w = shadow_.weight(i);
    s.points_[static_cast<std::size_t>(i)] = p;
    s.hpoints_[static_cast<std::size_t>(i)] = Vec4(w * p.x, w * p.y, w * p.z, w);
  };
  put(k);
  const int t = shadow_.twin(k);
  if (t >= 0) put(t);
  return s;
}

Vec3 blossom(const SpaceSpline& spline, const Segment& s, const double* args) {
  CMR_CHECK(!spline.is_rational());
  return blossom_span(spline.knots(), spline.points(), spline.degree(), s.span, args);
}

Vec4 homogeneous_blossom(const SpaceSpline& spline, const Segment& s, const double* args) {
  return blossom_span(spline.knots(), spline.homogeneous_points(), spline.degree(), s.span, args);
}

namespace {

Vec3 project(const Vec4& h) { return Vec3(h.x, h.y, h.z) / h.w; }

/// H^(r)(t) = d!/(d-r)!/(b-a)^r sum_i (-1)^{r-i} C(r,i) f(t^{d-r}, a^{r-i}, b^i) (blossom.hpp).
Vec4 homogeneous_derivative(const SpaceSpline& spline, double t, int r) {
  const int d = spline.degree();
  CMR_CHECK(r >= 0 && r <= d);
  const Segment& s = spline.segment_at(t);
  std::vector<double> args(d, t);
  Vec4 sum(0.0);
  double binom = 1.0;
  for (int i = 0; i <= r; ++i) {
    for (int k = 0; k < r; ++k) args[d - r + k] = k < r - i ? s.a : s.b;
    sum += ((r - i) % 2 == 0 ? binom : -binom) * homogeneous_blossom(spline, s, args.data());
    binom = binom * (r - i) / (i + 1);
  }
  double f = 1.0;
  for (int k = 0; k < r; ++k) f *= static_cast<double>(d - k) / (s.b - s.a);
  return f * sum;
}

}  // namespace

Vec3 evaluate(const SpaceSpline& spline, double t) {
  const std::vector<double> args(spline.degree(), t);
  return project(homogeneous_blossom(spline, spline.segment_at(t), args.data()));
}

Vec3 derivative(const SpaceSpline& spline, double t, int r) {
  if (!spline.is_rational()) {
    const Vec4 h = homogeneous_derivative(spline, t, r);
    return Vec3(h.x, h.y, h.z);
  }
  // Leibniz on X = W C: C^(r) = (X^(r) - sum_{i=1..r} C(r,i) W^(i) C^(r-i)) / W.
  std::vector<Vec4> H;
  for (int i = 0; i <= r; ++i) H.push_back(homogeneous_derivative(spline, t, i));
  std::vector<Vec3> C;
  for (int q = 0; q <= r; ++q) {
    Vec3 x(H[q].x, H[q].y, H[q].z);
    double binom = 1.0;
    for (int i = 1; i <= q; ++i) {
      binom = binom * (q - i + 1) / i;
      x -= binom * H[i].w * C[q - i];
    }
    C.push_back(x / H[0].w);
  }
  return C[r];
}

std::vector<Vec4> homogeneous_bezier_points(const SpaceSpline& spline, const Segment& s) {
  const int d = spline.degree();
  std::vector<Vec4> out;
  std::vector<double> args(d);
  for (int k = 0; k <= d; ++k) {
    for (int i = 0; i < d; ++i) args[i] = i < d - k ? s.a : s.b;
    out.push_back(homogeneous_blossom(spline, s, args.data()));
  }
  return out;
}

std::vector<Vec3> bezier_points(const SpaceSpline& spline, const Segment& s) {
  std::vector<Vec3> out;
  for (const Vec4& h : homogeneous_bezier_points(spline, s)) out.push_back(project(h));
  return out;
}

double space_curvature(const SpaceSpline& spline, double t) {
  const Vec3 d1 = derivative(spline, t, 1), d2 = derivative(spline, t, 2);
  return glm::length(glm::cross(d1, d2)) / std::pow(glm::length(d1), 3);
}

double space_torsion(const SpaceSpline& spline, double t) {
  const Vec3 d1 = derivative(spline, t, 1), d2 = derivative(spline, t, 2);
  const Vec3 d3 = spline.degree() >= 3 ? derivative(spline, t, 3) : Vec3(0.0);
  const Vec3 c = glm::cross(d1, d2);
  return glm::dot(c, d3) / glm::dot(c, c);
}

int spline_dimension(const nlohmann::json& doc) {
  if (!doc.is_object() || !doc.contains("points") || !doc["points"].is_array()) return 2;
  const nlohmann::json& pts = doc["points"];
  int dim = 0;
  std::size_t first = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].is_array() || (pts[i].size() != 2 && pts[i].size() != 3)) continue;  // the reader names it
    const int k = static_cast<int>(pts[i].size());
    if (dim == 0) {
      dim = k;
      first = i;
    } else if (k != dim) {
      throw InputError("points[" + std::to_string(i) + "] has " + std::to_string(k) + " coordinates but points[" +
                       std::to_string(first) + "] has " + std::to_string(dim) +
                       " (all points must be [x, y], or all [x, y, z])");
    }
  }
  return dim == 3 ? 3 : 2;
}

namespace {

nlohmann::json parse_file(const std::filesystem::path& path) {
  const std::string text = read_input_file(path);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    std::string what = e.what();
    const auto pos = what.find("] ");
    if (pos != std::string::npos) what = what.substr(pos + 2);
    throw InputError(input_name(path) + ": malformed JSON: " + what);
  }
}

}  // namespace

int spline_file_dimension(const std::filesystem::path& path) {
  nlohmann::json doc;
  try {
    doc = parse_file(path);
  } catch (const InputError&) {
    return 2;  // the planar reader reports it
  }
  return spline_file_dimension(path, doc);
}

int spline_file_dimension(const std::filesystem::path& path, const nlohmann::json& doc) {
  try {
    return spline_dimension(doc);
  } catch (const InputError& e) {
    throw InputFieldError(input_name(path) + ": " + marked_text(e));
  }
}

SpaceSpline space_spline_from_json(const nlohmann::json& doc, const ReadOptions& options) {
  if (!doc.is_object()) throw InputError("the document is not a JSON object with \"points\"");
  if (doc.contains("weights") && doc["weights"].is_array()) {
    const nlohmann::json& ws = doc["weights"];
    std::vector<double> given;
    for (std::size_t i = 0; i < ws.size(); ++i) given.push_back(ws[i].is_number() ? ws[i].get<double>() : 1.0);
    check_positive(given);  // the planar reader reports everything else about them
  }
  if (!doc.contains("points")) throw InputError("points: missing");
  const nlohmann::json& pts = doc["points"];
  if (!pts.is_array()) throw InputError("points: not an array of [x, y, z] triples");
  nlohmann::json planar = doc;
  std::vector<double> z;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "]";
    if (!pts[i].is_array() || pts[i].size() != 3) throw InputError(where + " is not an [x, y, z] triple");
    const nlohmann::json& v = pts[i][2];
    if (!v.is_number()) throw InputError(where + "[2] is not a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw InputError(where + "[2] is not a finite number");
    z.push_back(x);
    planar["points"][i] = nlohmann::json::array({pts[i][0], pts[i][1]});
  }
  return SpaceSpline::from_shadow(spline_from_json(planar, options), z);
}

SpaceSpline read_space_spline_file(const std::filesystem::path& path, const ReadOptions& options) {
  const nlohmann::json doc = parse_file(path);
  try {
    return space_spline_from_json(doc, options);
  } catch (const InputError& e) {
    throw InputFieldError(input_name(path) + ": " + marked_text(e));
  }
}

nlohmann::json space_spline_to_json(const SpaceSpline& spline) {
  nlohmann::json doc = spline_to_json(spline.shadow());
  nlohmann::json pts = nlohmann::json::array();
  for (int k = 0; k < spline.unique_point_count(); ++k) {
    const Vec3& p = spline.points()[static_cast<std::size_t>(k)];
    pts.push_back({p.x, p.y, p.z});
  }
  doc["points"] = pts;
  return doc;
}

}  // namespace cmr
