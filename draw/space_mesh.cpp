// The tube and plane patch of a space region (contracts: space_mesh.hpp).
#include "draw/space_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <tuple>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "draw/draw.hpp"
#include "spline/errors.hpp"

namespace cmr::mesh {
namespace {

OpenMesh::VPropHandleT<std::uint8_t> labels_of(Mesh& mesh) {
  OpenMesh::VPropHandleT<std::uint8_t> h;
  if (!mesh.get_property_handle(h, kLabelProperty)) mesh.add_property(h, kLabelProperty);
  return h;
}

Mesh::Point pt(const Vec3& p) { return Mesh::Point(p.x, p.y, p.z); }

unsigned char byte(double channel) { return static_cast<unsigned char>(std::lround(std::clamp(channel, 0.0, 1.0) * 255)); }

void add_face(Mesh& mesh, Mesh::VertexHandle a, Mesh::VertexHandle b, Mesh::VertexHandle c) {
  if (!mesh.add_face(a, b, c).is_valid()) throw std::logic_error("mesh: OpenMesh refused a face (non-manifold)");
}

// The unit tangent at t (the first non-zero derivative: a cusp has none of order 1).
Vec3 tangent(const SpaceSpline& s, double t) {
  for (int r = 1; r <= s.degree(); ++r) {
    const Vec3 d = derivative(s, t, r);
    const double n = glm::length(d);
    if (n > 0 && std::isfinite(n)) return d / n;
  }
  return {1, 0, 0};
}

double turn(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)); }

void refine(const SpaceSpline& s, double a, double b, double max_turn, int depth, std::vector<double>& out) {
  const double m = 0.5 * (a + b);
  const Vec3 ta = tangent(s, a), tm = tangent(s, m), tb = tangent(s, b);
  if (depth < 12 && (turn(ta, tm) > max_turn || turn(tm, tb) > max_turn)) {
    refine(s, a, m, max_turn, depth + 1, out);
    refine(s, m, b, max_turn, depth + 1, out);
    return;
  }
  out.push_back(m);
  out.push_back(b);
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

double default_tube_radius(const SpaceSpline& spline) {
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& p : spline.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double d = glm::length(hi - lo);
  return d > 0 && std::isfinite(d) ? 0.004 * d : 1e-3;
}

std::vector<double> tube_parameters(const SpaceSpline& spline, double max_turn) {
  std::vector<double> t{spline.domain_begin()};
  for (const Segment& seg : spline.segments())
    if (seg.b > seg.a) refine(spline, seg.a, seg.b, max_turn, 0, t);
  return t;
}

Mesh curve_tube(const SpaceSpline& spline, const TubeOptions& o) {
  if (!(o.radius > 0) || !std::isfinite(o.radius))
    throw InputFieldError(field("radius") + ": must be a positive number (got " + std::to_string(o.radius) + ")");
  if (o.sides < 3) throw InputError("tube: at least 3 sides (got " + std::to_string(o.sides) + ")");
  std::vector<double> ts = tube_parameters(spline, o.max_turn);
  std::vector<Vec3> c, tan, nor;
  for (double t : ts) c.push_back(evaluate(spline, t)), tan.push_back(tangent(spline, t));
  // The first normal: the axis least aligned with the tangent, made normal.
  Vec3 axis{1, 0, 0};
  if (std::abs(tan[0].y) < std::abs(tan[0][0]) && std::abs(tan[0].y) <= std::abs(tan[0].z)) axis = {0, 1, 0};
  else if (std::abs(tan[0].z) < std::abs(tan[0][0])) axis = {0, 0, 1};
  nor.push_back(glm::normalize(axis - glm::dot(axis, tan[0]) * tan[0]));
  for (std::size_t k = 0; k + 1 < ts.size(); ++k) {  // double reflection
    const Vec3 v1 = c[k + 1] - c[k];
    const double c1 = glm::dot(v1, v1);
    Vec3 rl = nor[k], tl = tan[k];
    if (c1 > 0) {
      rl = nor[k] - (2 / c1) * glm::dot(v1, nor[k]) * v1;
      tl = tan[k] - (2 / c1) * glm::dot(v1, tan[k]) * v1;
    }
    const Vec3 v2 = tan[k + 1] - tl;
    const double c2 = glm::dot(v2, v2);
    Vec3 r = c2 > 0 ? rl - (2 / c2) * glm::dot(v2, rl) * v2 : rl;
    r -= glm::dot(r, tan[k + 1]) * tan[k + 1];
    nor.push_back(glm::length(r) > 0 ? glm::normalize(r) : nor[k]);
  }
  const bool loop = spline.closed() && ts.size() > 2;
  double twist = 0;  // the angle from the carried first frame back to the first frame
  if (loop) {
    ts.pop_back(), c.pop_back(), tan.pop_back();
    const Vec3 last = nor.back();
    nor.pop_back();
    const Vec3 b0 = glm::cross(tan[0], nor[0]);
    twist = std::atan2(glm::dot(last, b0), glm::dot(last, nor[0]));
  }
  Mesh mesh;
  const auto label = labels_of(mesh);
  const Mesh::Color grey(64, 64, 64);
  const auto vertex = [&](const Vec3& p) {
    const auto v = mesh.add_vertex(pt(p));
    mesh.set_color(v, grey);
    mesh.property(label, v) = kTubeLabel;
    return v;
  };
  const std::size_t n = ts.size(), sides = static_cast<std::size_t>(o.sides);
  std::vector<Mesh::VertexHandle> ring;
  for (std::size_t k = 0; k < n; ++k) {
    const double undo = loop ? -twist * static_cast<double>(k) / static_cast<double>(n) : 0;
    const Vec3 b = glm::cross(tan[k], nor[k]);
    const Vec3 nk = std::cos(undo) * nor[k] + std::sin(undo) * b, bk = glm::cross(tan[k], nk);
    for (std::size_t s = 0; s < sides; ++s) {
      const double a = 2 * M_PI * static_cast<double>(s) / static_cast<double>(sides);
      ring.push_back(vertex(c[k] + o.radius * (std::cos(a) * nk + std::sin(a) * bk)));
    }
  }
  const auto at = [&](std::size_t k, std::size_t s) { return ring[(k % n) * sides + s % sides]; };
  for (std::size_t k = 0; k + 1 < n + (loop ? 1 : 0); ++k)
    for (std::size_t s = 0; s < sides; ++s) {
      add_face(mesh, at(k, s), at(k, s + 1), at(k + 1, s + 1));
      add_face(mesh, at(k, s), at(k + 1, s + 1), at(k + 1, s));
    }
  if (!loop) {  // end caps: fans around the curve's end points
    const auto first = vertex(c.front()), last = vertex(c.back());
    for (std::size_t s = 0; s < sides; ++s) {
      add_face(mesh, first, at(0, s + 1), at(0, s));
      add_face(mesh, last, at(n - 1, s), at(n - 1, s + 1));
    }
  }
  return mesh;
}

Mesh plane_patch(const RegionResult& img, const SpacePlane& plane) {
  Mesh mesh;
  const auto label = labels_of(mesh);
  const View& v = img.view;
  const int w = img.width, h = img.height;
  const auto corner = [&](int i, int j) {  // the corner left of column i, above row j
    const double a = v.x0 + ((v.x1 - v.x0) * i) / w, b = v.y1 - ((v.y1 - v.y0) * j) / h;
    return plane.origin + a * plane.u + b * plane.v;
  };
  struct Rect {
    int i0, i1, j0, j1;
    std::uint8_t code;
  };
  std::vector<Rect> rects;
  std::map<std::tuple<int, int, std::uint8_t>, std::size_t> open;  // runs of the row above
  for (int j = 0; j < h; ++j) {
    std::map<std::tuple<int, int, std::uint8_t>, std::size_t> next;
    for (int i = 0; i < w;) {
      const std::uint8_t code = img.code_at(static_cast<std::size_t>(j) * w + i);
      int e = i + 1;
      while (e < w && img.code_at(static_cast<std::size_t>(j) * w + e) == code) ++e;
      const auto key = std::make_tuple(i, e, code);
      const auto it = open.find(key);
      if (it != open.end()) {
        rects[it->second].j1 = j + 1;
        next[key] = it->second;
      } else {
        next[key] = rects.size();
        rects.push_back({i, e, j, j + 1, code});
      }
      i = e;
    }
    open = std::move(next);
  }
  for (const Rect& r : rects) {
    const draw::Rgb rgb = draw::label_colour(r.code, false);
    const Mesh::Color colour(byte(rgb.r), byte(rgb.g), byte(rgb.b));
    Mesh::VertexHandle q[4];
    const Vec3 p[4] = {corner(r.i0, r.j1), corner(r.i1, r.j1), corner(r.i1, r.j0), corner(r.i0, r.j0)};
    for (int k = 0; k < 4; ++k) {
      q[k] = mesh.add_vertex(pt(p[k]));
      mesh.set_color(q[k], colour);
      mesh.property(label, q[k]) = r.code;
    }
    add_face(mesh, q[0], q[1], q[2]);
    add_face(mesh, q[0], q[2], q[3]);
  }
  return mesh;
}

void append(Mesh& mesh, const Mesh& part) {
  const auto label = labels_of(mesh);
  OpenMesh::VPropHandleT<std::uint8_t> from;
  const bool labelled = part.get_property_handle(from, kLabelProperty);
  std::vector<Mesh::VertexHandle> map;
  map.reserve(part.n_vertices());
  for (const auto v : part.vertices()) {
    const auto n = mesh.add_vertex(part.point(v));
    mesh.set_color(n, part.color(v));
    mesh.property(label, n) = labelled ? part.property(from, v) : 0;
    map.push_back(n);
  }
  for (const auto f : part.faces()) {
    auto it = part.cfv_iter(f);
    const auto a = *it++, b = *it++, c = *it;
    add_face(mesh, map[static_cast<std::size_t>(a.idx())], map[static_cast<std::size_t>(b.idx())],
             map[static_cast<std::size_t>(c.idx())]);
  }
}

void check_mesh_file_name(const std::filesystem::path& path, const std::string& option) {
  const std::string ext = lower_extension(path);
  if (ext != ".obj" && ext != ".ply")
    throw InputFieldError(option + " " + path.string() + ": expected a file name ending in .obj or .ply");
}

std::string mesh_file(const std::filesystem::path& path, const Mesh& mesh, const std::string& option) {
  check_mesh_file_name(path, option);
  return lower_extension(path) == ".obj" ? obj_text(mesh) : ply_text(mesh);
}

}  // namespace cmr::mesh
