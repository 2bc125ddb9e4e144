#include "tools/cli_common.hpp"

#include <fstream>
#include <iostream>

#include "spline/errors.hpp"

namespace cmr::cli {

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

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

void check_output_path(const std::filesystem::path& path, const std::string& option) {
  const std::filesystem::path folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(option + " " + path.string() + ": the folder " + folder.string() + " does not exist");
}

OutputFiles::~OutputFiles() {
  for (const auto& p : written_) {
    std::error_code ec;
    std::filesystem::remove(p, ec);
  }
}

void OutputFiles::write(const std::filesystem::path& path, const std::string& bytes) {
  write_file_atomic(path, bytes);
  written_.push_back(path);
}

}  // namespace cmr::cli
