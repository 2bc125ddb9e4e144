// tools/figures: every claim about the paper's figures holds (CPU backend),
// the files are written and readable, and examples/figures/ is current.
#include <cairo.h>
#include <gtest/gtest.h>
#include <libxml/HTMLparser.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/figures.hpp"

namespace cmr::fig {
namespace {

namespace fs = std::filesystem;

/// A fresh folder (removed first) under this process's scratch folder.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cmr_figures_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  return dir;
}

const fs::path& out_dir() {
  static const fs::path dir = scratch("out");
  return dir;
}

/// One run for the whole suite: the claims and files are what every test looks at.
const FiguresResult& run_once() {
  static const FiguresResult result = [] {
    FiguresOptions o;
    o.out = out_dir();
    o.backend = std::make_shared<CpuRegionBackend>();
    return make_figures(o);
  }();
  return result;
}

TEST(Figures, EveryClaimPasses) {
  const FiguresResult& r = run_once();
  EXPECT_GE(r.claims.size(), 20u);
  for (const Claim& c : r.claims) EXPECT_TRUE(c.pass) << c.figure << ": " << c.text << " -- measured: " << c.detail;
  EXPECT_TRUE(r.all_pass());
}

TEST(Figures, EveryFigureHasClaims) {
  const FiguresResult& r = run_once();
  for (const char* f : {"Fig. 1", "Fig. 2", "Fig. 3", "Fig. 4", "Fig. 5", "Fig. 6", "Fig. 7", "Fig. 8", "Fig. 9",
                        "Fig. 10", "Fig. 11", "Fig. 12", "Fig. 13"}) {
    const std::string prefix = f;
    const auto n = std::count_if(r.claims.begin(), r.claims.end(), [&](const Claim& c) {
      if (c.figure.rfind(prefix, 0) != 0) return false;
      // "Fig. 1" must not count "Fig. 10a".
      return c.figure.size() == prefix.size() || !std::isdigit(static_cast<unsigned char>(c.figure[prefix.size()]));
    });
    EXPECT_GT(n, 0) << f;
  }
}

TEST(Figures, WritesValidPngsAndAnIndex) {
  const FiguresResult& r = run_once();
  ASSERT_EQ(r.figures.size(), 13u);
  for (const FigureFile& f : r.figures) {
    const fs::path png = out_dir() / (f.id + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
    EXPECT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS) << png;
    EXPECT_GE(cairo_image_surface_get_width(s), 400) << png;
    cairo_surface_destroy(s);
  }
  for (const fs::path& p : r.written) EXPECT_TRUE(fs::exists(p)) << p;
  const fs::path index = r.written.back();
  ASSERT_EQ(index.filename(), "index.html");
  std::ifstream in(index);
  std::stringstream html;
  html << in.rdbuf();
  for (const FigureFile& f : r.figures) EXPECT_NE(html.str().find(f.id + ".png"), std::string::npos) << f.id;
  EXPECT_EQ(html.str().find(">FAIL<"), std::string::npos);
}

TEST(Figures, ExampleFilesAreCurrent) {
  for (const BSpline& s : figure_splines()) {
    const fs::path p = fs::path(CMR_SOURCE_DIR) / "examples" / "figures" / (s.name() + ".json");
    ASSERT_TRUE(fs::exists(p)) << p << " is missing: run `cmr figures --out DIR` and copy DIR/*.json there";
    const BSpline f = read_spline_file(p);
    EXPECT_EQ(f.degree(), s.degree()) << p;
    EXPECT_EQ(f.knots(), s.knots()) << p;
    ASSERT_EQ(f.point_count(), s.point_count()) << p;
    for (int i = 0; i < s.point_count(); ++i) {
      EXPECT_EQ(f.points()[i].x, s.points()[i].x) << p << " point " << i;
      EXPECT_EQ(f.points()[i].y, s.points()[i].y) << p << " point " << i;
    }
  }
}

TEST(Figures, BadOptionsAreInputErrors) {
  FiguresOptions o;
  o.backend = std::make_shared<CpuRegionBackend>();
  o.size = 10;
  o.out = scratch("small");
  EXPECT_THROW(make_figures(o), InputError);
  o.size = 400;
  const fs::path blocker = scratch("blocker");
  fs::create_directories(blocker.parent_path());
  std::ofstream(blocker) << "a file where the folder should go";
  o.out = blocker / "figures";
  EXPECT_THROW(make_figures(o), InputError);
}

// ------------------------------------------------------------ page and SVG --

using XmlDoc = std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)>;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string name_of(const xmlNode* n) { return reinterpret_cast<const char*>(n->name); }

std::string text_of(xmlNode* n) {
  xmlChar* t = xmlNodeGetContent(n);
  std::string s = t ? reinterpret_cast<const char*>(t) : "";
  xmlFree(t);
  return s;
}

std::string attribute(xmlNode* n, const char* name) {
  xmlChar* v = xmlGetProp(n, reinterpret_cast<const xmlChar*>(name));
  std::string s = v ? reinterpret_cast<const char*>(v) : "";
  xmlFree(v);
  return s;
}

/// Every element under n, depth first, in document order.
void elements(xmlNode* n, std::vector<xmlNode*>& out) {
  for (xmlNode* c = n ? n->children : nullptr; c; c = c->next)
    if (c->type == XML_ELEMENT_NODE) {
      out.push_back(c);
      elements(c, out);
    }
}

bool blank(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c); });
}

// index.html, parsed as HTML: each figure is an <h2> with its title, then an
// <img> of its PNG whose alt is the title, then a <p> with its caption; none
// of them empty (they were, when the texts were read after being moved).
TEST(Figures, IndexHasAHeadingAnImageWithAltAndACaptionPerFigure) {
  const FiguresResult& r = run_once();
  const std::string html = slurp(out_dir() / "index.html");
  XmlDoc doc(htmlReadMemory(html.data(), static_cast<int>(html.size()), "index.html", "utf-8",
                            HTML_PARSE_NOERROR | HTML_PARSE_NOWARNING | HTML_PARSE_NONET),
             &xmlFreeDoc);
  ASSERT_TRUE(doc) << "index.html does not parse as HTML";
  std::vector<xmlNode*> all;
  elements(xmlDocGetRootElement(doc.get()), all);
  std::size_t figures = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (name_of(all[i]) != "img") continue;
    const std::string src = attribute(all[i], "src"), alt = attribute(all[i], "alt");
    const auto f = std::find_if(r.figures.begin(), r.figures.end(), [&](const FigureFile& x) { return x.id + ".png" == src; });
    ASSERT_NE(f, r.figures.end()) << "an image of no figure: " << src;
    ++figures;
    EXPECT_FALSE(blank(alt)) << src << ": empty alt text";
    EXPECT_EQ(alt, f->title) << src;
    // The nearest <h2> before the image and the first <p> after it.
    std::string heading, caption;
    for (std::size_t j = i; j-- > 0;)
      if (name_of(all[j]) == "h2") {
        heading = text_of(all[j]);
        break;
      }
    for (std::size_t j = i + 1; j < all.size(); ++j)
      if (name_of(all[j]) == "p") {
        caption = text_of(all[j]);
        break;
      }
    EXPECT_FALSE(blank(heading)) << src << ": empty heading";
    EXPECT_EQ(heading, f->title) << src;
    EXPECT_FALSE(blank(caption)) << src << ": empty caption";
    EXPECT_EQ(caption, f->caption) << src;
  }
  EXPECT_EQ(figures, r.figures.size()) << "every figure has one image on the page";
}

// Panel letters: every panel that starts with a letter has its own, in order
// from (a) with none left out; a panel belonging to another says so
// ("curvature plot of (a)") instead of repeating its letter (they repeated:
// (a)(a), (c)(c), and Fig. 12 had no (f)).
TEST(Figures, PanelLettersAreDistinctAndConsecutive) {
  const FiguresResult& r = run_once();
  for (const FigureFile& f : r.figures) {
    std::string letters;
    for (const std::string& caption : f.panels)
      if (caption.size() >= 3 && caption[0] == '(' && caption[2] == ')') letters += caption[1];
    std::string want;
    for (std::size_t k = 0; k < letters.size(); ++k) want += static_cast<char>('a' + k);
    EXPECT_EQ(letters, want) << f.id;
  }
}

// Each figure's SVG is well-formed XML with an <svg> root of the PNG's size,
// embedded region images (one per region panel) and drawn text and lines.
TEST(Figures, SvgBesideEveryPngIsWellFormedWithTheExpectedElements) {
  const FiguresResult& r = run_once();
  for (const FigureFile& f : r.figures) {
    const fs::path svg = out_dir() / (f.id + ".svg");
    ASSERT_TRUE(fs::exists(svg)) << svg;
    EXPECT_NE(std::find(r.written.begin(), r.written.end(), svg), r.written.end()) << svg << " not listed as written";
    const std::string xml = slurp(svg);
    XmlDoc doc(xmlReadMemory(xml.data(), static_cast<int>(xml.size()), svg.c_str(), nullptr,
                             XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING | XML_PARSE_HUGE),
               &xmlFreeDoc);
    ASSERT_TRUE(doc) << svg << " is not well-formed XML";
    xmlNode* root = xmlDocGetRootElement(doc.get());
    ASSERT_EQ(name_of(root), "svg") << svg;
    cairo_surface_t* png = cairo_image_surface_create_from_png((out_dir() / (f.id + ".png")).c_str());
    const int width = cairo_image_surface_get_width(png), height = cairo_image_surface_get_height(png);
    cairo_surface_destroy(png);
    EXPECT_EQ(std::stod(attribute(root, "width")), width) << svg;
    EXPECT_EQ(std::stod(attribute(root, "height")), height) << svg;
    std::vector<xmlNode*> all;
    elements(root, all);
    std::map<std::string, int> n;
    for (xmlNode* e : all) ++n[name_of(e)];
    EXPECT_GE(n["image"], 1) << svg << ": no embedded region image";
    EXPECT_GE(n["path"], 10) << svg << ": too few paths (curves, frames, glyphs)";
    EXPECT_GE(n["use"], 20) << svg << ": too few glyphs (Cairo draws text as <use> of glyph symbols)";
  }
}

// No two labels drawn inside one panel overlap (point names, axis and knot
// values, class tags), in every figure; and the region panels are named.
TEST(Figures, LabelsInsideAPanelNeverOverlap) {
  const FiguresResult& r = run_once();
  for (const FigureFile& f : r.figures) {
    ASSERT_FALSE(f.labels.empty()) << f.id;
    for (std::size_t p = 0; p < f.labels.size(); ++p) {
      const auto& boxes = f.labels[p];
      EXPECT_FALSE(boxes.empty()) << f.id << " panel " << p << " has no labels";
      for (std::size_t i = 0; i < boxes.size(); ++i)
        for (std::size_t j = i + 1; j < boxes.size(); ++j)
          EXPECT_FALSE(boxes[i].intersects(boxes[j]))
              << f.id << " panel " << p << ": '" << boxes[i].text << "' at (" << boxes[i].x0 << ", " << boxes[i].y0
              << ") overlaps '" << boxes[j].text << "' at (" << boxes[j].x0 << ", " << boxes[j].y0 << ")";
    }
  }
  // Fig. 13(b) is the crowded one: 36 points around a small loop. Most keep their name.
  const auto f13 = std::find_if(r.figures.begin(), r.figures.end(), [](const FigureFile& f) { return f.id == "fig13"; });
  ASSERT_NE(f13, r.figures.end());
  const auto& chain = f13->labels[1];
  const long names = std::count_if(chain.begin(), chain.end(), [](const draw::TextBox& b) { return b.text[0] == 'P'; });
  EXPECT_GE(names, 30) << "Fig. 13(b) names";
}

}  // namespace
}  // namespace cmr::fig
