#include "io/ufo.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <pugixml.hpp>

#include "io/output.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

namespace cmr::import {
namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// An XML document with its text, for line numbers of its nodes.
struct XmlFile {
  std::string path;
  std::string text;
  pugi::xml_document doc;
  std::vector<std::size_t> line_starts;

  int line_at(std::ptrdiff_t offset) const {
    if (offset < 0) return 0;
    return static_cast<int>(std::upper_bound(line_starts.begin(), line_starts.end(), static_cast<std::size_t>(offset)) -
                            line_starts.begin());
  }
  int line_of(const pugi::xml_node& node) const { return line_at(node.offset_debug()); }
  std::string where(const pugi::xml_node& node) const { return path + ":" + std::to_string(line_of(node)); }
};

/// Parses `text` (the bytes of `path`); InputError "PATH:LINE: not
/// well-formed XML (...)".
void parse_xml(XmlFile& f) {
  f.line_starts = {0};
  for (std::size_t i = 0; i < f.text.size(); ++i)
    if (f.text[i] == '\n') f.line_starts.push_back(i + 1);
  // A UFO's files are UTF-8 (pugixml does not check): a name in another
  // encoding would reach the JSON writers, which throw on it (found by fuzz_glif).
  for (std::size_t i = 0; i < f.text.size();) {
    const std::size_t n = utf8_sequence(std::string_view(f.text).substr(i));
    if (n == 0) {
      char byte[8];
      std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(f.text[i]));
      throw InputError(f.path + ":" + std::to_string(f.line_at(static_cast<std::ptrdiff_t>(i))) +
                       ": not UTF-8 (byte " + byte + ")");
    }
    i += n;
  }
  const pugi::xml_parse_result r =
      f.doc.load_buffer(f.text.data(), f.text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r) throw InputError(f.path + ":" + std::to_string(f.line_at(r.offset)) + ": not well-formed XML (" +
                           r.description() + ")");
}

std::unique_ptr<XmlFile> load_xml(const fs::path& path) {
  auto f = std::make_unique<XmlFile>();
  f->path = path.string();
  f->text = read_input_file(path);
  parse_xml(*f);
  return f;
}

pugi::xml_node first_element(const pugi::xml_node& parent) {
  for (pugi::xml_node n = parent.first_child(); n; n = n.next_sibling())
    if (n.type() == pugi::node_element) return n;
  return {};
}

// ------------------------------------------------------------ plists

/// A property-list value (only what a UFO's plists use).
struct PlistEntry;
struct Plist {
  enum class Kind { string, number, boolean, array, dict, other } kind = Kind::other;
  std::string text;
  double number = 0;
  std::vector<Plist> items;         // array
  std::vector<PlistEntry> entries;  // dict, in order
  int line = 0;

  const Plist* find(const std::string& key) const;
};
// A dict's key and value: a struct of its own, not a std::pair<std::string,
// Plist> inside Plist (clang 14 with libstdc++ 12 cannot instantiate that
// pair while Plist is incomplete: the fuzz build failed on it).
struct PlistEntry {
  std::string key;
  Plist value;
};

const Plist* Plist::find(const std::string& key) const {
  for (const auto& [k, v] : entries)
    if (k == key) return &v;
  return nullptr;
}

Plist plist_value(const XmlFile& f, const pugi::xml_node& node) {
  Plist p;
  p.line = f.line_of(node);
  const std::string tag = node.name();
  if (tag == "string") {
    p.kind = Plist::Kind::string;
    p.text = node.text().get();
  } else if (tag == "integer" || tag == "real") {
    p.kind = Plist::Kind::number;
    p.text = node.text().get();
    char* end = nullptr;
    p.number = std::strtod(p.text.c_str(), &end);
    if (p.text.empty() || *end != 0 || !std::isfinite(p.number))
      throw InputError(f.where(node) + ": <" + tag + "> '" + p.text + "' is not a number");
  } else if (tag == "true" || tag == "false") {
    p.kind = Plist::Kind::boolean;
    p.number = tag == "true" ? 1 : 0;
  } else if (tag == "array") {
    p.kind = Plist::Kind::array;
    for (pugi::xml_node c = node.first_child(); c; c = c.next_sibling())
      if (c.type() == pugi::node_element) p.items.push_back(plist_value(f, c));
  } else if (tag == "dict") {
    p.kind = Plist::Kind::dict;
    std::set<std::string> seen;
    for (pugi::xml_node c = first_element(node); c;) {
      if (std::string(c.name()) != "key") throw InputError(f.where(c) + ": <" + c.name() + "> where a <key> belongs");
      const std::string key = c.text().get();
      pugi::xml_node v = c.next_sibling();
      while (v && v.type() != pugi::node_element) v = v.next_sibling();
      if (!v) throw InputError(f.where(c) + ": the key '" + key + "' has no value");
      if (!seen.insert(key).second) throw InputError(f.where(c) + ": the key '" + key + "' appears twice");
      p.entries.push_back({key, plist_value(f, v)});
      c = v.next_sibling();
      while (c && c.type() != pugi::node_element) c = c.next_sibling();
    }
  }
  // <data>, <date>: read as "other" (a UFO's lib may hold them)
  return p;
}

/// The top-level value of a plist file.
Plist read_plist(const fs::path& path) {
  const std::unique_ptr<XmlFile> f = load_xml(path);
  const pugi::xml_node root = f->doc.child("plist");
  if (!root) throw InputError(f->path + ":1: not a property list (no <plist> element)");
  const pugi::xml_node top = first_element(root);
  if (!top) throw InputError(f->where(root) + ": an empty property list");
  return plist_value(*f, top);
}

// ------------------------------------------------------------ glif

/// A <point> of a .glif contour.
struct GlifPoint {
  enum class Type { offcurve, move, line, curve, qcurve };
  Vec2 p{0.0};
  Type type = Type::offcurve;
  int line = 0;
  std::string name;  ///< its `name` attribute, if any
  bool smooth = false;  ///< smooth="yes"
};

double coordinate(const XmlFile& f, const pugi::xml_node& point, const char* attr) {
  const pugi::xml_attribute a = point.attribute(attr);
  if (!a) throw InputError(f.where(point) + ": <point> has no " + attr);
  const std::string text = a.value();
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != 0 || !std::isfinite(v))
    throw InputError(f.where(point) + ": <point> " + attr + "=\"" + text + "\" is not a finite number");
  return v;
}

/// The parsed points of each <contour> of a glyph's <outline>, in order, and
/// the count of <component>s.
struct GlifOutline {
  std::string name;
  std::vector<std::uint32_t> unicodes;
  std::vector<std::vector<GlifPoint>> contours;
  int components = 0;
};

GlifOutline parse_glif(const XmlFile& f) {
  const pugi::xml_node glyph = f.doc.child("glyph");
  if (!glyph) throw InputError(f.path + ":1: not a glyph (no <glyph> element)");
  GlifOutline out;
  out.name = glyph.attribute("name").value();
  if (out.name.empty()) throw InputError(f.where(glyph) + ": <glyph> has no name");
  for (pugi::xml_node u = glyph.child("unicode"); u; u = u.next_sibling("unicode")) {
    const std::string hex = u.attribute("hex").value();
    char* end = nullptr;
    const unsigned long cp = std::strtoul(hex.c_str(), &end, 16);
    if (hex.empty() || *end != 0 || cp > 0x10FFFF)
      throw InputError(f.where(u) + ": <unicode hex=\"" + hex + "\"> is not a code point");
    out.unicodes.push_back(static_cast<std::uint32_t>(cp));
  }
  const pugi::xml_node outline = glyph.child("outline");
  for (pugi::xml_node c = outline.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    const std::string tag = c.name();
    if (tag == "component") {
      ++out.components;
      continue;
    }
    if (tag != "contour") continue;
    std::vector<GlifPoint> pts;
    for (pugi::xml_node p = c.child("point"); p; p = p.next_sibling("point")) {
      GlifPoint gp;
      gp.line = f.line_of(p);
      gp.name = p.attribute("name").value();
      gp.smooth = std::string(p.attribute("smooth").value()) == "yes";
      gp.p = {coordinate(f, p, "x"), coordinate(f, p, "y")};
      const std::string type = p.attribute("type").value();
      if (type.empty() || type == "offcurve") gp.type = GlifPoint::Type::offcurve;
      else if (type == "move") gp.type = GlifPoint::Type::move;
      else if (type == "line") gp.type = GlifPoint::Type::line;
      else if (type == "curve") gp.type = GlifPoint::Type::curve;
      else if (type == "qcurve") gp.type = GlifPoint::Type::qcurve;
      else throw InputError(f.where(p) + ": <point type=\"" + type + "\"> is not a point type");
      pts.push_back(gp);
    }
    out.contours.push_back(std::move(pts));
  }
  return out;
}

/// A closed .glif contour as outline points: each off-curve point is conic
/// or cubic by the on-curve point that ends its run. nullopt with `note` set
/// for an open contour; InputError for one that is not a chain of pieces.
std::optional<std::vector<OutlinePoint>> contour_points(const XmlFile& f, const std::vector<GlifPoint>& pts,
                                                       bool& conic, bool& cubic, std::string& note, int index) {
  const int n = static_cast<int>(pts.size());
  auto at = [&](int i) { return f.path + ":" + std::to_string(pts[i].line); };
  for (int i = 0; i < n; ++i)
    if (pts[i].type == GlifPoint::Type::move) {
      if (i != 0) throw InputError(at(i) + ": a move point inside a contour (only its first point may be one)");
      if (n > 1) note = "contour " + std::to_string(index) + " is open (not judged)";
      return std::nullopt;  // an open contour, or a one-point anchor (UFO 2)
    }
  std::vector<OutlinePoint> out(n);
  bool has_on = false;
  for (int i = 0; i < n; ++i) {
    out[i].p = pts[i].p;
    if (pts[i].type == GlifPoint::Type::offcurve) continue;
    has_on = true;
    out[i].tag = OutlinePoint::Tag::on;
    // The off-curve run that ends here.
    int run = 0;
    for (int j = (i + n - 1) % n; pts[j].type == GlifPoint::Type::offcurve && run < n; j = (j + n - 1) % n) ++run;
    if (run == 0) continue;
    OutlinePoint::Tag tag = OutlinePoint::Tag::conic;
    switch (pts[i].type) {
      case GlifPoint::Type::curve:
        if (run != 2)
          throw InputError(at(i) + ": a curve point after " + std::to_string(run) +
                           " off-curve points (cmr reads 0 or 2; a quadratic piece is a qcurve)");
        tag = OutlinePoint::Tag::cubic;
        cubic = true;
        break;
      case GlifPoint::Type::qcurve: conic = true; break;
      default: throw InputError(at(i) + ": off-curve points before a line point");
    }
    for (int k = 1; k <= run; ++k) out[(i + n - k) % n].tag = tag;
  }
  if (!has_on) {
    conic = true;  // a closed quadratic loop of off-curve points only (TrueType)
    for (OutlinePoint& p : out) p.tag = OutlinePoint::Tag::conic;
  }
  bool c2 = false, c3 = false;
  for (const OutlinePoint& p : out) (p.tag == OutlinePoint::Tag::conic ? c2 : c3) |= p.tag != OutlinePoint::Tag::on;
  if (c2 && c3) throw InputError(at(0) + ": the contour mixes curve and qcurve pieces (cmr reads one kind per contour)");
  return out;
}

/// A glyph read from its .glif (without its contours made: the degree of a
/// contour of lines only is the font's, known after every glyph is read).
struct RawGlyph {
  std::string name;
  fs::path file;
  std::string error;
  GlifOutline outline;
  std::vector<std::optional<std::vector<OutlinePoint>>> contours;
  std::vector<std::string> notes;
  std::vector<std::vector<int>> lines;
  std::vector<std::vector<std::string>> labels;
  std::vector<std::vector<bool>> smooth;
  bool conic = false, cubic = false;
};

/// A .glif's glyph from its text (`text` set: read_glif_text) or its file.
RawGlyph read_raw_glyph(const fs::path& file, const std::string& listed_name, const std::string* text = nullptr) {
  RawGlyph g;
  g.name = listed_name;
  g.file = file;
  try {
    std::error_code ec;
    if (!text && !fs::exists(file, ec))
      throw InputError(file.string() + ": missing (listed in contents.plist for the glyph '" + listed_name + "')");
    std::unique_ptr<XmlFile> f;
    if (text) {
      f = std::make_unique<XmlFile>();
      f->path = file.string();
      f->text = *text;
      parse_xml(*f);
    } else {
      f = load_xml(file);
    }
    g.outline = parse_glif(*f);
    if (g.name.empty()) g.name = g.outline.name;
    if (g.outline.components > 0)
      g.notes.push_back(std::to_string(g.outline.components) +
                        (g.outline.components == 1 ? " component" : " components") +
                        " not judged here (each base glyph is judged as itself)");
    for (std::size_t c = 0; c < g.outline.contours.size(); ++c) {
      std::string note;
      g.contours.push_back(contour_points(*f, g.outline.contours[c], g.conic, g.cubic, note, static_cast<int>(c)));
      if (!note.empty()) g.notes.push_back(note);
      std::vector<int> lines;
      std::vector<std::string> labels;
      std::vector<bool> smooth;
      for (const GlifPoint& p : g.outline.contours[c])
        lines.push_back(p.line), labels.push_back(p.name), smooth.push_back(p.smooth);
      g.lines.push_back(std::move(lines));
      g.labels.push_back(std::move(labels));
      g.smooth.push_back(std::move(smooth));
    }
  } catch (const InputError& e) {
    g.error = e.what();
  }
  return g;
}

Glyph make_glyph(RawGlyph& raw, int font_degree, bool keep_zero_lines) {
  Glyph g;
  g.name = raw.name;
  g.codepoint = raw.outline.unicodes.empty() ? 0 : raw.outline.unicodes.front();
  g.source = raw.file.string();
  g.error = raw.error;
  g.notes = raw.notes;
  g.point_lines = raw.lines;
  g.point_labels = raw.labels;
  g.point_smooth = raw.smooth;
  if (!g.error.empty()) return g;
  try {
    for (std::size_t c = 0; c < raw.contours.size(); ++c) {
      if (!raw.contours[c]) continue;
      const auto& pts = *raw.contours[c];
      int degree = font_degree;
      for (const OutlinePoint& p : pts)
        if (p.tag != OutlinePoint::Tag::on) degree = p.tag == OutlinePoint::Tag::cubic ? 3 : 2;
      if (std::optional<Contour> contour =
              outline_contour(pts, static_cast<int>(c), degree, g.name, PointNaming::source, keep_zero_lines))
        g.contours.push_back(std::move(*contour));
    }
  } catch (const InputError& e) {
    g.contours.clear();
    g.error = raw.file.string() + ": " + e.what();
  }
  return g;
}

/// The default layer's folder of a UFO: "glyphs", checked against UFO 3's
/// layercontents.plist (names unique, folders present).
fs::path default_layer(const fs::path& ufo) {
  const fs::path lc = ufo / "layercontents.plist";
  std::error_code ec;
  if (!fs::exists(lc, ec)) return ufo / "glyphs";
  const Plist layers = read_plist(lc);
  if (layers.kind != Plist::Kind::array) throw InputError(lc.string() + ":1: not an array of layers");
  std::set<std::string> names;
  std::optional<fs::path> found;
  for (const Plist& l : layers.items) {
    if (l.kind != Plist::Kind::array || l.items.size() != 2 || l.items[0].kind != Plist::Kind::string ||
        l.items[1].kind != Plist::Kind::string)
      throw InputError(lc.string() + ":" + std::to_string(l.line) + ": a layer is not [name, folder]");
    if (!names.insert(l.items[0].text).second)
      throw InputError(lc.string() + ":" + std::to_string(l.line) + ": two layers are named '" + l.items[0].text + "'");
    if (l.items[1].text == "glyphs") found = ufo / "glyphs";
  }
  if (!found) throw InputError(lc.string() + ": no default layer (the folder 'glyphs')");
  return *found;
}

}  // namespace

bool is_ufo_path(const fs::path& path) {
  const std::string ext = lower_extension(path.has_filename() ? path : path.parent_path());
  return ext == ".ufo" || ext == ".glif";
}

bool is_designspace_path(const fs::path& path) { return lower_extension(path) == ".designspace"; }

bool is_source_path(const fs::path& path) { return is_ufo_path(path) || is_designspace_path(path); }

Font read_ufo(const fs::path& path_in, const GlyphSelection& which, bool keep_zero_lines) {
  const fs::path path = path_in.has_filename() ? path_in : path_in.parent_path();  // "a.ufo/" names a.ufo
  Font font;
  font.path = path_in.string();
  std::vector<RawGlyph> raw;
  if (lower_extension(path) == ".glif") {
    raw.push_back(read_raw_glyph(path, ""));
    if (!raw.back().error.empty()) throw InputError(raw.back().error);
  } else {
    std::error_code ec;
    if (!fs::is_directory(path, ec)) throw InputError(path.string() + ": not a UFO folder");
    const fs::path meta = path / "metainfo.plist";
    if (!fs::exists(meta, ec)) throw InputError(path.string() + ": not a UFO (no metainfo.plist)");
    const Plist mi = read_plist(meta);
    const Plist* version = mi.find("formatVersion");
    if (!version || version->kind != Plist::Kind::number || (version->number != 2 && version->number != 3))
      throw InputError(meta.string() + ": formatVersion must be 2 or 3");
    if (fs::exists(path / "fontinfo.plist", ec)) {
      const Plist info = read_plist(path / "fontinfo.plist");
      if (const Plist* u = info.find("unitsPerEm"); u && u->kind == Plist::Kind::number) {
        if (!(u->number >= 1 && u->number <= 16384))  // NaN too; an int cast of 1e78 is undefined
          throw InputError((path / "fontinfo.plist").string() + ":" + std::to_string(u->line) +
                           ": unitsPerEm must be from 1 to 16384 font units (OpenType's range)");
        font.units_per_em = static_cast<int>(u->number);
      }
      if (const Plist* fam = info.find("familyName"); fam && fam->kind == Plist::Kind::string) font.family = fam->text;
      if (const Plist* st = info.find("styleName"); st && st->kind == Plist::Kind::string) font.style = st->text;
    }
    const fs::path layer = default_layer(path);
    const Plist contents = read_plist(layer / "contents.plist");
    if (contents.kind != Plist::Kind::dict)
      throw InputError((layer / "contents.plist").string() + ":1: not a dictionary of glyph files");
    std::vector<std::pair<std::string, fs::path>> files;
    for (const auto& [name, file] : contents.entries) {
      if (file.kind != Plist::Kind::string || file.text.empty() || file.text.find('/') != std::string::npos)
        throw InputError((layer / "contents.plist").string() + ":" + std::to_string(file.line) +
                         ": the glyph '" + name + "' has no file name in this folder");
      files.emplace_back(name, layer / file.text);
    }
    std::sort(files.begin(), files.end());
    std::set<std::string> named(which.names.begin(), which.names.end());
    for (const std::string& n : which.names)
      if (std::none_of(files.begin(), files.end(), [&](const auto& f) { return f.first == n; }))
        throw InputError(path.string() + ": no glyph named '" + n + "'");
    // Every glyph is read when code points select: its <unicode>s are in its file.
    const bool by_codepoint = !which.codepoints.empty();
    for (const auto& [name, file] : files)
      if (which.all || by_codepoint || named.count(name)) raw.push_back(read_raw_glyph(file, name));
    if (!which.all) {
      std::vector<RawGlyph> chosen;
      std::vector<bool> taken(raw.size(), false);
      for (const std::uint32_t cp : which.codepoints) {
        bool found = false;
        for (std::size_t i = 0; i < raw.size() && !found; ++i) {
          const auto& u = raw[i].outline.unicodes;
          if (!taken[i] && std::find(u.begin(), u.end(), cp) != u.end()) taken[i] = found = true, chosen.push_back(raw[i]);
        }
        if (!found) font.missing.push_back(cp);
      }
      for (std::size_t i = 0; i < raw.size(); ++i) {
        // Named glyphs, and glyphs that cannot be read (their code points
        // are unknown): a selection by code point lists them as invalid.
        const bool broken = by_codepoint && !raw[i].error.empty();
        if (!taken[i] && (named.count(raw[i].name) || broken)) chosen.push_back(raw[i]);
      }
      raw = std::move(chosen);
    }
  }
  bool conic = false, cubic = false;
  for (const RawGlyph& g : raw) conic |= g.conic, cubic |= g.cubic;
  font.cubic = cubic || !conic;
  for (RawGlyph& g : raw) font.glyphs.push_back(make_glyph(g, font.cubic ? 3 : 2, keep_zero_lines));
  return font;
}

Glyph read_glif_text(const std::string& text, const std::string& file_name) {
  RawGlyph raw = read_raw_glyph(file_name, "", &text);
  if (!raw.error.empty()) throw InputError(raw.error);
  return make_glyph(raw, raw.conic && !raw.cubic ? 2 : 3, false);
}

// ------------------------------------------------------------ designspace

namespace {

/// The piecewise-linear function through `pts` (x ascending) at x, or x
/// itself without points; the end pieces extended.
double piecewise(const std::vector<std::pair<double, double>>& pts, double x, bool inverse) {
  if (pts.empty()) return x;
  auto X = [&](std::size_t k) { return inverse ? pts[k].second : pts[k].first; };
  auto Y = [&](std::size_t k) { return inverse ? pts[k].first : pts[k].second; };
  if (pts.size() == 1) return x - X(0) + Y(0);
  std::size_t k = 1;
  while (k + 1 < pts.size() && x > X(k)) ++k;
  const double x0 = X(k - 1), x1 = X(k), y0 = Y(k - 1), y1 = Y(k);
  return x1 == x0 ? y0 : y0 + (x - x0) * (y1 - y0) / (x1 - x0);
}

}  // namespace

double Designspace::Axis::to_design(double user) const { return piecewise(map, user, false); }
double Designspace::Axis::to_user(double design) const { return piecewise(map, design, true); }

Designspace read_designspace(const fs::path& path) {
  const std::unique_ptr<XmlFile> f = load_xml(path);
  const pugi::xml_node root = f->doc.child("designspace");
  if (!root) throw InputError(f->path + ":1: not a designspace (no <designspace> element)");
  Designspace ds;
  auto number = [&](const pugi::xml_node& n, const char* attr, bool required) {
    const pugi::xml_attribute a = n.attribute(attr);
    if (!a) {
      if (required) throw InputError(f->where(n) + ": <" + n.name() + "> has no " + attr);
      return 0.0;
    }
    char* end = nullptr;
    const double v = std::strtod(a.value(), &end);
    if (*a.value() == 0 || *end != 0 || !std::isfinite(v))
      throw InputError(f->where(n) + ": " + attr + "=\"" + a.value() + "\" is not a number");
    return v;
  };
  for (pugi::xml_node a = root.child("axes").child("axis"); a; a = a.next_sibling("axis")) {
    Designspace::Axis axis;
    axis.tag = a.attribute("tag").value();
    axis.name = a.attribute("name").value();
    if (axis.name.empty()) throw InputError(f->where(a) + ": <axis> has no name");
    if (a.attribute("values")) {  // a discrete axis (format 5): values="0 1"
      std::istringstream in(a.attribute("values").value());
      std::string word;
      while (in >> word) {
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (*end != 0 || !std::isfinite(v))
          throw InputError(f->where(a) + ": values=\"" + a.attribute("values").value() + "\" holds '" + word +
                           "', not a number");
        axis.values.push_back(v);
      }
      if (axis.values.empty()) throw InputError(f->where(a) + ": the discrete axis '" + axis.name + "' has no values");
      std::sort(axis.values.begin(), axis.values.end());
      axis.values.erase(std::unique(axis.values.begin(), axis.values.end()), axis.values.end());
      axis.minimum = axis.values.front();
      axis.maximum = axis.values.back();
      axis.default_value = number(a, "default", true);
      if (!std::binary_search(axis.values.begin(), axis.values.end(), axis.default_value))
        throw InputError(f->where(a) + ": the discrete axis '" + axis.name + "' has its default at none of its values");
    } else {
      axis.minimum = number(a, "minimum", true);
      axis.maximum = number(a, "maximum", true);
      axis.default_value = number(a, "default", true);
    }
    if (axis.minimum > axis.maximum || axis.default_value < axis.minimum || axis.default_value > axis.maximum)
      throw InputError(f->where(a) + ": the axis '" + axis.name + "' has its default outside [minimum, maximum]");
    for (pugi::xml_node m = a.child("map"); m; m = m.next_sibling("map")) {
      const std::pair<double, double> io{number(m, "input", true), number(m, "output", true)};
      if (!axis.map.empty() && (io.first <= axis.map.back().first || io.second < axis.map.back().second))
        throw InputError(f->where(m) + ": the axis '" + axis.name + "' has a <map> that is not increasing");
      axis.map.push_back(io);
    }
    // Sources locate by axis name: two axes of one name would be one (found by fuzz_designspace).
    if (std::any_of(ds.axes.begin(), ds.axes.end(), [&](const Designspace::Axis& o) { return o.name == axis.name; }))
      throw InputError(f->where(a) + ": two axes are named '" + axis.name + "'");
    ds.axes.push_back(axis);
  }
  const fs::path folder = path.parent_path();
  for (pugi::xml_node s = root.child("sources").child("source"); s; s = s.next_sibling("source")) {
    Designspace::Source src;
    src.line = f->line_of(s);
    const std::string file = s.attribute("filename").value();
    if (file.empty()) throw InputError(f->where(s) + ": <source> has no filename");
    src.path = folder / file;
    src.name = s.attribute("name") ? s.attribute("name").value() : file;
    src.layer = s.attribute("layer").value();
    for (const Designspace::Axis& a : ds.axes) src.location[a.name] = a.to_design(a.default_value);
    for (pugi::xml_node d = s.child("location").child("dimension"); d; d = d.next_sibling("dimension")) {
      const std::string axis = d.attribute("name").value();
      if (!src.location.count(axis)) throw InputError(f->where(d) + ": <dimension> names no axis ('" + axis + "')");
      const auto known = std::find_if(ds.axes.begin(), ds.axes.end(),
                                      [&](const Designspace::Axis& x) { return x.name == axis; });
      const bool discrete = !known->values.empty();
      // On a discrete axis user and design values are one; elsewhere only xvalue (design) is read.
      const double v = number(d, discrete && !d.attribute("xvalue") ? "uservalue" : "xvalue", true);
      if (discrete && !std::binary_search(known->values.begin(), known->values.end(), v))
        throw InputError(f->where(d) + ": the discrete axis '" + axis + "' has no value " + d.attribute(
                                            discrete && !d.attribute("xvalue") ? "uservalue" : "xvalue").value());
      src.location[axis] = v;
    }
    std::error_code ec;
    if (!fs::exists(src.path, ec))
      throw InputError(f->where(s) + ": the source '" + file + "' does not exist (" + src.path.string() + ")");
    src.is_default = std::all_of(ds.axes.begin(), ds.axes.end(),
                                 [&](const Designspace::Axis& a) { return src.location[a.name] == a.to_design(a.default_value); });
    ds.sources.push_back(std::move(src));
  }
  if (ds.sources.empty()) throw InputError(f->path + ": no <source>");
  return ds;
}

// ------------------------------------------------------------ write back

std::string glif_number(double v) {
  if (v == std::floor(v) && std::abs(v) < 1e15) {
    const long long i = static_cast<long long>(v);
    return std::to_string(i);
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

namespace {

/// Replaces the value of attribute `name` in the start tag at text[tag..]
/// (an XML start tag: attributes name="..." or name='...').
bool set_attribute(std::string& text, std::size_t tag, const std::string& name, const std::string& value) {
  std::size_t i = tag + 1;
  while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i])) && text[i] != '/' && text[i] != '>') ++i;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i >= text.size() || text[i] == '/' || text[i] == '>') return false;
    const std::size_t name_start = i;
    while (i < text.size() && text[i] != '=' && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    const std::string attr = text.substr(name_start, i - name_start);
    while (i < text.size() && text[i] != '=') ++i;
    ++i;
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i >= text.size() || (text[i] != '"' && text[i] != '\'')) return false;
    const char quote = text[i];
    const std::size_t value_start = ++i;
    const std::size_t value_end = text.find(quote, value_start);
    if (value_end == std::string::npos) return false;
    if (attr == name) {
      text.replace(value_start, value_end - value_start, value);
      return true;
    }
    i = value_end + 1;
  }
  return false;
}

}  // namespace

std::string rewrite_glif_points(const std::string& text, const std::vector<PointEdit>& edits,
                                const std::string& file_name) {
  XmlFile f;
  f.path = file_name;
  f.text = text;
  parse_xml(f);
  const pugi::xml_node glyph = f.doc.child("glyph");
  if (!glyph) throw InputError(file_name + ":1: not a glyph (no <glyph> element)");
  // The start tag of each point, by (contour, point).
  std::vector<std::vector<std::size_t>> tags;
  for (pugi::xml_node c = glyph.child("outline").child("contour"); c; c = c.next_sibling("contour")) {
    std::vector<std::size_t> t;
    for (pugi::xml_node p = c.child("point"); p; p = p.next_sibling("point")) {
      std::size_t at = static_cast<std::size_t>(p.offset_debug());
      while (at > 0 && text[at] != '<') --at;  // offset_debug names the element's name
      t.push_back(at);
    }
    tags.push_back(std::move(t));
  }
  // Edit from the end so that earlier offsets stay valid.
  std::vector<std::pair<std::size_t, const PointEdit*>> order;
  for (const PointEdit& e : edits) {
    if (e.contour < 0 || e.contour >= static_cast<int>(tags.size()) || e.point < 0 ||
        e.point >= static_cast<int>(tags[e.contour].size()))
      throw InputError(file_name + ": no point " + std::to_string(e.point) + " in contour " + std::to_string(e.contour));
    order.emplace_back(tags[e.contour][e.point], &e);
  }
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string out = text;
  for (const auto& [tag, e] : order) {
    if (!e->then.empty()) {  // after the element's end (the tag's '>' outside quotes), before the edit moves it
      std::size_t end = tag;
      for (char quote = 0; end < out.size() && (quote || out[end] != '>'); ++end)
        if (out[end] == '"' || out[end] == '\'') quote = quote == out[end] ? 0 : (quote ? quote : out[end]);
      if (end < out.size() && out[end - 1] != '/')  // <point ...>...</point >
        end = out.find('>', out.find("</point", end));
      if (end >= out.size()) throw InputError(file_name + ": the <point> of contour " + std::to_string(e->contour) +
                                              ", point " + std::to_string(e->point) + " has no end");
      std::size_t lead = tag;
      while (lead > 0 && std::isspace(static_cast<unsigned char>(out[lead - 1]))) --lead;
      std::string added;
      for (const NewPoint& n : e->then)
        added += out.substr(lead, tag - lead) + "<point x=\"" + glif_number(n.x) + "\" y=\"" + glif_number(n.y) + "\"" +
                 (n.node ? " type=\"curve\" smooth=\"yes\"" : "") + "/>";
      out.insert(end + 1, added);
    }
    if (e->move &&
        (!set_attribute(out, tag, "y", glif_number(e->y)) || !set_attribute(out, tag, "x", glif_number(e->x))))
      throw InputError(file_name + ": the <point> of contour " + std::to_string(e->contour) + ", point " +
                       std::to_string(e->point) + " has no x or y attribute");
  }
  return out;
}

GlyphSelection parse_glyph_selection(const std::string& spec) {
  GlyphSelection which;
  which.all = spec == "all";
  if (!which.all) which.codepoints = parse_glyph_spec(spec);
  return which;
}

}  // namespace cmr::import
