#include "tools/edit/model.hpp"

#include <algorithm>
#include <cmath>

#include "spline/errors.hpp"

namespace cmr::edit {

std::vector<int> chain_anchors(const BSpline& spline) {
  // Polar form: point i is f(u_i .. u_{i+d-1}); an interior knot value u of
  // multiplicity d at knot indices j..j+d-1 makes point j = f(u, ..., u), the
  // curve point at the joint, with its handles j-1 and j+1.
  const int d = spline.degree();
  const std::vector<double>& u = spline.knots();
  std::vector<int> anchors;
  for (const Segment& s : spline.segments()) {
    if (s.index == 0) continue;
    const double joint = s.a;
    if (spline.multiplicity(joint) != d) continue;
    const int first = static_cast<int>(std::lower_bound(u.begin(), u.end(), joint) - u.begin());
    if (first >= 1 && first + 1 < spline.point_count()) anchors.push_back(first);
  }
  return anchors;
}

std::optional<HandlePiece> handle_piece(const BSpline& chain, int k) {
  const int d = chain.degree();
  if (k < 0 || k >= chain.point_count() || k % d == 0) return std::nullopt;
  // A Bezier chain of degree d: knots u_0 = ... = u_{d-1}, then each joint d
  // times; piece j is points dj .. dj+d, so handle k lies in piece k / d only.
  const std::vector<double>& u = chain.knots();
  if ((chain.point_count() - 1) % d != 0) return std::nullopt;
  for (std::size_t i = 0; i < u.size(); ++i)
    if (u[i] != u[i / d * d]) return std::nullopt;  // runs of d equal knots
  const int first = k / d * d;
  std::vector<Vec2> pts(chain.points().begin() + first, chain.points().begin() + first + d + 1);
  return HandlePiece{BSpline::bezier(std::move(pts), chain.name()), k - first};
}

namespace {

bool contains(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

}  // namespace

std::vector<int> translation_group(const Document& doc, int k) {
  std::vector<int> g{k};
  auto add = [&](int i) {
    if (i >= 0 && i < doc.spline.point_count() && !contains(g, i)) g.push_back(i);
  };
  if (k == doc.selected) {
    for (int i : doc.group) add(i);
  }
  if (doc.chain && contains(chain_anchors(doc.spline), k)) {
    add(k - 1);
    add(k + 1);
  }
  return g;
}

BSpline move_point(const Document& doc, int k, Vec2 p) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InputError("move: the new position is not finite");
  const std::vector<Vec2>& pts = doc.spline.points();
  const Vec2 delta = p - pts[k];
  BSpline s = doc.spline;
  for (int i : translation_group(doc, k)) s = s.with_point(i, i == k ? p : pts[i] + delta);
  if (!doc.chain) return s;
  // A handle next to an anchor: turn the opposite handle onto the line through
  // the anchor, keeping its distance (G1, Application 1).
  for (int anchor : chain_anchors(doc.spline)) {
    if (k != anchor - 1 && k != anchor + 1) continue;
    if (contains(translation_group(doc, k), anchor)) continue;  // moved rigidly with it
    const int other = k == anchor - 1 ? anchor + 1 : anchor - 1;
    const Vec2 a = s.points()[anchor];
    const Vec2 dir = a - s.points()[k];
    const double len = std::hypot(dir.x, dir.y);
    const Vec2 old = s.points()[other] - a;
    const double keep = std::hypot(old.x, old.y);
    if (len > 0) s = s.with_point(other, a + dir * (keep / len));
  }
  return s;
}

Vec2 Viewport::to_world(double px, double py) const {
  return {view.x0 + (view.x1 - view.x0) * px / width, view.y1 - (view.y1 - view.y0) * py / height};
}

Vec2 Viewport::to_screen(Vec2 w) const {
  return {(w.x - view.x0) / (view.x1 - view.x0) * width, (view.y1 - w.y) / (view.y1 - view.y0) * height};
}

Viewport Viewport::fit(const BSpline& spline, int w, int h, int canvas_w, int canvas_h) {
  canvas_w = std::clamp(canvas_w, 1, w);
  canvas_h = std::clamp(canvas_h, 1, h);
  return Viewport{default_view(spline, canvas_w, canvas_h), canvas_w, canvas_h}.resized(w, h);
}

Viewport Viewport::resized(int w, int h) const {
  const double sx = (view.x1 - view.x0) / width, sy = (view.y1 - view.y0) / height;
  return {{view.x0, view.y1 - sy * h, view.x0 + sx * w, view.y1}, w, h};
}

Viewport Viewport::panned(double dx, double dy) const {
  const double wx = -dx * (view.x1 - view.x0) / width, wy = dy * (view.y1 - view.y0) / height;
  return {{view.x0 + wx, view.y0 + wy, view.x1 + wx, view.y1 + wy}, width, height};
}

Viewport Viewport::zoomed(double factor, double px, double py) const {
  const Vec2 c = to_world(px, py);
  const double s = 1.0 / factor;
  return {{c.x + (view.x0 - c.x) * s, c.y + (view.y0 - c.y) * s, c.x + (view.x1 - c.x) * s,
           c.y + (view.y1 - c.y) * s},
          width,
          height};
}

void History::commit(Document next, const std::string& merge_key) {
  const bool merge = !merge_key.empty() && merge_key == merge_key_;
  if (!merge) undo_.push_back(current_);
  current_ = std::move(next);
  redo_.clear();
  merge_key_ = merge_key;
  ++changes_;
}

bool History::undo() {
  if (undo_.empty()) return false;
  redo_.push_back(std::move(current_));
  current_ = std::move(undo_.back());
  undo_.pop_back();
  merge_key_.clear();
  ++changes_;
  return true;
}

bool History::redo() {
  if (redo_.empty()) return false;
  undo_.push_back(std::move(current_));
  current_ = std::move(redo_.back());
  redo_.pop_back();
  merge_key_.clear();
  ++changes_;
  return true;
}

}  // namespace cmr::edit
