#include "tools/cli_common.hpp"

#include <fstream>
#include <iostream>

#include "spline/errors.hpp"

namespace cmr::cli {

void print_json(const nlohmann::ordered_json& doc) { std::cout << doc.dump(2) << '\n'; }

void write_file_atomic(const std::filesystem::path& path, const std::string& bytes) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError(path.string() + ": cannot write (does the folder exist?)");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw InputError(path.string() + ": write failed");
    }
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace cmr::cli
