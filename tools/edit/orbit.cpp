#include "tools/edit/orbit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "design/space_fix.hpp"
#include "io/output.hpp"
#include "spline/errors.hpp"
#include "tools/field_flags.hpp"

namespace cmr::edit {

bool OrbitProjection::to_screen(const Vec3& q, Vec2& s) const {
  const Vec3 d = q - eye;
  const double depth = glm::dot(d, forward);
  if (!(depth > 1e-12)) return false;
  s = {cx + focal * glm::dot(d, right) / depth, cy - focal * glm::dot(d, up) / depth};
  return true;
}

Vec3 OrbitProjection::ray(Vec2 s) const { return forward + ((s.x - cx) / focal) * right - ((s.y - cy) / focal) * up; }

OrbitProjection orbit_projection(const OrbitCamera& c, int width, int height) {
  OrbitProjection p;
  const Vec3 dir{std::cos(c.pitch) * std::cos(c.yaw), std::cos(c.pitch) * std::sin(c.yaw), std::sin(c.pitch)};
  p.eye = c.target + c.distance * dir;
  p.forward = -dir;
  Vec3 r = glm::cross(p.forward, Vec3{0, 0, 1});
  if (glm::length(r) < 1e-12) r = Vec3{1, 0, 0};  // looking straight down or up
  p.right = glm::normalize(r);
  p.up = glm::cross(p.right, p.forward);
  p.focal = 0.5 * std::max(1, height) / std::tan(0.5 * c.fov);
  p.cx = 0.5 * width;
  p.cy = 0.5 * height;
  return p;
}

OrbitPlane parse_orbit_plane(const std::string& text) {
  if (text == "region") return OrbitPlane::region;
  if (text == "screen") return OrbitPlane::screen;
  if (text == "xy") return OrbitPlane::xy;
  if (text == "yz") return OrbitPlane::yz;
  if (text == "zx") return OrbitPlane::zx;
  throw InputError("plane: expected region, screen, xy, yz or zx (got '" + text + "')");
}

const char* orbit_plane_name(OrbitPlane p) {
  switch (p) {
    case OrbitPlane::region: return "region";
    case OrbitPlane::screen: return "screen";
    case OrbitPlane::xy: return "xy";
    case OrbitPlane::yz: return "yz";
    case OrbitPlane::zx: return "zx";
  }
  return "region";
}

namespace {

OrbitRegion compute_region(const SpaceSpline& spline, int k, const SpacePlane& plane, int size) {
  const auto start = std::chrono::steady_clock::now();
  SpaceRegionRequest r;
  r.point = k;
  r.plane = plane;
  r.width = r.height = size;
  const SpaceRegionProblem problem = SpaceRegionProblem::make(spline, r);
  RegionResult res = problem.render(0);
  OrbitRegion out;
  out.point = k;
  out.plane = plane;
  out.view = res.view;
  out.width = res.width;
  out.height = res.height;
  out.labels = std::move(res.labels);
  out.full = size >= OrbitView::kFullRegion;
  if (out.full) {  // a small region: again over its box
    int i0 = size, i1 = -1, j0 = size, j1 = -1;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const Direction d = out.labels[static_cast<std::size_t>(j) * size + i];
        if (d == Direction::increasing || d == Direction::decreasing)
          i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
      }
    i0 = std::max(0, i0 - 2), j0 = std::max(0, j0 - 2), i1 = std::min(size - 1, i1 + 2), j1 = std::min(size - 1, j1 + 2);
    const int bw = i1 - i0 + 1, bh = j1 - j0 + 1;
    if (i1 >= i0 && 4 * bw * bh < size * size) {
      const View& v = out.view;
      const double da = (v.x1 - v.x0) / size, db = (v.y1 - v.y0) / size;
      out.detail_view = View{v.x0 + da * i0, v.y1 - db * (j1 + 1), v.x0 + da * (i1 + 1), v.y1 - db * j0};
      const int longer = std::max(bw, bh);
      out.detail_width = std::max(1, size * bw / longer);
      out.detail_height = std::max(1, size * bh / longer);
      r.view = out.detail_view;
      r.width = out.detail_width;
      r.height = out.detail_height;
      out.detail = SpaceRegionProblem::make(spline, r).render(0).labels;
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

OrbitView::OrbitView(SpaceSpline spline, std::filesystem::path path, int width, int height)
    : spline_(std::move(spline)), path_(std::move(path)), width_(width), height_(height) {
  analyse();
  fit();
  reset_plane();
}

OrbitView::~OrbitView() {
  if (pending_.valid()) pending_.wait();
  for (auto& f : stale_) f.wait();
}

void OrbitView::resize(int w, int h) {
  width_ = w;
  height_ = h;
}

void OrbitView::analyse() {
  SpaceAnalyzeOptions o;
  o.torsion = true;
  analysis_ = analyze_space(spline_, o);
  samples_.clear();
  kappa_min_ = 1e300;
  kappa_max_ = 0;
  tau_max_ = 0;
  for (const Segment& seg : spline_.segments())
    for (int i = 0; i <= kSamples; ++i) {
      CurveSample c;
      c.t = seg.a + (seg.b - seg.a) * i / kSamples;
      c.p = evaluate(spline_, c.t);
      c.kappa = space_curvature(spline_, c.t);
      c.tau = space_torsion(spline_, c.t);
      if (!std::isfinite(c.kappa)) c.kappa = 0;
      if (!std::isfinite(c.tau)) c.tau = 0;
      kappa_min_ = std::min(kappa_min_, c.kappa);
      kappa_max_ = std::max(kappa_max_, c.kappa);
      tau_max_ = std::max(tau_max_, std::abs(c.tau));
      samples_.push_back(c);
    }
  if (samples_.empty()) kappa_min_ = 0;
  extrema_.clear();
  for (const Segment& seg : spline_.segments())
    for (const SpaceExtremum& e : space_curvature_extrema(spline_, seg))
      extrema_.push_back({evaluate(spline_, e.t), e.t, space_curvature(spline_, e.t), e.maximum});
  Vec3 lo{1e300}, hi{-1e300};
  for (const Vec3& p : spline_.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double diag = glm::length(hi - lo);
  const double scale = kappa_max_ > 0 ? comb_size * 0.2 * diag / kappa_max_ : 0;
  for (CurveSample& c : samples_) {
    const Vec3 d1 = derivative(spline_, c.t, 1), d2 = derivative(spline_, c.t, 2);
    const Vec3 n = glm::cross(glm::cross(d1, d2), d1);
    const double len = glm::length(n);
    c.comb = len > 0 && std::isfinite(len) ? c.p + (c.kappa * scale / len) * n : c.p;
  }
}

void OrbitView::fit() {
  Vec3 lo{1e300}, hi{-1e300};
  for (const Vec3& p : spline_.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
  camera.target = 0.5 * (lo + hi);
  const double radius = std::max(1e-9, 0.5 * glm::length(hi - lo));
  // The narrower of the vertical and horizontal half-angles of the canvas.
  const double aspect = std::max(1, width_ - panel_width) / static_cast<double>(std::max(1, height_));
  const double half = std::min(0.5 * camera.fov, std::atan(std::tan(0.5 * camera.fov) * aspect));
  camera.distance = 1.05 * radius / std::sin(half);
}

void OrbitView::orbit(double yaw_deg, double pitch_deg) {
  camera.yaw = yaw_deg * M_PI / 180;
  camera.pitch = std::clamp(pitch_deg, -89.0, 89.0) * M_PI / 180;
}

void OrbitView::face_plane() {
  if (plane_) {
    Vec3 n = glm::cross(plane_->u, plane_->v);
    if (n.z < 0) n = -n;
    const double len = glm::length(n);
    if (len > 0) {
      n /= len;
      const double pitch = std::clamp(std::asin(std::clamp(n.z, -1.0, 1.0)) * 180 / M_PI, 20.0, 65.0);
      const double yaw = std::hypot(n.x, n.y) > 1e-9 ? std::atan2(n.y, n.x) * 180 / M_PI : camera.yaw * 180 / M_PI;
      orbit(yaw, pitch);
    }
  }
  fit();
}

void OrbitView::zoom(double f) {
  if (!(f > 0) || !std::isfinite(f)) throw InputError("zoom: the factor must be a positive number");
  camera.distance /= f;
}

void OrbitView::pan(double dx, double dy) {
  const OrbitProjection p = projection();
  const double per_pixel = camera.distance / p.focal;
  camera.target -= (dx * per_pixel) * p.right - (dy * per_pixel) * p.up;
}

int OrbitView::pick(Vec2 s) const {
  const OrbitProjection p = projection();
  int best = -1;
  double best_d = 9;
  for (int k = 0; k < spline_.unique_point_count(); ++k) {
    Vec2 q;
    if (!p.to_screen(spline_.points()[k], q)) continue;
    const double d = std::hypot(q.x - s.x, q.y - s.y);
    if (d <= best_d) best_d = d, best = k;
  }
  return best;
}

void OrbitView::mouse_move(double x, double y) {
  const Vec2 now{x, y};
  const Vec2 d = now - last_;
  last_ = now;
  if (!held_) return;
  if (dragging_ >= 0) {
    move_to_screen(now);
  } else if (*held_ == MouseButton::left) {
    camera.yaw -= d.x * 0.3 * M_PI / 180;
    camera.pitch = std::clamp(camera.pitch + d.y * 0.3 * M_PI / 180, -89 * M_PI / 180, 89 * M_PI / 180);
  } else {
    pan(d.x, d.y);
  }
}

void OrbitView::mouse_button(MouseButton button, bool down) {
  if (!down) {
    if (held_ && *held_ == button) {
      held_.reset();
      if (dragging_ >= 0) {
        dragging_ = -1;
        if (drag_start_ && drag_start_->points() != spline_.points()) undo_.push_back(*drag_start_), redo_.clear();
        drag_start_.reset();
      }
    }
    return;
  }
  if (held_) return;
  held_ = button;
  if (button != MouseButton::left) return;
  const int k = pick(last_);
  if (k < 0) return;
  if (k != selected_) select(k);
  if (plane_kind_ == OrbitPlane::screen && plane_) {  // the screen plane of the view the drag starts in
    const OrbitProjection p = projection();
    if (plane_->u != p.right || plane_->v != p.up) reset_plane();
  }
  if (plane_) {
    dragging_ = k;
    drag_start_ = spline_;
  }
}

void OrbitView::scroll(double dy) { camera.distance /= std::pow(1.1, dy); }

void OrbitView::select(int k) {
  if (k < 0 || k >= spline_.unique_point_count())
    throw InputError("select: no point " + std::to_string(k) + " (0.." + std::to_string(spline_.unique_point_count() - 1) + ")");
  selected_ = k;
  reset_plane();
}

void OrbitView::open_on_region_point(std::optional<int> point) {
  const int m = spline_.unique_point_count();
  if (point) {
    if (*point < 0 || *point >= m)
      throw InputError("--point: no point " + std::to_string(*point) + " (0.." + std::to_string(m - 1) + ")");
    select(*point);
    message = "opened on P" + std::to_string(*point);
    return;
  }
  int best = 0;
  long best_count = -1;
  bool timed_out = false;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < m; ++k) {
    if (std::chrono::steady_clock::now() - start > std::chrono::seconds(3)) {  // high degrees: each region is slow
      timed_out = true;
      break;
    }
    long count = 0;
    try {
      const OrbitRegion r = compute_region(spline_, k, default_space_plane(spline_, k), kLowRegion);
      count = std::count_if(r.labels.begin(), r.labels.end(),
                            [](Direction d) { return d == Direction::increasing || d == Direction::decreasing; });
    } catch (const InputError&) {
      continue;  // a degenerate plane: no region
    }
    if (count > best_count) best = k, best_count = count;
    if (count >= 4) break;
  }
  select(best);
  message = "opened on P" + std::to_string(best) +
            (best_count >= 4 ? ": the first point whose region shows in its plane"
             : timed_out     ? ": the largest region of the points tried in 3 s (--point K opens another)"
                             : ": no point has a region of 4 pixels in its plane's default view");
}

void OrbitView::set_plane_kind(OrbitPlane p) {
  plane_kind_ = p;
  reset_plane();
}

void OrbitView::reset_plane() {
  const Vec3 through = spline_.points()[selected_];
  plane_.reset();
  try {
    switch (plane_kind_) {
      case OrbitPlane::region: plane_ = default_space_plane(spline_, selected_); break;
      case OrbitPlane::screen: {
        const OrbitProjection p = projection();
        plane_ = SpacePlane{through, p.right, p.up};
        break;
      }
      default: plane_ = parse_space_plane(orbit_plane_name(plane_kind_), through); break;
    }
  } catch (const InputError& e) {
    message = std::string("P") + std::to_string(selected_) + " has no plane: " + cli::shown_message(e);
  }
  ++generation_;
  region_.reset();
  update_label();
}

Vec2 OrbitView::plane_coordinates(const Vec3& q) const {
  if (!plane_) return {0.0, 0.0};
  const Vec3 d = q - plane_->origin, &u = plane_->u, &v = plane_->v;
  const double uu = glm::dot(u, u), uv = glm::dot(u, v), vv = glm::dot(v, v);
  const double du = glm::dot(u, d), dv = glm::dot(v, d);
  const double det = uu * vv - uv * uv;
  return {(du * vv - dv * uv) / det, (dv * uu - du * uv) / det};
}

Vec3 OrbitView::plane_point(double a, double b) const {
  if (!plane_) return spline_.points()[selected_];
  return plane_->origin + a * plane_->u + b * plane_->v;
}

bool OrbitView::move_to_screen(Vec2 s) {
  if (!plane_) return false;
  const OrbitProjection p = projection();
  const Vec3 r = p.ray(s), n = glm::cross(plane_->u, plane_->v);
  const double rn = glm::dot(r, n);
  if (std::abs(rn) < 1e-9 * glm::length(r) * glm::length(n)) return false;
  const double t = glm::dot(plane_->origin - p.eye, n) / rn;
  if (!(t > 0)) return false;
  const Vec2 ab = plane_coordinates(p.eye + t * r);
  move_in_plane(ab.x, ab.y);
  return true;
}

void OrbitView::move_in_plane(double a, double b) {
  const Vec3 q = plane_point(a, b);
  if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) return;
  set_spline(spline_.with_point(selected_, q), false);
}

void OrbitView::set_spline(SpaceSpline s, bool others_changed) {
  spline_ = std::move(s);
  analyse();
  if (others_changed) reset_plane();
  else update_label();
}

void OrbitView::update_label() {
  label_here_ = Direction::undecided;
  if (!plane_) return;
  try {
    SpaceRegionRequest r;
    r.point = selected_;
    r.plane = *plane_;
    r.width = r.height = 1;
    r.view = View{-1, -1, 1, 1};  // classify does not read the view
    const Vec2 ab = plane_coordinates(spline_.points()[selected_]);
    label_here_ = SpaceRegionProblem::make(spline_, r).classify(ab.x, ab.y).label;
  } catch (const InputError& e) {
    message = cli::shown_message(e);
  }
}

void OrbitView::start_full_region() {
  if (pending_.valid()) stale_.push_back(std::move(pending_));
  pending_generation_ = generation_;
  pending_ = std::async(std::launch::async, [s = spline_, k = selected_, pl = *plane_]() {
    return compute_region(s, k, pl, kFullRegion);
  });
}

const OrbitRegion* OrbitView::region() {
  if (!plane_ || !show_region) return nullptr;
  const auto ready = [](const std::future<OrbitRegion>& f) {
    return f.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
  };
  stale_.erase(std::remove_if(stale_.begin(), stale_.end(), ready), stale_.end());
  if (pending_.valid() && ready(pending_)) {
    OrbitRegion r = pending_.get();
    if (pending_generation_ == generation_ && region_) region_ = std::move(r);
  }
  if (!region_) {
    try {
      region_ = compute_region(spline_, selected_, *plane_, kLowRegion);
      start_full_region();
    } catch (const InputError& e) {
      message = cli::shown_message(e);
      return nullptr;
    }
  }
  return &*region_;
}

void OrbitView::settle() {
  if (!region()) return;
  if (pending_.valid()) {
    pending_.wait();
    (void)region();
  }
  for (auto& f : stale_) f.wait();
  stale_.clear();
}

void OrbitView::fix() {
  SpaceFixRequest r;
  r.time_limit = 5;
  try {
    const SpaceFixResult f = space_fix(spline_, r);
    if (f.already) {
      message = "fix (cmrwi): |kappa| is already monotone; nothing moves";
    } else if (!f.fixed || !f.spline || f.moves.empty()) {
      message =
          "fix (cmrwi): " + (f.reason.empty() ? std::string("no certified fix found") : cli::show_fields(f.reason));
    } else {
      undo_.push_back(spline_);
      redo_.clear();
      const SpacePointMove& m = f.moves[0];
      set_spline(*f.spline, true);
      char buf[200];
      std::snprintf(buf, sizeof buf, "fix (cmrwi): moved P%d by %.6g (%.2f%% of the curve size); certified by analyze",
                    m.point, m.distance, f.size > 0 ? 100 * m.distance / f.size : 0.0);
      message = buf;
    }
  } catch (const InputError& e) {
    message = std::string("fix: ") + cli::shown_message(e);
  }
}

void OrbitView::undo() {
  if (undo_.empty()) return;
  redo_.push_back(spline_);
  SpaceSpline s = undo_.back();
  undo_.pop_back();
  set_spline(std::move(s), true);
}

void OrbitView::redo() {
  if (redo_.empty()) return;
  undo_.push_back(spline_);
  SpaceSpline s = redo_.back();
  redo_.pop_back();
  set_spline(std::move(s), true);
}

void OrbitView::save(const std::filesystem::path& p) {
  write_file_atomic(p, space_spline_to_json(spline_).dump(1) + "\n");
  message = "saved " + p.string();
}

void orbit_key(OrbitView& v, const std::string& name, bool ctrl) {
  if (ctrl && name == "z") v.undo();
  else if (ctrl && name == "y") v.redo();
  else if (name == "f") v.fit();
  else if (name == "x") v.fix();
  else if (name == "c") v.comb = !v.comb;
}

}  // namespace cmr::edit
