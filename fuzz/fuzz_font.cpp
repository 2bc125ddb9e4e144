// The font importer (FreeType underneath) on arbitrary bytes, through a file
// as cmr import reads it.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/font.hpp"
#include "spline/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("cmr_fuzz_font_" + std::to_string(::getpid()) + ".ttf");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    // Latin letters (the common case) and the Lycian letters of the TrueType
    // seed (fuzz/run.sh: small complete fonts, so -max_len keeps them whole).
    static const auto codepoints = cmr::import::parse_glyph_spec("A-C,o,U+10280-U+10284");
    const auto font = cmr::import::read_font(path, codepoints);
    for (const auto& g : font.glyphs)
      for (const auto& c : g.contours) (void)cmr::import::contour_json(c).dump();
  } catch (const cmr::InputError&) {
  } catch (const std::exception&) {
  }
  return 0;
}
