// Masters and the pieces where points move affinely (io/masters.hpp).
#include "io/masters.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/format.hpp"

namespace cmr::import {
namespace fs = std::filesystem;

namespace {

std::string num(double v) { return format_number(v, 7); }

}  // namespace

// ------------------------------------------------------------ pieces

double PieceAxis::user(double s) const {
  if (at.empty()) return 0;
  if (at.size() == 1 || s <= at.front().first) return at.front().second;
  for (std::size_t k = 1; k < at.size(); ++k)
    if (s <= at[k].first) {
      const auto [s0, u0] = at[k - 1];
      const auto [s1, u1] = at[k];
      return s1 == s0 ? u1 : u0 + (s - s0) * (u1 - u0) / (s1 - s0);
    }
  return at.back().second;
}

bool PieceAxis::varies() const {
  return std::any_of(at.begin(), at.end(), [&](const auto& p) { return p.second != at.front().second; });
}

std::string Piece::location(double s) const {
  std::string out;
  for (int pass = 0; pass < 2; ++pass)
    for (const PieceAxis& a : axes) {
      if (a.varies() != (pass == 0)) continue;
      if (!out.empty()) out += ", ";
      out += "\"";
      out += a.name;
      out += "\": ";
      out += num(a.user(s));
    }
  return out;
}

std::string Piece::range(double sa, double sb) const {
  std::string out;
  for (const PieceAxis& a : axes) {
    if (!a.varies()) continue;
    double u0 = a.user(sa), u1 = a.user(sb);
    if (u0 > u1) std::swap(u0, u1);
    if (!out.empty()) out += ", ";
    out += a.name;
    out += " in (";
    out += num(u0);
    out += ", ";
    out += num(u1);
    out += ")";
  }
  return out;
}

Segment2 parse_between(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || text.find(':', colon + 1) != std::string::npos)
    throw InputFieldError(field("between") + ": '" + text + "' is not LOC1:LOC2 (wght=400:wght=700)");
  auto part = [&](const std::string& t) {
    try {
      return parse_location(t);
    } catch (const InputError& e) {
      std::string m = marked_text(e);
      const std::string location = field("location");
      if (m.rfind(location, 0) == 0) m.replace(0, location.size(), field("between"));
      throw InputFieldError(m);
    }
  };
  return {part(text.substr(0, colon)), part(text.substr(colon + 1))};
}

namespace {

/// An axis of a design space as the pieces need it: user range and default,
/// and the maps between user values and the coordinate that the instances
/// are affine in (a designspace: design values; a variable font:
/// normalised values after avar).
struct SpaceAxis {
  std::string tag, name;
  double minimum = 0, maximum = 0, default_value = 0;  // user
  std::function<double(double)> to_coord, to_user;
  std::vector<double> coord_breaks;  // coordinates where to_user has a break (map points)
};

/// The user values of axis `ax` along a line from coordinate c0 (s = 0) to
/// c1 (s = 1) of that axis.
PieceAxis piece_axis(const SpaceAxis& ax, double c0, double c1) {
  PieceAxis p;
  p.name = ax.name;
  p.tag = ax.tag;
  p.at.emplace_back(0.0, ax.to_user(c0));
  if (c0 != c1) {
    std::vector<double> inner;
    for (double b : ax.coord_breaks)
      if ((b - c0) * (b - c1) < 0) inner.push_back((b - c0) / (c1 - c0));
    std::sort(inner.begin(), inner.end());
    for (double s : inner) p.at.emplace_back(s, ax.to_user(c0 + s * (c1 - c0)));
    p.at.emplace_back(1.0, ax.to_user(c1));
  }
  return p;
}

/// A location given by tags and user values as coordinates (unnamed axes at
/// their defaults), checked against the axes.
std::vector<double> coordinates(const Location& loc, const std::vector<SpaceAxis>& axes, const std::string& file) {
  std::vector<double> out;
  for (const SpaceAxis& a : axes) out.push_back(a.to_coord(a.default_value));
  for (const auto& [tag, value] : loc) {
    std::size_t k = 0;
    while (k < axes.size() && axes[k].tag != tag) ++k;
    if (k == axes.size()) {
      std::string have;
      for (const SpaceAxis& a : axes) have += (have.empty() ? "" : ", ") + a.tag;
      throw InputFieldError(file + ": " + field("between") + ": no axis '" + tag + "' (the axes: " + have + ")");
    }
    const SpaceAxis& a = axes[k];
    if (value < a.minimum || value > a.maximum)
      throw InputFieldError(file + ": " + field("between") + ": " + tag + "=" + num(value) +
                            " is outside the axis's range [" + num(a.minimum) + ", " + num(a.maximum) + "]");
    out[k] = a.to_coord(value);
  }
  return out;
}

std::string location_text(const Location& loc) {
  std::string out;
  for (const auto& [tag, v] : loc) out += (out.empty() ? "" : ",") + tag + "=" + num(v);
  return out.empty() ? "default" : out;
}

/// The axis two coordinate vectors differ in (-1: none or several).
int varying_axis(const std::vector<double>& a, const std::vector<double>& b) {
  int axis = -1;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k] != b[k]) {
      if (axis >= 0) return -2;
      axis = static_cast<int>(k);
    }
  return axis;
}

/// `--between LOC1:LOC2`: its two locations' coordinates (p0, p1) and the
/// one axis along which they differ. InputError when they are one location
/// or differ in more than one axis.
int between_axis(const Segment2& between, const std::vector<SpaceAxis>& axes, const std::string& file,
                 std::vector<double>& p0, std::vector<double>& p1) {
  p0 = coordinates(between.first, axes, file);
  p1 = coordinates(between.second, axes, file);
  const int ax = varying_axis(p0, p1);
  if (ax < 0)
    throw InputFieldError(file + ": " + field("between") + ": " + location_text(between.first) + " and " +
                          location_text(between.second) +
                          (ax == -1 ? " are one location" : " differ in more than one axis"));
  return ax;
}

/// Why two masters' glyphs cannot be interpolated ("" when they can).
std::string incompatibility(const Glyph& a, const std::string& name_a, const Glyph& b, const std::string& name_b) {
  if (a.contours.size() != b.contours.size())
    return std::to_string(a.contours.size()) + " contours in " + name_a + ", " + std::to_string(b.contours.size()) +
           " in " + name_b;
  for (std::size_t c = 0; c < a.contours.size(); ++c) {
    const BSpline& x = a.contours[c].spline;
    const BSpline& y = b.contours[c].spline;
    const std::string which = "contour " + std::to_string(a.contours[c].index);
    if (a.contours[c].index != b.contours[c].index) return which + " is open in one of " + name_a + ", " + name_b;
    // Source points (a line's added inner points are none).
    auto count = [](const Contour& k) { return std::count_if(k.font_point.begin(), k.font_point.end(), [](int p) { return p >= 0; }); };
    if (x.points().size() != y.points().size() || x.degree() != y.degree() || count(a.contours[c]) != count(b.contours[c]))
      return which + " has " + std::to_string(count(a.contours[c])) + " points in " + name_a + ", " +
             std::to_string(count(b.contours[c])) + " in " + name_b;
    if (x.knots() != y.knots() || a.contours[c].node != b.contours[c].node)
      return which + " has other point types in " + name_b + " than in " + name_a;
  }
  return {};
}

/// Per segment: the node starting it is marked smooth in the glyph (no
/// marks, a binary font: true).
std::vector<bool> smooth_marks(const Glyph& g, const Contour& c) {
  std::vector<bool> out;
  for (const int sp : c.joint_source_point) {
    bool s = true;
    if (!g.point_smooth.empty()) {
      s = c.index < static_cast<int>(g.point_smooth.size()) && sp >= 0 &&
          sp < static_cast<int>(g.point_smooth[c.index].size()) && g.point_smooth[c.index][sp];
    }
    out.push_back(s);
  }
  return out;
}

// ------------------------------------------------------------ designspace

namespace {

/// One read_designspace_masters: the designspace's full masters, the lines
/// between adjacent ones, the pieces on them (or on --between), and each
/// compatible glyph's contours' motions along every piece.
class DesignspaceReading {
 public:
  DesignspaceReading(const fs::path& path, const GlyphSelection& which)
      : path_(path), ds_(read_designspace(path)), axes_(space_axes(ds_)) {
    // Sources in a UFO's other layer (sparse masters) are not read: the
    // pieces run between the full masters.
    for (const Designspace::Source& src : ds_.sources)
      if (src.layer.empty()) sources_.push_back(src);
    if (sources_.empty()) throw InputError(path.string() + ": every source is a layer of a UFO (no full master)");
    n_ = sources_.size();
    loc_.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      for (const Designspace::Axis& a : ds_.axes) loc_[k].push_back(sources_[k].location.at(a.name));
      if (sources_[k].is_default) def_ = k;
    }
    // The default master first, then the others (each a UFO: its errors are the run's).
    fonts_.resize(n_);
    fonts_[def_] = read_ufo(sources_[def_].path, which);
    for (std::size_t k = 0; k < n_; ++k) {
      if (k == def_) continue;
      GlyphSelection all;
      all.all = true;
      fonts_[k] = read_ufo(sources_[k].path, all);
    }
    by_name_.resize(n_);
    for (std::size_t k = 0; k < n_; ++k)
      if (k != def_)
        for (const Glyph& g : fonts_[k].glyphs) by_name_[k][g.name] = &g;
    lines_ = adjacent_lines();
  }

  Masters masters(const std::optional<Segment2>& between) {
    const std::vector<LinePiece> pieces = between ? pieces_between(*between) : whole_lines();
    Masters m;
    m.font = std::move(fonts_[def_]);
    m.font.path = path_.string();
    m.motions.resize(m.font.glyphs.size());
    for (const LinePiece& pc : pieces) m.pieces.push_back(pc.piece);
    std::vector<std::string> why(m.font.glyphs.size());
    std::vector<std::string> retry;  // glyphs whose masters differ: read again keeping lines of zero length
    for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi) {
      const Glyph& g = m.font.glyphs[gi];
      if (!g.error.empty()) continue;
      why[gi] = compatibility(g, by_name_);
      if (!why[gi].empty()) retry.push_back(g.name);
    }
    if (!retry.empty()) read_again_with_zero_length_lines(m.font, retry, why);
    for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi) {
      Glyph& g = m.font.glyphs[gi];
      if (g.error.empty() && !why[gi].empty()) {
        g.error = g.name + ": incompatible masters: " + why[gi];
        g.contours.clear();
      }
      if (g.error.empty()) m.motions[gi] = motions(g, pieces);
    }
    return m;
  }

 private:
  /// A line between two adjacent masters: they differ in `axis` only.
  struct Line {
    std::size_t a, b;  // masters at s = 0 and s = 1
    int axis;
  };
  struct LinePiece {
    Line line;
    std::shared_ptr<const Piece> piece;
  };
  using ByName = std::vector<std::map<std::string, const Glyph*>>;

  static std::vector<SpaceAxis> space_axes(const Designspace& ds) {
    std::vector<SpaceAxis> axes;
    for (const Designspace::Axis& a : ds.axes) {
      SpaceAxis s;
      s.tag = a.tag.empty() ? a.name : a.tag;
      s.name = a.name;
      s.minimum = a.minimum;
      s.maximum = a.maximum;
      s.default_value = a.default_value;
      s.to_coord = [a](double u) { return a.to_design(u); };
      s.to_user = [a](double d) { return a.to_user(d); };
      for (const auto& m : a.map) s.coord_breaks.push_back(m.second);
      axes.push_back(std::move(s));
    }
    return axes;
  }

  /// Pieces between adjacent masters along each axis.
  std::vector<Line> adjacent_lines() const {
    std::vector<Line> lines;
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t j = 0; j < n_; ++j) {
        const int ax = varying_axis(loc_[i], loc_[j]);
        if (ax < 0 || loc_[i][ax] >= loc_[j][ax]) continue;
        bool adjacent = true;
        for (std::size_t k = 0; k < n_ && adjacent; ++k)
          if (varying_axis(loc_[i], loc_[k]) == ax && loc_[k][ax] > loc_[i][ax] && loc_[k][ax] < loc_[j][ax])
            adjacent = false;
        if (adjacent) lines.push_back({i, j, ax});
      }
    return lines;
  }

  std::shared_ptr<const Piece> piece(const Line& l, double s0, double s1, std::string from, std::string to) const {
    auto p = std::make_shared<Piece>();
    p->s0 = s0;
    p->s1 = s1;
    p->from = std::move(from);
    p->to = std::move(to);
    p->master_a = sources_[l.a].name;
    p->master_b = sources_[l.b].name;
    const double c0 = loc_[l.a][l.axis], c1 = loc_[l.b][l.axis];
    for (std::size_t k = 0; k < axes_.size(); ++k) {
      const double x0 = static_cast<int>(k) == l.axis ? c0 + s0 * (c1 - c0) : loc_[l.a][k];
      const double x1 = static_cast<int>(k) == l.axis ? c0 + s1 * (c1 - c0) : loc_[l.a][k];
      p->axes.push_back(piece_axis(axes_[k], x0, x1));
    }
    return p;
  }

  std::vector<LinePiece> whole_lines() const {
    std::vector<LinePiece> pieces;
    for (const Line& l : lines_) pieces.push_back({l, piece(l, 0, 1, sources_[l.a].name, sources_[l.b].name)});
    return pieces;
  }

  /// --between: the parts of the lines that the segment covers; it must run
  /// between masters along one axis.
  std::vector<LinePiece> pieces_between(const Segment2& between) const {
    const std::string file = path_.string();
    std::vector<double> p0, p1;
    const int ax = between_axis(between, axes_, file, p0, p1);
    if (p0[ax] > p1[ax]) std::swap(p0, p1);
    std::vector<LinePiece> pieces;
    double covered = 0;
    for (const Line& l : lines_) {
      const int off = varying_axis(loc_[l.a], p0);  // the same line: the other axes agree
      if (l.axis != ax || (off != ax && off != -1)) continue;
      const double c0 = loc_[l.a][ax], c1 = loc_[l.b][ax];
      const double lo = std::max(c0, p0[ax]), hi = std::min(c1, p1[ax]);
      if (!(lo < hi)) continue;
      covered += hi - lo;
      auto name_at = [&](double c) {
        if (c == c0) return sources_[l.a].name;
        if (c == c1) return sources_[l.b].name;
        return axes_[ax].tag + "=" + num(axes_[ax].to_user(c));
      };
      pieces.push_back({l, piece(l, (lo - c0) / (c1 - c0), (hi - c0) / (c1 - c0), name_at(lo), name_at(hi))});
    }
    if (covered < p1[ax] - p0[ax])
      throw InputFieldError(file + ": " + field("between") + ": " + location_text(between.first) + ":" +
                            location_text(between.second) +
                            " does not run between masters (in a designspace, cmr interpolates along an axis between "
                            "masters that differ in that axis only; a variable font takes any segment)");
    return pieces;
  }

  /// Compatibility with every master that has the glyph ("" when compatible).
  std::string compatibility(const Glyph& g, const ByName& others) const {
    std::string why;
    for (std::size_t k = 0; k < n_ && why.empty(); ++k) {
      if (k == def_) continue;
      const auto it = others[k].find(g.name);
      if (it == others[k].end()) continue;
      const Glyph* o = it->second;
      if (!o->error.empty()) why = "cannot be read in " + sources_[k].name + " (" + o->error + ")";
      else why = incompatibility(g, sources_[def_].name, *o, sources_[k].name);
    }
    return why;
  }

  /// A line that shrinks to zero length in one master is dropped by the
  /// reader there (io/font.hpp) and kept in the others: those glyphs are
  /// read again from every master with their lines of zero length kept (a
  /// segment of equal points), so that their points correspond; a glyph
  /// that is then compatible takes its masters from that reading.
  void read_again_with_zero_length_lines(Font& font, const std::vector<std::string>& retry, std::vector<std::string>& why) {
    kept_.resize(n_);
    ByName kept_by_name(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      GlyphSelection names;
      for (const std::string& name : retry)
        if (k == def_ || by_name_[k].count(name)) names.names.push_back(name);
      kept_[k] = read_ufo(sources_[k].path, names, true);
      for (const Glyph& g : kept_[k].glyphs) kept_by_name[k][g.name] = &g;
    }
    for (std::size_t gi = 0; gi < font.glyphs.size(); ++gi) {
      if (why[gi].empty()) continue;
      const Glyph& g = font.glyphs[gi];
      const auto d = std::find_if(kept_[def_].glyphs.begin(), kept_[def_].glyphs.end(),
                                  [&](const Glyph& x) { return x.name == g.name; });
      if (d == kept_[def_].glyphs.end() || !d->error.empty() || !compatibility(*d, kept_by_name).empty()) continue;
      const std::string name = g.name;
      const std::uint32_t codepoint = g.codepoint;
      font.glyphs[gi] = *d;
      font.glyphs[gi].codepoint = codepoint;
      why[gi].clear();
      for (std::size_t k = 0; k < n_; ++k)
        if (k != def_ && kept_by_name[k].count(name)) by_name_[k][name] = kept_by_name[k][name];
    }
  }

  /// Each contour's motion along every piece whose two masters have the glyph.
  std::vector<std::vector<ContourMotion>> motions(const Glyph& g, const std::vector<LinePiece>& pieces) const {
    auto glyph_in = [&](std::size_t k) -> const Glyph* {
      if (k == def_) return &g;
      const auto it = by_name_[k].find(g.name);
      return it == by_name_[k].end() ? nullptr : it->second;
    };
    std::vector<std::vector<ContourMotion>> out(g.contours.size());
    for (const LinePiece& lp : pieces) {
      const Glyph* ga = glyph_in(lp.line.a);
      const Glyph* gb = glyph_in(lp.line.b);
      if (ga == nullptr || gb == nullptr) continue;  // a sparse master
      for (std::size_t c = 0; c < g.contours.size(); ++c) {
        ContourMotion mo{lp.piece, ga->contours[c].spline, gb->contours[c].spline, {}};
        const std::vector<bool> sa = smooth_marks(*ga, ga->contours[c]), sb = smooth_marks(*gb, gb->contours[c]);
        for (std::size_t k = 0; k < sa.size(); ++k) mo.smooth.push_back(sa[k] && k < sb.size() && sb[k]);
        out[c].push_back(std::move(mo));
      }
    }
    return out;
  }

  const fs::path path_;
  const Designspace ds_;
  const std::vector<SpaceAxis> axes_;
  std::vector<Designspace::Source> sources_;  // the full masters
  std::size_t n_ = 0, def_ = 0;               // how many; the default's index
  std::vector<std::vector<double>> loc_;      // each master's design location, by axis
  std::vector<Font> fonts_;                   // each master's glyphs (the default's: those selected)
  std::vector<Font> kept_;                    // the glyphs read again with their lines of zero length
  ByName by_name_;                            // the other masters' glyphs by name (pointing into fonts_ or kept_)
  std::vector<Line> lines_;
};

}  // namespace

Masters read_designspace_masters(const fs::path& path, const GlyphSelection& which,
                                 const std::optional<Segment2>& between) {
  return DesignspaceReading(path, which).masters(between);
}

// ------------------------------------------------------------ variable fonts

/// A variable font's axes as design-space axes: fvar's normalisation, then
/// avar's map (a designspace axis's piecewise map, reused).
std::vector<SpaceAxis> variation_axes(const Variations& var) {
  std::vector<SpaceAxis> axes;
  for (const Variations::Axis& a : var.axes) {
    SpaceAxis s;
    s.tag = a.tag;
    s.name = a.name;
    s.minimum = a.minimum;
    s.maximum = a.maximum;
    s.default_value = a.default_value;
    Designspace::Axis avar;
    avar.map = a.avar;
    s.to_coord = [a, avar](double u) {
      const double n = u < a.default_value   ? (a.default_value == a.minimum ? 0 : (u - a.default_value) / (a.default_value - a.minimum))
                       : u > a.default_value ? (a.maximum == a.default_value ? 0 : (u - a.default_value) / (a.maximum - a.default_value))
                                             : 0.0;
      return avar.to_design(n);
    };
    s.to_user = [a, avar](double c) {
      const double n = avar.to_user(c);
      return n < 0 ? a.default_value + n * (a.default_value - a.minimum) : a.default_value + n * (a.maximum - a.default_value);
    };
    s.coord_breaks.push_back(0);
    for (const auto& m : a.avar) s.coord_breaks.push_back(m.second);
    axes.push_back(std::move(s));
  }
  return axes;
}

/// "wght=400,wdth=100": a location by its user values.
std::string location_name(const std::vector<SpaceAxis>& axes, const std::vector<double>& c) {
  std::string out;
  for (std::size_t k = 0; k < axes.size(); ++k) out += (out.empty() ? "" : ",") + axes[k].tag + "=" + num(axes[k].to_user(c[k]));
  return out;
}

/// A piece of a variable font's design space: from `a` to `b` (normalised
/// coordinates) along one axis, from cut to cut, and the part s0..s1 of it
/// that is judged (--between).
struct PieceEnds {
  std::vector<double> a, b;
  double s0 = 0, s1 = 1;
};

/// The pieces where every point moves affinely: along each axis, from cut
/// to cut (gvar's region peaks, starts and ends), with the other axes at the
/// default and at each peak's location; or the user's --between segment,
/// cut the same way.
std::vector<PieceEnds> variation_pieces(const Variations& var, const std::vector<SpaceAxis>& axes,
                                        const std::optional<Segment2>& between, const std::string& file) {
  const std::size_t n_axes = axes.size();
  std::vector<PieceEnds> ends;
  auto cut_line = [&](const std::vector<double>& p0, const std::vector<double>& p1, int ax) {
    const std::vector<double>& cuts = var.cuts[ax];  // -1, ..., 1
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double lo = std::max(cuts[k], p0[ax]), hi = std::min(cuts[k + 1], p1[ax]);
      if (!(lo < hi)) continue;
      PieceEnds e{p0, p0, 0, 1};
      e.a[ax] = cuts[k];
      e.b[ax] = cuts[k + 1];
      e.s0 = (lo - cuts[k]) / (cuts[k + 1] - cuts[k]);
      e.s1 = (hi - cuts[k]) / (cuts[k + 1] - cuts[k]);
      ends.push_back(std::move(e));
    }
  };
  if (!between) {
    for (std::size_t ax = 0; ax < n_axes; ++ax) {
      std::set<std::vector<double>> bases{std::vector<double>(n_axes, 0.0)};
      for (std::vector<double> p : var.peaks) {
        p[ax] = 0;
        bases.insert(p);
      }
      for (std::vector<double> b : bases) {
        std::vector<double> e = b;
        b[ax] = -1;
        e[ax] = 1;
        cut_line(b, e, static_cast<int>(ax));
      }
    }
    return ends;
  }
  std::vector<double> p0, p1;
  const int ax = between_axis(*between, axes, file, p0, p1);
  if (p0[ax] > p1[ax]) std::swap(p0, p1);
  cut_line(p0, p1, ax);
  return ends;
}

/// A variable font's instances share their points: they differ only where
/// the reader dropped a line of zero length at one instance (io/font.hpp).
/// The glyphs with a reason in `why` are read again, at the default and at
/// every piece's end, with their lines of zero length kept (a segment of
/// equal points there); a glyph whose readings then correspond takes them
/// (in `m.font` and `glyph_at`), and its reason is cleared.
void reread_with_zero_length_lines(const fs::path& path, const std::vector<SpaceAxis>& axes,
                                   const std::map<std::vector<double>, Font>& instances, Masters& m,
                                   std::map<std::vector<double>, std::vector<const Glyph*>>& glyph_at,
                                   std::vector<std::string>& why, std::optional<Font>& kept_default,
                                   std::map<std::vector<double>, Font>& kept) {
  std::vector<std::uint32_t> retry;
  for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi)
    if (!why[gi].empty()) retry.push_back(m.font.glyphs[gi].codepoint);
  if (retry.empty()) return;
  kept_default = read_font(path, retry, {}, {}, true);
  for (const auto& [c, f] : instances) kept.emplace(c, read_font(path, retry, {}, c, true));
  for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi) {
    if (why[gi].empty()) continue;
    const std::string& name = m.font.glyphs[gi].name;
    auto find = [&](const Font& f) -> const Glyph* {
      for (const Glyph& x : f.glyphs)
        if (x.name == name) return &x;
      return nullptr;
    };
    const Glyph* d = find(*kept_default);
    if (d == nullptr) continue;
    std::string again;
    std::map<std::vector<double>, const Glyph*> found;
    for (const auto& [c, f] : kept) {
      const Glyph* x = find(f);
      if (x == nullptr) {
        again = "the instance at " + location_name(axes, c) + " has other glyphs";
        break;
      }
      again = incompatibility(*d, "the default instance", *x, "the instance at " + location_name(axes, c));
      if (!again.empty()) break;
      found[c] = x;
    }
    if (!again.empty()) continue;
    m.font.glyphs[gi] = *d;
    for (auto& [c, at] : glyph_at) at[gi] = found.at(c);
    why[gi].clear();
  }
}

Masters read_variable_masters(const fs::path& path, const GlyphSelection& which, const std::optional<Segment2>& between) {
  const std::string file = path.string();
  const Variations var = read_variations(path);
  const std::vector<SpaceAxis> axes = variation_axes(var);
  const std::size_t n_axes = axes.size();
  const auto name_of = [&](const std::vector<double>& c) { return location_name(axes, c); };
  const std::vector<PieceEnds> ends = variation_pieces(var, axes, between, file);

  Masters m;
  m.font = read_font(path, which.codepoints);
  m.font.path = file;
  // The instances at the pieces' ends, each loaded once.
  std::map<std::vector<double>, Font> instances;
  for (const PieceEnds& e : ends)
    for (const std::vector<double>* c : {&e.a, &e.b})
      if (!instances.count(*c)) instances.emplace(*c, read_font(path, which.codepoints, {}, *c));
  for (const PieceEnds& e : ends) {
    auto p = std::make_shared<Piece>();
    p->s0 = e.s0;
    p->s1 = e.s1;
    p->master_a = name_of(e.a);
    p->master_b = name_of(e.b);
    std::vector<double> x0 = e.a, x1 = e.a;
    for (std::size_t x = 0; x < n_axes; ++x) {
      x0[x] = e.a[x] + e.s0 * (e.b[x] - e.a[x]);
      x1[x] = e.a[x] + e.s1 * (e.b[x] - e.a[x]);
      p->axes.push_back(piece_axis(axes[x], x0[x], x1[x]));
    }
    p->from = name_of(x0);
    p->to = name_of(x1);
    m.pieces.push_back(p);
  }
  m.motions.resize(m.font.glyphs.size());
  // Each instance's glyph gi (nullptr: the instance has other glyphs).
  std::map<std::vector<double>, std::vector<const Glyph*>> glyph_at;
  for (const auto& [c, f] : instances) {
    std::vector<const Glyph*>& at = glyph_at[c];
    for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi)
      at.push_back(gi < f.glyphs.size() && f.glyphs[gi].name == m.font.glyphs[gi].name ? &f.glyphs[gi] : nullptr);
  }
  auto compatibility = [&](const Glyph& g, std::size_t gi) {
    for (const auto& [c, at] : glyph_at) {
      if (at[gi] == nullptr) return "the instance at " + name_of(c) + " has other glyphs";
      std::string why = incompatibility(g, "the default instance", *at[gi], "the instance at " + name_of(c));
      if (!why.empty()) return why;
    }
    return std::string();
  };
  std::vector<std::string> why(m.font.glyphs.size());
  for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi) why[gi] = compatibility(m.font.glyphs[gi], gi);
  std::optional<Font> kept_default;  // the glyphs read again, which glyph_at then points into
  std::map<std::vector<double>, Font> kept;
  reread_with_zero_length_lines(path, axes, instances, m, glyph_at, why, kept_default, kept);
  for (std::size_t gi = 0; gi < m.font.glyphs.size(); ++gi) {
    Glyph& g = m.font.glyphs[gi];
    if (!why[gi].empty()) {
      // Still incompatible, with lines of zero length kept: a contour shrinks to a point there.
      g.error = g.name + ": " + why[gi] + " (with lines of zero length kept); not judged between the masters";
      g.contours.clear();
      continue;
    }
    m.motions[gi].resize(g.contours.size());
    for (std::size_t k = 0; k < ends.size(); ++k) {
      const Glyph& ga = *glyph_at.at(ends[k].a)[gi];
      const Glyph& gb = *glyph_at.at(ends[k].b)[gi];
      for (std::size_t c = 0; c < g.contours.size(); ++c)
        m.motions[gi][c].push_back(ContourMotion{m.pieces[k], ga.contours[c].spline, gb.contours[c].spline, {}});
    }
  }
  return m;
}

}  // namespace

Masters read_masters(const fs::path& path, const GlyphSelection& which, const std::optional<Segment2>& between) {
  if (is_designspace_path(path)) return read_designspace_masters(path, which, between);
  if (is_ufo_path(path))
    throw InputError(path.string() + ": one master (a UFO): the interpolation gates need a designspace or a variable font");
  return read_variable_masters(path, which, between);
}

}  // namespace cmr::import
