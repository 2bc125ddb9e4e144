// Font sources (io/ufo.hpp): what the fuzz harnesses found, held here.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/ufo.hpp"
#include "spline/errors.hpp"

namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / ("cmr_ufo_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string glif(const std::string& name) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<glyph name=\"" + name + "\" format=\"2\">\n  <outline>\n"
         "    <contour>\n      <point x=\"0\" y=\"0\" type=\"line\"/>\n      <point x=\"100\" y=\"0\" type=\"line\"/>\n"
         "      <point x=\"100\" y=\"100\" type=\"line\"/>\n    </contour>\n  </outline>\n</glyph>\n";
}

cmr::import::GlyphSelection every_glyph() {
  cmr::import::GlyphSelection all;
  all.all = true;
  return all;
}



// fuzz_glif: a glyph name that is not UTF-8 was read, and writing the
// glyph's contours as JSON threw nlohmann's type_error 316 (std::terminate in
// cmr import). Now the file is refused where it is read, naming the line.
TEST(UfoRead, TextThatIsNotUtf8IsAnInputErrorNamingTheLine) {
  const fs::path bad = write("bad.glif", glif("a\xE1\xE1"));
  try {
    (void)cmr::import::read_ufo(bad, every_glyph());
    FAIL() << "no InputError";
  } catch (const cmr::InputError& e) {
    EXPECT_EQ(std::string(e.what()), bad.string() + ":2: not UTF-8 (byte 0xE1)");
  }
  EXPECT_THROW((void)cmr::import::rewrite_glif_points(glif("a\xE1\xE1"), {}, "bad.glif"), cmr::InputError);
  // The fuzzer's own input (fuzz/corpus/glif/not_utf8_name) is refused too.
  std::ifstream in(fs::path(CMR_SOURCE_DIR) / "fuzz/corpus/glif/not_utf8_name", std::ios::binary);
  const std::string found((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(found.empty());
  EXPECT_THROW((void)cmr::import::read_ufo(write("found.glif", found), every_glyph()), cmr::InputError);
  // UTF-8 names, of any script, are read.
  const auto font = cmr::import::read_ufo(write("ok.glif", glif("\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80")), every_glyph());
  ASSERT_EQ(font.glyphs.size(), 1u);
  EXPECT_EQ(font.glyphs[0].name, "\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80");
  EXPECT_EQ(font.glyphs[0].contours.size(), 1u);
}

// fuzz_designspace: two <axis> elements named "Width" were both kept, and a
// source's location (by axis name) held one of them. Now refused.
TEST(UfoRead, DesignspaceWithTwoAxesOfOneNameIsAnInputError) {
  fs::create_directories(scratch() / "a.ufo");
  const fs::path p = write("two.designspace",
                           "<?xml version='1.0' encoding='UTF-8'?>\n<designspace format=\"5.0\">\n  <axes>\n"
                           "    <axis tag=\"wdth\" name=\"Width\" minimum=\"75\" maximum=\"100\" default=\"100\"/>\n"
                           "    <axis tag=\"wdt2\" name=\"Width\" minimum=\"0\" maximum=\"10\" default=\"5\"/>\n  </axes>\n"
                           "  <sources><source filename=\"a.ufo\"/></sources>\n</designspace>\n");
  try {
    (void)cmr::import::read_designspace(p);
    FAIL() << "no InputError";
  } catch (const cmr::InputError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":5: two axes are named 'Width'");
  }
  std::ifstream in(fs::path(CMR_SOURCE_DIR) / "fuzz/corpus/designspace/two_axes_one_name", std::ios::binary);
  const std::string found((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(found.empty());
  EXPECT_THROW((void)cmr::import::read_designspace(write("found.designspace", found)), cmr::InputError);
}

// Format 5's discrete axes (values="..."): their values read, a source's
// location on one is one of them (xvalue or uservalue), and a default or a
// location at none of them is refused with the line.
TEST(UfoRead, DesignspaceDiscreteAxesAreRead) {
  fs::create_directories(scratch() / "a.ufo");
  fs::create_directories(scratch() / "b.ufo");
  auto doc = [](const std::string& italic_default, const std::string& b_location) {
    return "<?xml version='1.0' encoding='UTF-8'?>\n<designspace format=\"5.0\">\n  <axes>\n"
           "    <axis tag=\"wght\" name=\"Weight\" minimum=\"100\" maximum=\"900\" default=\"400\"/>\n"
           "    <axis tag=\"ital\" name=\"Italic\" values=\"1 0\" default=\"" + italic_default + "\"/>\n  </axes>\n"
           "  <sources>\n    <source filename=\"a.ufo\"/>\n"
           "    <source filename=\"b.ufo\" name=\"Italic\"><location>" + b_location + "</location></source>\n"
           "  </sources>\n</designspace>\n";
  };
  const cmr::import::Designspace ds = cmr::import::read_designspace(
      write("discrete.designspace", doc("0", "<dimension name=\"Italic\" uservalue=\"1\"/>")));
  ASSERT_EQ(ds.axes.size(), 2u);
  EXPECT_TRUE(ds.axes[0].values.empty());
  EXPECT_EQ(ds.axes[1].values, (std::vector<double>{0, 1}));
  EXPECT_EQ(ds.axes[1].minimum, 0);
  EXPECT_EQ(ds.axes[1].maximum, 1);
  ASSERT_EQ(ds.sources.size(), 2u);
  EXPECT_TRUE(ds.sources[0].is_default);
  EXPECT_EQ(ds.sources[1].location.at("Italic"), 1);
  EXPECT_FALSE(ds.sources[1].is_default);
  const fs::path bad_default = write("bad_default.designspace", doc("0.5", ""));
  try {
    (void)cmr::import::read_designspace(bad_default);
    FAIL() << "no InputError";
  } catch (const cmr::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              bad_default.string() + ":5: the discrete axis 'Italic' has its default at none of its values");
  }
  const fs::path bad_location =
      write("bad_location.designspace", doc("0", "<dimension name=\"Italic\" xvalue=\"0.5\"/>"));
  try {
    (void)cmr::import::read_designspace(bad_location);
    FAIL() << "no InputError";
  } catch (const cmr::InputError& e) {
    EXPECT_EQ(std::string(e.what()), bad_location.string() + ":9: the discrete axis 'Italic' has no value 0.5");
  }
  EXPECT_THROW((void)cmr::import::read_designspace(write("bad_values.designspace",
                                                         "<?xml version='1.0'?>\n<designspace format=\"5.0\"><axes>"
                                                         "<axis tag=\"ital\" name=\"Italic\" values=\"0 x\" default=\"0\"/>"
                                                         "</axes><sources><source filename=\"a.ufo\"/></sources>"
                                                         "</designspace>\n")),
               cmr::InputError);
}

}  // namespace

// `cmr fix --add-nodes`: added points follow their point, each with the
// whitespace before that point's element; a point that only leads added
// ones keeps its bytes; the text reads back with the new points in order.
TEST(UfoWrite, AddedPointsFollowTheirPointAndReadBack) {
  const std::string text =
      "<?xml version='1.0' encoding='UTF-8'?>\n<glyph name=\"o\" format=\"2\">\n  <outline>\n    <contour>\n"
      "      <point x=\"0\" y=\"0\" type=\"curve\" smooth=\"yes\"/>\n      <point x=\"0.0\" y=\"50\"/>\n"
      "      <point x='50' y='100' name=\"a>b\"/>\n      <point x=\"100\" y=\"100\" type=\"curve\"/>\n"
      "      <point x=\"100\" y=\"0\" type=\"line\"/>\n    </contour>\n  </outline>\n</glyph>\n";
  cmr::import::PointEdit lead{0, 1, 0, 0, false, {{10, 70, false}, {25, 80, true}, {40, 90, false}}};
  const cmr::import::PointEdit moved{0, 2, 60, 100};
  const std::string out = cmr::import::rewrite_glif_points(text, {lead, moved}, "o.glif");
  EXPECT_EQ(out,
            "<?xml version='1.0' encoding='UTF-8'?>\n<glyph name=\"o\" format=\"2\">\n  <outline>\n    <contour>\n"
            "      <point x=\"0\" y=\"0\" type=\"curve\" smooth=\"yes\"/>\n      <point x=\"0.0\" y=\"50\"/>\n"
            "      <point x=\"10\" y=\"70\"/>\n      <point x=\"25\" y=\"80\" type=\"curve\" smooth=\"yes\"/>\n"
            "      <point x=\"40\" y=\"90\"/>\n"
            "      <point x='60' y='100' name=\"a>b\"/>\n      <point x=\"100\" y=\"100\" type=\"curve\"/>\n"
            "      <point x=\"100\" y=\"0\" type=\"line\"/>\n    </contour>\n  </outline>\n</glyph>\n");
  const cmr::import::Glyph g = cmr::import::read_glif_text(out, "o.glif");
  EXPECT_EQ(g.name, "o");
  EXPECT_EQ(g.source, "o.glif");
  ASSERT_EQ(g.contours.size(), 1u);
  ASSERT_EQ(g.point_smooth.size(), 1u);
  EXPECT_EQ(g.point_smooth[0].size(), 8u);  // 5 points and 3 added
  EXPECT_TRUE(g.point_smooth[0][3]);        // the added node
  EXPECT_EQ(g.point_lines[0][3], 8);        // on its own line
  EXPECT_THROW((void)cmr::import::read_glif_text("<glyph", "bad.glif"), cmr::InputError);
}
