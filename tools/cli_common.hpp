#pragma once
// Shared pieces of the cmr command: exit codes, output helpers.
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace cmr::cli {

enum Exit : int { kOk = 0, kFail = 1, kInvalid = 2, kEnvironment = 3 };

/// Thrown by commands for environment failures (no Vulkan device, ...): exit 3.
struct EnvironmentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Text made safe for HTML element content and attribute values.
std::string html_escape(const std::string& text);

/// Prints JSON to stdout (2-space indent, one trailing newline).
void print_json(const nlohmann::ordered_json& doc);
/// Writes a file atomically: a temporary name in the same folder, then rename.
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);

/// Throws InputError unless `path`'s folder exists (checked before any work,
/// so that a bad output path fails fast and writes nothing).
void check_output_path(const std::filesystem::path& path, const std::string& option);

/// Files written by one command: all or none. Each file is written atomically;
/// if a later one fails, the earlier ones are removed again before the error
/// propagates.
class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();
  /// Writes bytes to path (atomically) and remembers it.
  void write(const std::filesystem::path& path, const std::string& bytes);
  /// Runs writer(path) (which must write path atomically) and remembers it.
  template <class Writer>
  void write_with(const std::filesystem::path& path, Writer&& writer) {
    writer(path);
    written_.push_back(path);
  }
  /// Keeps the files: call after the last write.
  void keep() { written_.clear(); }

 private:
  std::vector<std::filesystem::path> written_;
};

/// Each command registers itself; the callback sets the exit code.
void add_segments_command(CLI::App& app, int& exit_code);
void add_analyze_command(CLI::App& app, int& exit_code);
void add_region_command(CLI::App& app, int& exit_code);
void add_figures_command(CLI::App& app, int& exit_code);
void add_report_command(CLI::App& app, int& exit_code);
void add_edit_command(CLI::App& app, int& exit_code);  // tools/cmd_edit.cpp, built with the editor

}  // namespace cmr::cli
