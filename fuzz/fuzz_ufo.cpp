// A UFO's property lists: the input is cut at NUL bytes into
// metainfo.plist, fontinfo.plist, layercontents.plist and the default
// layer's contents.plist (a missing part: that file is absent), laid out as
// a tiny UFO in a temp folder with one fixed glyph file (glyphs/a.glif),
// and read with read_ufo (every glyph, and glyphs by code point and name).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "io/ufo.hpp"
#include "spline/errors.hpp"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& p, std::string_view bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fs::path ufo = [] {
    const fs::path p = fs::temp_directory_path() / ("cmr_fuzz_ufo_" + std::to_string(::getpid())) / "f.ufo";
    fs::create_directories(p / "glyphs");
    write(p / "glyphs" / "a.glif",
          "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<glyph name=\"a\" format=\"2\">\n"
          "  <unicode hex=\"0061\"/>\n  <outline>\n    <contour>\n"
          "      <point x=\"0\" y=\"0\" type=\"line\"/>\n      <point x=\"100\" y=\"0\" type=\"line\"/>\n"
          "      <point x=\"100\" y=\"100\" type=\"line\"/>\n    </contour>\n  </outline>\n</glyph>\n");
    return p;
  }();
  static const char* const names[] = {"metainfo.plist", "fontinfo.plist", "layercontents.plist", "glyphs/contents.plist"};
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  std::size_t pos = 0;
  for (const char* name : names) {
    std::error_code ec;
    if (pos > in.size()) {
      fs::remove(ufo / name, ec);
      continue;
    }
    const std::size_t nul = std::min(in.find('\0', pos), in.size());
    write(ufo / name, in.substr(pos, nul - pos));
    pos = nul + 1;
  }
  try {
    (void)cmr::import::read_ufo(ufo, {.all = true});
  } catch (const cmr::InputError&) {
  }
  try {
    (void)cmr::import::read_ufo(ufo, {.codepoints = {0x61, 0x62}});
  } catch (const cmr::InputError&) {
  }
  try {
    (void)cmr::import::read_ufo(ufo, {.names = {"a"}});
  } catch (const cmr::InputError&) {
  }
  return 0;
}
