#pragma once
// Shared pieces of the cmr command: exit codes, output helpers.
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace cmr::cli {

enum Exit : int { kOk = 0, kFail = 1, kInvalid = 2, kEnvironment = 3 };

/// Thrown by commands for environment failures (no Vulkan device, ...): exit 3.
struct EnvironmentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Prints JSON to stdout (2-space indent, one trailing newline).
void print_json(const nlohmann::ordered_json& doc);
/// Writes a file atomically: a temporary name in the same folder, then rename.
void write_file_atomic(const std::filesystem::path& path, const std::string& bytes);

/// Each command registers itself; the callback sets the exit code.
void add_segments_command(CLI::App& app, int& exit_code);
void add_analyze_command(CLI::App& app, int& exit_code);
void add_region_command(CLI::App& app, int& exit_code);
void add_figures_command(CLI::App& app, int& exit_code);
void add_report_command(CLI::App& app, int& exit_code);

}  // namespace cmr::cli
