// A single .glif file: read through read_ufo (a temp NAME.glif, as cmr
// import and report read one), and the point rewriter on the same bytes with
// a few edits taken from the input's last bytes (some adding points, as
// `cmr fix --add-nodes` does). What the rewriter returns is still a glyph it
// can read.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/ufo.hpp"
#include "spline/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("cmr_fuzz_glif_" + std::to_string(::getpid()) + ".glif");
  const std::string text(reinterpret_cast<const char*>(data), size);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  }
  try {
    const auto font = cmr::import::read_ufo(path, {.all = true});
    for (const auto& g : font.glyphs)
      for (const auto& c : g.contours) (void)cmr::import::contour_json(c).dump();
  } catch (const cmr::InputError&) {
  }
  // Edits: up to three points (contour 0-1, point 0-7) with new coordinates
  // that are integers, halves, tiny and huge values.
  static constexpr double values[] = {0, 455, -0.25, 455.5, 1e-300, -1.7e308, 1e15, 0.1};
  std::vector<cmr::import::PointEdit> edits;
  const std::uint8_t tail = size ? data[size - 1] : 0;
  for (std::size_t i = 0; i < 1u + (tail & 3u) && i < size; ++i) {
    const std::uint8_t b = data[size - 1 - i];
    edits.push_back({.contour = (b >> 7) & 1, .point = (b >> 4) & 7, .x = values[b & 7], .y = values[(b >> 3) & 7]});
  }
  // `cmr fix --add-nodes`: points added after the first edited one (its x
  // and y kept or set), and the text read back as a glyph.
  if ((tail & 4u) && !edits.empty()) {
    edits.front().then = {{values[tail & 7], 1, false}, {2, values[(tail >> 3) & 7], true}};
    edits.front().move = (tail & 8u) != 0;
  }
  std::string rewritten;
  try {
    rewritten = cmr::import::rewrite_glif_points(text, edits, "f.glif");
  } catch (const cmr::InputError&) {
    return 0;
  }
  try {
    (void)cmr::import::rewrite_glif_points(rewritten, {}, "f.glif");
  } catch (const cmr::InputError&) {
    __builtin_trap();  // a glyph the rewriter read became one it cannot read
  }
  try {
    (void)cmr::import::read_glif_text(rewritten, "f.glif");
  } catch (const cmr::InputError&) {  // an outline the reader refuses (one line): not a finding
  }
  return 0;
}
