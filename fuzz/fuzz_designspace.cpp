// A .designspace document (format 4 or 5), read with read_designspace from
// a temp folder that holds two source UFOs the document may name (a.ufo and
// b.ufo, empty folders: the reader only checks that a source exists).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/ufo.hpp"
#include "spline/errors.hpp"

namespace fs = std::filesystem;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fs::path path = [] {
    const fs::path dir = fs::temp_directory_path() / ("cmr_fuzz_designspace_" + std::to_string(::getpid()));
    fs::create_directories(dir / "a.ufo");
    fs::create_directories(dir / "b.ufo");
    return dir / "f.designspace";
  }();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const auto ds = cmr::import::read_designspace(path);
    for (const auto& a : ds.axes)
      if (!(a.minimum <= a.default_value && a.default_value <= a.maximum)) __builtin_trap();
    for (const auto& s : ds.sources)
      if (s.location.size() < ds.axes.size()) __builtin_trap();  // missing axes are at their default
  } catch (const cmr::InputError&) {
  }
  return 0;
}
