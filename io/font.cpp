#include "io/font.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include FT_FONT_FORMATS_H
#include FT_MULTIPLE_MASTERS_H
#include FT_TRUETYPE_TABLES_H
#include FT_TRUETYPE_TAGS_H

#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/spline_json.hpp"
#include "io/chain.hpp"
#include "io/output.hpp"

namespace cmr::import {
namespace {

/// A location's value as written: "700", "14.5".
std::string format_location_value(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

/// Decodes one UTF-8 character at text[i] (advancing i); InputError if malformed.
std::uint32_t utf8_at(const std::string& text, std::size_t& i) {
  const auto b = static_cast<unsigned char>(text[i]);
  int extra = b < 0x80 ? 0 : (b >> 5) == 6 ? 1 : (b >> 4) == 14 ? 2 : (b >> 3) == 30 ? 3 : -1;
  if (extra < 0 || i + extra >= text.size() + (extra == 0 ? 1 : 0))
    throw InputFieldError(field("glyphs") + ": '" + text + "' is not valid UTF-8");
  std::uint32_t c = extra == 0 ? b : (b & (0x3F >> extra));
  ++i;
  for (int k = 0; k < extra; ++k, ++i) {
    if (i >= text.size() || (static_cast<unsigned char>(text[i]) >> 6) != 2)
      throw InputFieldError(field("glyphs") + ": '" + text + "' is not valid UTF-8");
    c = (c << 6) | (static_cast<unsigned char>(text[i]) & 0x3F);
  }
  return c;
}

/// One character of a spec item: "U+hex" or a single UTF-8 character.
std::uint32_t spec_char(const std::string& item, std::size_t& i) {
  if (item.compare(i, 2, "U+") == 0 && i + 2 < item.size()) {
    std::size_t j = i + 2;
    std::uint32_t c = 0;
    while (j < item.size() && std::isxdigit(static_cast<unsigned char>(item[j])) && j - i < 8)
      c = c * 16 + static_cast<std::uint32_t>(std::stoi(item.substr(j++, 1), nullptr, 16));
    if (j == i + 2 || c > 0x10FFFF) throw InputFieldError(field("glyphs") + ": '" + item + "' has a bad U+ code point");
    i = j;
    return c;
  }
  return utf8_at(item, i);
}

struct FreeTypeLibrary {
  FT_Library lib = nullptr;
  FreeTypeLibrary() {
    if (FT_Init_FreeType(&lib) != 0) throw EnvironmentError("FreeType: cannot initialise the library");
  }
  ~FreeTypeLibrary() { FT_Done_FreeType(lib); }
};

struct FaceDeleter {
  void operator()(FT_Face f) const { FT_Done_Face(f); }
};
using FacePtr = std::unique_ptr<FT_FaceRec_, FaceDeleter>;

/// The face of a font file's bytes (the caller keeps `bytes` alive: FreeType
/// reads from them), on this thread's library; InputError naming the file
/// when FreeType cannot read it.
FT_Library ft_library() {
  static thread_local FreeTypeLibrary library;  // one per thread: FT_Library is not thread-safe
  return library.lib;
}

FacePtr open_face(const std::filesystem::path& path, const std::string& bytes) {
  FT_Face raw = nullptr;
  if (const FT_Error e = FT_New_Memory_Face(ft_library(), reinterpret_cast<const FT_Byte*>(bytes.data()),
                                            static_cast<FT_Long>(bytes.size()), 0, &raw);
      e != 0)
    throw InputError(path.string() + ": not a font FreeType can read (error " + std::to_string(e) + ")");
  return FacePtr(raw);
}

/// A control point of the chain being built.
struct Item {
  Vec2 p;
  std::string name;
  int font_point = -1;
  int line_of = -1;   // an added line point: the font point of the line's first node
  bool node = false;  // explicit on-curve point
};

/// Names of a cubic (CFF) contour's points, as a font editor shows a
/// PostScript outline: the on-curve nodes numbered along the contour from
/// its first one ("n0", "n1", ...); each handle after its node: "n3.out"
/// leaves node n3, "n4.in" arrives at node n4 (the handles of the piece
/// from n3 to n4); the inner points of a straight piece "n3+n4@1/3" and
/// "n3+n4@2/3". The font's point indices (font_point) are kept beside.
/// `items` starts at a node (a cubic contour always has one).
void name_cubic_items(std::vector<Item>& items, const std::string& prefix) {
  std::vector<int> number(items.size(), -1);
  int nodes = 0;
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].node) number[k] = nodes++;
  auto node_name = [&](int n) {
    std::string name = "n";  // appended, not "n" + ...: GCC 12 warns (-Wrestrict) on that
    return name.append(std::to_string(n % nodes));
  };
  int last = 0;  // the node before item k
  for (std::size_t k = 0; k < items.size(); ++k) {
    Item& it = items[k];
    if (it.node) {
      last = number[k];
      it.name = prefix + "/" + node_name(last);
      continue;
    }
    const bool after_node = items[k - 1].node;  // items[0] is a node
    if (it.font_point < 0) {  // a straight piece's inner point: k-th of degree-1
      const int step = after_node ? 1 : 2;
      it.name = prefix + "/" + node_name(last) + "+" + node_name(last + 1) + "@" + std::to_string(step) + "/3";
    } else if (after_node) {
      it.name = prefix + "/" + node_name(last) + ".out";
    } else {
      it.name = prefix + "/" + node_name(last + 1) + ".in";
    }
  }
}

/// x = a + b exactly in double (Knuth's TwoSum: the rounding error is 0).
bool exact_sum(double a, double b, double& x) {
  x = a + b;
  const double a1 = x - b, b1 = x - a1;
  return std::isfinite(x) && (a - a1) + (b - b1) == 0;
}

/// A CFF line from A to B as a cubic whose inner points lie exactly on the
/// line: A + k (B - A) and B - k (B - A) with k = 21845/65536 (1/3 within
/// 5e-6), when every step is exact in double (font units are integers, so it
/// always is). The uniform thirds (2A + B)/3, (A + 2B)/3 are not doubles:
/// rounded, they bend the line by ~1e-16 of its length, which gave every
/// slanted line a tiny curvature, inflections and a "curvature jump" to the
/// next straight piece, and sent it through the exact rational path. A line
/// is straight for any inner points on it in order (curvature 0; its
/// direction at both ends is B - A); only its speed is not uniform, by 5e-6.
/// nullopt (the rounded thirds) where a step would round.
std::optional<std::array<Vec2, 2>> exact_cubic_line(Vec2 a, Vec2 b) {
  constexpr double k = 21845.0 / 65536.0;
  std::array<Vec2, 2> out;
  for (int c = 0; c < 2; ++c) {
    const double ac = c == 0 ? a.x : a.y, bc = c == 0 ? b.x : b.y;
    double d, first, second;
    if (!exact_sum(bc, -ac, d)) return std::nullopt;
    const double q = k * d;  // exact when fma finds no rounding error
    if (std::fma(k, d, -q) != 0) return std::nullopt;
    if (!exact_sum(ac, q, first) || !exact_sum(bc, -q, second)) return std::nullopt;
    (c == 0 ? out[0].x : out[0].y) = first;
    (c == 0 ? out[1].x : out[1].y) = second;
  }
  return out;
}

/// The chain of one contour (its points in the font's order), or empty when
/// the contour has no piece (a lone point).
std::vector<Item> contour_items(const std::vector<OutlinePoint>& points, int degree, const std::string& prefix,
                                PointNaming naming, bool keep_zero_lines) {
  const int n = static_cast<int>(points.size());
  int start = 0;
  while (start < n && points[start].tag != OutlinePoint::Tag::on) ++start;
  const bool has_node = start < n;
  if (!has_node) {
    if (degree == 3) throw InputError(prefix + ": a cubic contour without an on-curve point");
    start = 0;
  }
  auto name = [&](int idx) { return prefix + "/p" + std::to_string(idx); };
  std::vector<Item> items;
  // Inner points of the straight piece from a node to the next (by value:
  // the pushes below may move `items`).
  auto add_line = [&](const Item from, const Item to) {
    const std::optional<std::array<Vec2, 2>> exact = degree == 3 ? exact_cubic_line(from.p, to.p) : std::nullopt;
    for (int k = 1; k < degree; ++k) {
      const double s = static_cast<double>(k) / degree;
      Item it;
      it.p = exact ? (*exact)[k - 1] : from.p + s * (to.p - from.p);
      it.name = from.name;
      it.name.append("+p").append(std::to_string(to.font_point));  // font_point is already contour-relative
      if (degree > 2) it.name.append("@").append(std::to_string(k)).append("/").append(std::to_string(degree));
      it.line_of = from.font_point;
      items.push_back(it);
    }
  };
  int inner_run = 0;  // inner points since the last node (cubic: must be 0 or 2)
  for (int j = 0; j < n; ++j) {
    const int idx = (start + j) % n;
    const OutlinePoint::Tag tag = points[idx].tag;
    Item it;
    it.p = points[idx].p;
    it.name = name(idx);
    it.font_point = idx;
    it.node = tag == OutlinePoint::Tag::on;
    if ((tag == OutlinePoint::Tag::cubic) != (degree == 3) && !it.node)
      throw InputError(prefix + ": point " + std::to_string(idx) + " mixes conic and cubic control points");
    if (it.node) {
      if (degree == 3 && inner_run != 0 && inner_run != 2)
        throw InputError(prefix + ": " + std::to_string(inner_run) + " cubic control points before point " +
                         std::to_string(idx) + " (expected 2)");
      inner_run = 0;
      if (!items.empty() && items.back().node) {
        if (items.back().p == it.p && !keep_zero_lines) continue;  // zero-length line: dropped
        add_line(items.back(), it);
      }
    } else {
      ++inner_run;
    }
    items.push_back(it);
  }
  if (degree == 3 && inner_run != 0 && inner_run != 2)
    throw InputError(prefix + ": " + std::to_string(inner_run) + " cubic control points close the contour (expected 2)");
  // Closing: the last node back to the first.
  if (has_node && items.size() > 1 && items.back().node) {
    if (items.back().p == items.front().p && !keep_zero_lines) {
      items.pop_back();
    }
    if (items.size() > 1 && items.back().node) add_line(items.back(), items.front());
  }
  const bool any_inner = std::any_of(items.begin(), items.end(), [](const Item& i) { return !i.node; });
  if (items.size() < 2 || !any_inner) return {};
  if (degree == 3 && naming == PointNaming::editor) name_cubic_items(items, prefix);
  return items;
}

/// The points of contour c of a FreeType outline, contour-relative.
std::vector<OutlinePoint> outline_points(const FT_Outline& o, int c) {
  const int first = c == 0 ? 0 : o.contours[c - 1] + 1, last = o.contours[c];
  std::vector<OutlinePoint> out;
  for (int i = first; i <= last; ++i) {
    const int tag = FT_CURVE_TAG(o.tags[i]);
    out.push_back({{static_cast<double>(o.points[i].x), static_cast<double>(o.points[i].y)},
                   tag == FT_CURVE_TAG_ON      ? OutlinePoint::Tag::on
                   : tag == FT_CURVE_TAG_CUBIC ? OutlinePoint::Tag::cubic
                                               : OutlinePoint::Tag::conic});
  }
  return out;
}

}  // namespace

std::optional<Contour> outline_contour(const std::vector<OutlinePoint>& points, int c, int degree,
                                       const std::string& glyph, PointNaming naming, bool keep_zero_lines) {
  const std::string prefix = glyph + "/c" + std::to_string(c);
  const std::vector<Item> items = contour_items(points, degree, prefix, naming, keep_zero_lines);
  if (items.empty()) return std::nullopt;
  const std::size_t m = items.size();
  // A piece starts at each inner point whose predecessor is a node; in degree
  // 2 at every inner point (two in a row meet at the implied midpoint).
  std::vector<bool> inc(m);
  for (std::size_t k = 0; k < m; ++k)
    inc[k] = !items[k].node && (degree == 2 || items[(k + m - 1) % m].node);
  std::vector<Vec2> pts;
  std::vector<std::string> point_names, joint_names;
  std::vector<int> font_point, source_point;
  std::vector<bool> node;
  for (const Item& it : items) {
    pts.push_back(it.p);
    point_names.push_back(it.name);
    font_point.push_back(it.font_point);
    source_point.push_back(it.font_point >= 0 ? it.font_point : it.line_of);
    node.push_back(it.node);
  }
  // Segments in order of their first inner point k = 1..m (item m is item 0).
  std::vector<int> joint_source_point;
  for (std::size_t k = 1; k <= m; ++k) {
    if (!inc[k % m]) continue;
    const Item& prev = items[k - 1];
    joint_names.push_back(prev.node ? prev.name : prev.name + "+p" + std::to_string(items[k % m].font_point));
    joint_source_point.push_back(prev.font_point >= 0 ? prev.font_point : prev.line_of);
  }
  Contour out{c, BSpline::make_closed(degree, chain_knots(inc), std::move(pts), prefix), std::move(point_names),
              std::move(font_point), std::move(node), std::move(joint_names), std::move(source_point),
              std::move(joint_source_point)};
  return out;
}

std::vector<std::uint32_t> parse_glyph_spec(const std::string& spec) {
  std::vector<std::uint32_t> out;
  std::size_t pos = 0;
  while (pos <= spec.size()) {
    const std::size_t comma = spec.find(',', pos);
    const std::string item = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? spec.size() + 1 : comma + 1;
    if (item.empty()) throw InputFieldError(field("glyphs") + ": empty item in '" + spec + "'");
    std::size_t i = 0;
    const std::uint32_t a = spec_char(item, i);
    std::uint32_t b = a;
    if (i < item.size()) {
      if (item[i] != '-' || i + 1 >= item.size())
        throw InputFieldError(field("glyphs") + ": '" + item + "' is not a character or a range A-Z");
      ++i;
      b = spec_char(item, i);
      if (i != item.size())
        throw InputFieldError(field("glyphs") + ": '" + item + "' is not a character or a range A-Z");
      if (b < a) throw InputFieldError(field("glyphs") + ": the range '" + item + "' runs backwards");
    }
    for (std::uint32_t c = a; c <= b; ++c)
      if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
  }
  return out;
}

bool is_font_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  for (const char* e : {".ttf", ".otf", ".ttc", ".otc", ".cff", ".pfb", ".pfa", ".t1", ".woff"})
    if (ext == e) return true;
  return false;
}

Location parse_location(const std::string& text) {
  Location out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? text.size() + 1 : comma + 1;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq > 4)
      throw InputFieldError(field("location") + ": '" + item +
                            "' is not TAG=VALUE (an axis tag of at most 4 characters: wght=700)");
    const std::string value = item.substr(eq + 1);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != 0 || !std::isfinite(v))
      throw InputFieldError(field("location") + ": '" + value + "' (axis " + item.substr(0, eq) + ") is not a number");
    out.emplace_back(item.substr(0, eq), v);
  }
  return out;
}

namespace {

/// Sets the face to the instance at `location` (see read_font).
void set_location(FT_Library lib, FT_Face face, const Location& location, const std::string& path, Font& font) {
  FT_MM_Var* mm = nullptr;
  if (!FT_HAS_MULTIPLE_MASTERS(face) || FT_Get_MM_Var(face, &mm) != 0)
    throw InputFieldError(path + ": not a variable font (no fvar table), so " + field("location") + " does not apply");
  struct Done {
    FT_Library lib;
    FT_MM_Var* mm;
    ~Done() { FT_Done_MM_Var(lib, mm); }
  } done{lib, mm};
  std::vector<FT_Fixed> coords(mm->num_axis);
  for (FT_UInt a = 0; a < mm->num_axis; ++a) coords[a] = mm->axis[a].def;
  std::string named;
  for (const auto& [tag, value] : location) {
    FT_UInt a = 0;
    for (; a < mm->num_axis; ++a) {
      const FT_ULong t = mm->axis[a].tag;
      const std::string name{static_cast<char>(t >> 24), static_cast<char>((t >> 16) & 0xFF),
                             static_cast<char>((t >> 8) & 0xFF), static_cast<char>(t & 0xFF)};
      if (name == tag || (tag.size() < 4 && name == tag + std::string(4 - tag.size(), ' '))) break;
    }
    if (a == mm->num_axis)
      throw InputFieldError(path + ": " + field("location") + ": the font has no axis '" + tag + "'");
    const double lo = mm->axis[a].minimum / 65536.0, hi = mm->axis[a].maximum / 65536.0;
    if (value < lo || value > hi)
      throw InputFieldError(path + ": " + field("location") + ": " + tag + "=" + format_location_value(value) +
                            " is outside the axis's range [" + format_location_value(lo) + ", " +
                            format_location_value(hi) + "]");
    coords[a] = static_cast<FT_Fixed>(std::lround(value * 65536.0));
    named += (named.empty() ? "" : ",") + tag + "=" + format_location_value(value);
  }
  if (FT_Set_Var_Design_Coordinates(face, mm->num_axis, coords.data()) != 0)
    throw InputError(path + ": FreeType cannot set the location " + named);
  font.style += (font.style.empty() ? "" : " ") + std::string("@") + named;
}

}  // namespace

Font read_font(const std::filesystem::path& path, const std::vector<std::uint32_t>& codepoints,
               const Location& location, const std::vector<double>& blend, bool keep_zero_lines) {
  // Read as every input is (regular files only, size-limited: a FIFO or a
  // device is refused at once); the bytes outlive the face.
  const std::string bytes = read_input_file(path);
  const FacePtr face = open_face(path, bytes);
  Font font;
  font.path = path.string();
  font.family = face->family_name ? face->family_name : "";
  font.style = face->style_name ? face->style_name : "";
  font.units_per_em = face->units_per_EM;
  // The format decides the degree, so that a glyph of straight lines only is
  // a spline of the font's degree too.
  const std::string format = FT_Get_Font_Format(face.get()) ? FT_Get_Font_Format(face.get()) : "";
  font.cubic = format == "CFF" || format == "Type 1" || format == "CID Type 1";
  if (!location.empty()) set_location(ft_library(), face.get(), location, path.string(), font);
  if (!blend.empty()) {
    std::vector<FT_Fixed> coords;
    for (const double v : blend) coords.push_back(static_cast<FT_Fixed>(std::lround(v * 65536.0)));
    if (!FT_HAS_MULTIPLE_MASTERS(face.get()) ||
        FT_Set_Var_Blend_Coordinates(face.get(), static_cast<FT_UInt>(coords.size()), coords.data()) != 0)
      throw InputError(path.string() + ": FreeType cannot set the blend coordinates of an instance");
  }
  const int font_degree = font.cubic ? 3 : 2;
  std::vector<std::uint32_t> every;  // no code points asked for: every one the character map has
  if (codepoints.empty()) {
    FT_UInt gid = 0;
    for (FT_ULong cp = FT_Get_First_Char(face.get(), &gid); gid != 0; cp = FT_Get_Next_Char(face.get(), cp, &gid))
      every.push_back(static_cast<std::uint32_t>(cp));
  }
  for (const std::uint32_t cp : codepoints.empty() ? every : codepoints) {
    const FT_UInt gid = FT_Get_Char_Index(face.get(), cp);
    if (gid == 0) {
      font.missing.push_back(cp);
      continue;
    }
    if (const FT_Error e = FT_Load_Glyph(face.get(), gid, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP);
        e != 0)
      throw InputError(path.string() + ": glyph " + std::to_string(gid) + " cannot be loaded (error " +
                       std::to_string(e) + ")");
    if (face->glyph->format != FT_GLYPH_FORMAT_OUTLINE)
      throw InputError(path.string() + ": glyph " + std::to_string(gid) + " is not an outline");
    Glyph g;
    g.codepoint = cp;
    char buf[128] = {0};
    if (FT_HAS_GLYPH_NAMES(face.get()) && FT_Get_Glyph_Name(face.get(), gid, buf, sizeof buf) == 0 && buf[0] != 0) {
      g.name = buf;
    } else {
      std::snprintf(buf, sizeof buf, "uni%04X", static_cast<unsigned>(cp));
      g.name = buf;
    }
    const FT_Outline& o = face->glyph->outline;
    const int degree = font_degree;
    try {
      for (int c = 0; c < o.n_contours; ++c) {
        if (std::optional<Contour> contour =
                outline_contour(outline_points(o, c), c, degree, g.name, PointNaming::editor, keep_zero_lines))
          g.contours.push_back(std::move(*contour));
      }
    } catch (const InputError& e) {
      throw InputFieldError(path.string() + ": " + marked_text(e));
    }
    font.glyphs.push_back(std::move(g));
  }
  return font;
}

std::vector<std::string> contour_labels(const Contour& contour, const std::vector<std::string>& labels) {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < contour.font_point.size(); ++k) {
    const int sp = contour.font_point[k];
    out.push_back(sp >= 0 && sp < static_cast<int>(labels.size()) ? labels[sp] : std::string());
  }
  return out;
}

nlohmann::json contour_json(const Contour& contour, const std::vector<std::string>* labels) {
  nlohmann::json doc = spline_to_json(contour.spline);
  doc["point_names"] = contour.point_names;
  if (labels) {
    const std::vector<std::string> per_point = contour_labels(contour, *labels);
    if (std::any_of(per_point.begin(), per_point.end(), [](const std::string& l) { return !l.empty(); }))
      doc["point_labels"] = per_point;
  }
  return doc;
}

std::string file_stem(const std::string& glyph_name) {
  std::string out;
  for (const unsigned char ch : glyph_name) {
    if (std::isalnum(ch) || ch == '.' || ch == '-') {  // '_' is the escape
      out += static_cast<char>(ch);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "_%02X", ch);
      out += hex;
    }
  }
  return out;
}

// ------------------------------------------------------------ variations

namespace {

/// A font table's bytes (empty when the font has none).
std::vector<unsigned char> sfnt_table(FT_Face face, FT_ULong tag) {
  FT_ULong length = 0;
  if (FT_Load_Sfnt_Table(face, tag, 0, nullptr, &length) != 0 || length == 0) return {};
  std::vector<unsigned char> out(length);
  if (FT_Load_Sfnt_Table(face, tag, 0, out.data(), &length) != 0) return {};
  return out;
}

/// Big-endian reads, bounds-checked (InputError naming the table).
struct Reader {
  const std::vector<unsigned char>& b;
  std::string what;
  std::size_t need(std::size_t at, std::size_t n) const {
    if (at > b.size() || n > b.size() - at) throw InputError(what + ": truncated");
    return at;
  }
  unsigned u8(std::size_t at) const { return b[need(at, 1)]; }
  unsigned u16(std::size_t at) const { need(at, 2); return (unsigned{b[at]} << 8) | b[at + 1]; }
  std::uint32_t u32(std::size_t at) const { return (std::uint32_t{u16(at)} << 16) | u16(at + 2); }
  double f2dot14(std::size_t at) const { return static_cast<std::int16_t>(u16(at)) / 16384.0; }
};

/// One region (start, peak, end per axis) into the cuts and peaks.
void add_region(Variations& v, const std::vector<double>& start, const std::vector<double>& peak,
                const std::vector<double>& end, std::set<std::vector<double>>& peaks) {
  for (std::size_t a = 0; a < v.axes.size(); ++a) {
    if (peak[a] == 0) continue;  // the region does not involve the axis
    for (const double c : {start[a], peak[a], end[a]})
      if (c >= -1 && c <= 1) v.cuts[a].push_back(c);
  }
  peaks.insert(peak);
}

/// gvar: every tuple header of every glyph (OpenType gvar, version 1).
void gvar_regions(const std::vector<unsigned char>& t, Variations& v, std::set<std::vector<double>>& peaks,
                  const std::string& path) {
  const Reader r{t, path + ": gvar"};
  const std::size_t axes = r.u16(4), shared_count = r.u16(6);
  if (axes != v.axes.size()) throw InputError(path + ": gvar has " + std::to_string(axes) + " axes, fvar " +
                                              std::to_string(v.axes.size()));
  const std::uint32_t shared_at = r.u32(8);
  const std::size_t glyphs = r.u16(12);
  const bool long_offsets = (r.u16(14) & 1) != 0;
  const std::uint32_t data_at = r.u32(16);
  auto tuple = [&](std::size_t at) {
    std::vector<double> out(axes);
    for (std::size_t a = 0; a < axes; ++a) out[a] = r.f2dot14(at + 2 * a);
    return out;
  };
  std::vector<std::vector<double>> shared;
  for (std::size_t k = 0; k < shared_count; ++k) shared.push_back(tuple(shared_at + k * axes * 2));
  for (std::size_t g = 0; g < glyphs; ++g) {
    const std::size_t o0 = long_offsets ? r.u32(20 + 4 * g) : 2 * std::size_t{r.u16(20 + 2 * g)};
    const std::size_t o1 = long_offsets ? r.u32(24 + 4 * g) : 2 * std::size_t{r.u16(22 + 2 * g)};
    if (o1 <= o0) continue;
    std::size_t at = data_at + o0;
    const std::size_t count = r.u16(at) & 0x0FFF;
    at += 4;
    for (std::size_t k = 0; k < count; ++k) {
      const unsigned index = r.u16(at + 2);
      at += 4;
      std::vector<double> peak;
      if (index & 0x8000) {
        peak = tuple(at);
        at += 2 * axes;
      } else {
        if ((index & 0x0FFF) >= shared.size()) throw InputError(path + ": gvar: a tuple names no shared tuple");
        peak = shared[index & 0x0FFF];
      }
      std::vector<double> start(axes), end(axes);
      if (index & 0x4000) {
        start = tuple(at);
        end = tuple(at + 2 * axes);
        at += 4 * axes;
      } else {
        for (std::size_t a = 0; a < axes; ++a) start[a] = std::min(0.0, peak[a]), end[a] = std::max(0.0, peak[a]);
      }
      add_region(v, start, peak, end, peaks);
    }
  }
}

/// CFF2: the regions of the top DICT's item variation store (operator 24).
void cff2_regions(const std::vector<unsigned char>& t, Variations& v, std::set<std::vector<double>>& peaks,
                  const std::string& path) {
  const Reader r{t, path + ": CFF2"};
  const std::size_t header = r.u8(2), dict_length = r.u16(3);
  std::size_t at = header, end = header + dict_length;
  r.need(header, dict_length);
  std::vector<double> operands;
  std::optional<std::size_t> vstore;
  while (at < end) {
    const unsigned b0 = r.u8(at);
    if (b0 == 28) operands.push_back(static_cast<std::int16_t>(r.u16(at + 1))), at += 3;
    else if (b0 == 29) operands.push_back(static_cast<std::int32_t>(r.u32(at + 1))), at += 5;
    else if (b0 == 30) {  // a real: nibbles to 0xf
      ++at;
      while (at < end && (r.u8(at) & 0x0F) != 0x0F && (r.u8(at) >> 4) != 0x0F) ++at;
      ++at;
      operands.push_back(0);
    } else if (b0 >= 32 && b0 <= 246) operands.push_back(static_cast<int>(b0) - 139), ++at;
    else if (b0 >= 247 && b0 <= 250) operands.push_back((static_cast<int>(b0) - 247) * 256 + r.u8(at + 1) + 108), at += 2;
    else if (b0 >= 251 && b0 <= 254) operands.push_back(-(static_cast<int>(b0) - 251) * 256 - static_cast<int>(r.u8(at + 1)) - 108), at += 2;
    else {  // an operator
      const unsigned op = b0 == 12 ? 1200 + r.u8(at + 1) : b0;
      at += b0 == 12 ? 2 : 1;
      if (op == 24 && !operands.empty()) vstore = static_cast<std::size_t>(operands.back());
      operands.clear();
    }
  }
  if (!vstore) return;
  const std::size_t store = *vstore + 2;  // after its u16 length
  const std::size_t list = store + r.u32(store + 2);
  const std::size_t axes = r.u16(list), regions = r.u16(list + 2);
  if (axes != v.axes.size()) throw InputError(path + ": CFF2's variation store has " + std::to_string(axes) + " axes");
  for (std::size_t k = 0; k < regions; ++k) {
    std::vector<double> start(axes), peak(axes), stop(axes);
    for (std::size_t a = 0; a < axes; ++a) {
      const std::size_t p = list + 4 + (k * axes + a) * 6;
      start[a] = r.f2dot14(p);
      peak[a] = r.f2dot14(p + 2);
      stop[a] = r.f2dot14(p + 4);
    }
    add_region(v, start, peak, stop, peaks);
  }
}

}  // namespace

Variations read_variations(const std::filesystem::path& path) {
  const std::string bytes = read_input_file(path);
  const FacePtr face = open_face(path, bytes);
  FT_MM_Var* mm = nullptr;
  if (!FT_HAS_MULTIPLE_MASTERS(face.get()) || FT_Get_MM_Var(face.get(), &mm) != 0)
    throw InputError(path.string() + ": no fvar table: the interpolation gates need a variable font or a designspace");
  Variations v;
  for (FT_UInt a = 0; a < mm->num_axis; ++a) {
    Variations::Axis ax;
    const FT_ULong t = mm->axis[a].tag;
    ax.tag = {static_cast<char>(t >> 24), static_cast<char>((t >> 16) & 0xFF), static_cast<char>((t >> 8) & 0xFF),
              static_cast<char>(t & 0xFF)};
    while (!ax.tag.empty() && ax.tag.back() == ' ') ax.tag.pop_back();
    ax.name = mm->axis[a].name ? mm->axis[a].name : ax.tag;
    ax.minimum = mm->axis[a].minimum / 65536.0;
    ax.default_value = mm->axis[a].def / 65536.0;
    ax.maximum = mm->axis[a].maximum / 65536.0;
    v.axes.push_back(ax);
  }
  FT_Done_MM_Var(ft_library(), mm);
  const std::string file = path.string();
  if (const std::vector<unsigned char> avar = sfnt_table(face.get(), TTAG_avar); !avar.empty()) {
    const Reader r{avar, file + ": avar"};
    const std::size_t axes = r.u16(6);
    std::size_t at = 8;
    for (std::size_t a = 0; a < axes; ++a) {
      const std::size_t count = r.u16(at);
      at += 2;
      for (std::size_t k = 0; k < count; ++k, at += 4)
        if (a < v.axes.size()) v.axes[a].avar.emplace_back(r.f2dot14(at), r.f2dot14(at + 2));
    }
  }
  v.cuts.assign(v.axes.size(), {-1.0, 0.0, 1.0});
  std::set<std::vector<double>> peaks;
  if (const std::vector<unsigned char> gvar = sfnt_table(face.get(), TTAG_gvar); !gvar.empty())
    gvar_regions(gvar, v, peaks, file);
  if (const std::vector<unsigned char> cff2 = sfnt_table(face.get(), FT_MAKE_TAG('C', 'F', 'F', '2')); !cff2.empty())
    cff2_regions(cff2, v, peaks, file);
  for (std::vector<double>& c : v.cuts) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
  }
  v.peaks.assign(peaks.begin(), peaks.end());
  return v;
}

}  // namespace cmr::import
