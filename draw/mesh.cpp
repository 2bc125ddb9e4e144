// Region meshes, region tubes and their files (contracts: mesh.hpp).
#include "draw/mesh.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

#include "spline/errors.hpp"
#include "draw/draw.hpp"
#include "draw/svg_text.hpp"

namespace cmr::mesh {
namespace {

/// %.17g: every double written reads back as the same double.
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

OpenMesh::VPropHandleT<std::uint8_t> label_property(const Mesh& mesh) {
  OpenMesh::VPropHandleT<std::uint8_t> h;
  if (!mesh.get_property_handle(h, kLabelProperty)) h.reset();
  return h;
}

/// Adds a triangle; the constructions above make every face manifold, so a
/// refusal is a programming error.
void add_triangle(Mesh& mesh, Mesh::VertexHandle a, Mesh::VertexHandle b, Mesh::VertexHandle c) {
  if (!mesh.add_face(a, b, c).is_valid()) throw std::logic_error("mesh: OpenMesh refused a face (non-manifold)");
}

unsigned char byte(double channel) { return static_cast<unsigned char>(std::lround(std::clamp(channel, 0.0, 1.0) * 255)); }

}  // namespace

Mesh region_mesh(const RegionContours& contours) {
  Mesh mesh;
  OpenMesh::VPropHandleT<std::uint8_t> label;
  mesh.add_property(label, kLabelProperty);
  for (const LabelContours& lc : contours.labels) {
    const draw::Rgb c = draw::label_colour(lc.label, contours.split, contours.alternating, contours.each_piece);
    const Mesh::Color colour(byte(c.r), byte(c.g), byte(c.b));
    std::vector<Mesh::VertexHandle> handles;
    handles.reserve(lc.vertices.size());
    for (const Vec2& p : lc.vertices) {
      const auto v = mesh.add_vertex(Mesh::Point(p.x, p.y, 0));
      mesh.property(label, v) = lc.label;
      mesh.set_color(v, colour);
      handles.push_back(v);
    }
    for (const std::vector<int>& piece : lc.pieces)
      for (std::size_t k = 1; k + 1 < piece.size(); ++k)
        add_triangle(mesh, handles[piece[0]], handles[piece[k]], handles[piece[k + 1]]);
  }
  return mesh;
}

std::uint8_t vertex_label(const Mesh& mesh, Mesh::VertexHandle v) {
  const auto h = label_property(mesh);
  return h.is_valid() ? mesh.property(h, v) : 0;
}

double mesh_area(const Mesh& mesh) {
  double area = 0;
  for (const auto f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    const Mesh::Point a = mesh.point(*it++), b = mesh.point(*it++), c = mesh.point(*it);
    area += 0.5 * ((b - a) % (c - a)).norm();
  }
  return area;
}

double mesh_volume(const Mesh& mesh) {
  double six = 0;
  for (const auto f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    const Mesh::Point a = mesh.point(*it++), b = mesh.point(*it++), c = mesh.point(*it);
    six += a | (b % c);
  }
  return six / 6;
}

bool is_closed(const Mesh& mesh) {
  for (const auto h : mesh.halfedges())
    if (mesh.is_boundary(h)) return false;
  return true;
}

Mesh tube_mesh(const VoxelStack& s) {
  const std::size_t K = s.knots.size();
  if (s.width < 1 || s.height < 1 || K < 1 || s.in.size() != static_cast<std::size_t>(s.width) * s.height * K)
    throw InputError("tube_mesh: the voxel stack's size does not match its width, height and knots");
  for (std::size_t k = 1; k < K; ++k)
    if (!(s.knots[k] > s.knots[k - 1])) throw InputError("tube_mesh: the knots must increase");
  const double du = K > 1 ? (s.knots[K - 1] - s.knots[0]) / static_cast<double>(K - 1) : 1.0;
  const double dx = (s.view.x1 - s.view.x0) / s.width, dy = (s.view.y1 - s.view.y0) / s.height;
  // Padded samples (i, j, k), 0 and W+1 (H+1, K+1) the padding.
  const long SW = s.width + 2, SH = s.height + 2, SK = static_cast<long>(K) + 2;
  auto inside = [&](long i, long j, long k) {
    if (i < 1 || j < 1 || k < 1 || i > s.width || j > s.height || k > static_cast<long>(K)) return false;
    return static_cast<bool>(s.in[((k - 1) * s.height + (j - 1)) * static_cast<std::size_t>(s.width) + (i - 1)]);
  };
  auto id = [&](long i, long j, long k) { return (k * SH + j) * SW + i; };
  auto position = [&](long i, long j, long k) {
    // Pixel centres and knots for real samples; one spacing further out for the padding.
    return Mesh::Point(s.view.x0 + dx * (static_cast<double>(i) - 0.5), s.view.y1 - dy * (static_cast<double>(j) - 0.5),
                       s.knots[0] + du * static_cast<double>(k - 1));
  };
  Mesh mesh;
  std::unordered_map<long, Mesh::VertexHandle> on_edge;
  using Sample = std::array<long, 3>;
  auto midpoint = [&](const Sample& a, const Sample& b) {
    const long ia = id(a[0], a[1], a[2]), ib = id(b[0], b[1], b[2]);
    const long key = std::min(ia, ib) * (SW * SH * SK) + std::max(ia, ib);
    auto [it, fresh] = on_edge.try_emplace(key);
    if (fresh) it->second = mesh.add_vertex((position(a[0], a[1], a[2]) + position(b[0], b[1], b[2])) * 0.5);
    return it->second;
  };
  auto oriented = [&](Mesh::VertexHandle a, Mesh::VertexHandle b, Mesh::VertexHandle c, const Mesh::Point& towards_out) {
    const Mesh::Point n = (mesh.point(b) - mesh.point(a)) % (mesh.point(c) - mesh.point(a));
    if ((n | towards_out) < 0) std::swap(b, c);
    add_triangle(mesh, a, b, c);
  };
  static constexpr std::array<std::array<int, 3>, 6> kPermutations = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (long k = 0; k + 1 < SK; ++k)
    for (long j = 0; j + 1 < SH; ++j)
      for (long i = 0; i + 1 < SW; ++i) {
        // Skip cubes whose eight samples agree.
        int count = 0;
        for (int c = 0; c < 8; ++c) count += inside(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        if (count == 0 || count == 8) continue;
        for (const auto& perm : kPermutations) {
          std::array<Sample, 4> t;
          t[0] = {i, j, k};
          for (int step = 0; step < 3; ++step) {
            t[step + 1] = t[step];
            ++t[step + 1][perm[step]];
          }
          std::vector<Sample> in, out;
          for (const Sample& v : t) (inside(v[0], v[1], v[2]) ? in : out).push_back(v);
          if (in.empty() || out.empty()) continue;
          Mesh::Point cin(0, 0, 0), cout(0, 0, 0);
          for (const Sample& v : in) cin += position(v[0], v[1], v[2]) / static_cast<double>(in.size());
          for (const Sample& v : out) cout += position(v[0], v[1], v[2]) / static_cast<double>(out.size());
          const Mesh::Point towards_out = cout - cin;
          if (in.size() == 1 || out.size() == 1) {
            const Sample& odd = in.size() == 1 ? in[0] : out[0];
            const std::vector<Sample>& rest = in.size() == 1 ? out : in;
            oriented(midpoint(odd, rest[0]), midpoint(odd, rest[1]), midpoint(odd, rest[2]), towards_out);
          } else {
            // The quadrilateral in0-out0, in0-out1, in1-out1, in1-out0 (cyclic).
            const auto a = midpoint(in[0], out[0]), b = midpoint(in[0], out[1]), c = midpoint(in[1], out[1]),
                       d = midpoint(in[1], out[0]);
            oriented(a, b, c, towards_out);
            oriented(a, c, d, towards_out);
          }
        }
      }
  return mesh;
}

std::string obj_text(const Mesh& mesh) {
  std::string out = "# cmr region mesh\n";
  for (const auto v : mesh.vertices()) {
    const Mesh::Point p = mesh.point(v);
    out += "v " + num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + "\n";
  }
  const auto label = label_property(mesh);
  int group = -1;
  for (const auto f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    const auto a = *it++, b = *it++, c = *it;
    if (label.is_valid() && mesh.property(label, a) != group) {
      group = mesh.property(label, a);
      out += "g label_" + std::to_string(group) + "\n";
    }
    out += "f " + std::to_string(a.idx() + 1) + " " + std::to_string(b.idx() + 1) + " " + std::to_string(c.idx() + 1) +
           "\n";
  }
  return out;
}

std::string ply_text(const Mesh& mesh) {
  const auto label = label_property(mesh);
  std::string out = "ply\nformat ascii 1.0\ncomment cmr region mesh\nelement vertex " +
                    std::to_string(mesh.n_vertices()) +
                    "\nproperty double x\nproperty double y\nproperty double z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (label.is_valid()) out += "property uchar label\n";
  out += "element face " + std::to_string(mesh.n_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto v : mesh.vertices()) {
    const Mesh::Point p = mesh.point(v);
    const Mesh::Color c = mesh.color(v);
    out += num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + " " + std::to_string(c[0]) + " " + std::to_string(c[1]) +
           " " + std::to_string(c[2]);
    if (label.is_valid()) out.append(" ").append(std::to_string(mesh.property(label, v)));
    out += "\n";
  }
  for (const auto f : mesh.faces()) {
    out += "3";
    for (const auto v : mesh.fv_range(f)) out.append(" ").append(std::to_string(v.idx()));
    out += "\n";
  }
  return out;
}

std::string contours_svg(const RegionContours& rc) {
  const View& v = rc.view;
  const double w = v.x1 - v.x0, h = v.y1 - v.y0;
  // World y up: the SVG's y is -y, so the viewBox starts at -y1.
  std::string out = draw::svg_open({{"width", num(std::max(1.0, 800 * std::min(1.0, w / h)))},
                                    {"height", num(std::max(1.0, 800 * std::min(1.0, h / w)))},
                                    {"viewBox", num(v.x0) + " " + num(-v.y1) + " " + num(w) + " " + num(h)}}) +
                    "\n";
  const double stroke = std::min(w, h) / 800;
  out += "<rect x=\"" + num(v.x0) + "\" y=\"" + num(-v.y1) + "\" width=\"" + num(w) + "\" height=\"" + num(h) +
         "\" fill=\"white\"/>\n";
  for (const LabelContours& lc : rc.labels) {
    const draw::Rgb c = draw::label_colour(lc.label, rc.split, rc.alternating, rc.each_piece);
    const std::string fill = draw::svg_colour(c);
    const std::string name = rc.label_name(lc.label);
    out += "<path data-label=\"" + std::to_string(lc.label) + "\" data-name=\"" + name + "\" data-area=\"" +
           num(lc.area) + "\" fill=\"" + fill + "\" fill-rule=\"nonzero\" stroke=\"black\" stroke-width=\"" +
           num(stroke) + "\" d=\"";
    for (const std::vector<int>& loop : lc.outlines) {
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const Vec2 p = lc.vertices[loop[k]];
        out.append(k == 0 ? "M" : "L").append(num(p.x)).append(" ").append(num(-p.y)).append(" ");
      }
      out += "Z ";
    }
    out += "\"/>\n";
  }
  if (!rc.band.outlines.empty()) {  // undecided at the depth limit, narrower than a pixel
    out += "<path data-label=\"" + std::to_string(rc.band.label) + "\" data-name=\"" + kUndecidedBandName +
           "\" data-area=\"" + num(rc.band.area) + "\" fill=\"#a0a0a0\" fill-rule=\"nonzero\" stroke=\"black\" stroke-width=\"" +
           num(stroke) + "\" d=\"";
    for (const std::vector<int>& loop : rc.band.outlines) {
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const Vec2 p = rc.band.vertices[loop[k]];
        out.append(k == 0 ? "M" : "L").append(num(p.x)).append(" ").append(num(-p.y)).append(" ");
      }
      out += "Z ";
    }
    out += "\"/>\n";
  }
  out.append(draw::kSvgClose).append("\n");
  return out;
}

namespace {
std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}
}  // namespace

void check_contour_file_name(const std::filesystem::path& path, const std::string& option) {
  const std::string ext = lower_extension(path);
  if (ext != ".svg" && ext != ".obj" && ext != ".ply")
    throw InputFieldError(option + " " + path.string() + ": expected a file name ending in .svg, .obj or .ply");
}

std::string contour_file(const std::filesystem::path& path, const RegionContours& contours, const std::string& option) {
  check_contour_file_name(path, option);
  const std::string ext = lower_extension(path);
  if (ext == ".svg") return contours_svg(contours);
  const Mesh mesh = region_mesh(contours);
  return ext == ".obj" ? obj_text(mesh) : ply_text(mesh);
}

}  // namespace cmr::mesh
