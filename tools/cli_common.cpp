#include "tools/cli_common.hpp"

#include <iostream>

#include "spline/errors.hpp"

namespace cmr::cli {

void print_json(const nlohmann::ordered_json& doc) { std::cout << doc.dump(2) << '\n'; }

void check_output_path(const std::filesystem::path& path, const std::string& option) {
  const std::filesystem::path folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(option + " " + path.string() + ": the folder " + folder.string() + " does not exist");
  if (std::filesystem::is_directory(path, ec)) throw InputError(option + " " + path.string() + ": is a directory");
}

OutputFiles::~OutputFiles() {
  for (const auto& p : written_) {
    std::error_code ec;
    std::filesystem::remove(p, ec);
  }
}

void OutputFiles::write(const std::filesystem::path& path, std::string_view bytes) {
  write_file_atomic(path, bytes);
  written_.push_back(path);
}

}  // namespace cmr::cli
