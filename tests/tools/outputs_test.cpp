// The cmr command's outputs and exit codes, one row per case (issue 12,
// "Outputs never lost or mixed" and "CLI polish"): each row runs the real
// binary in a fresh folder and asserts the exit code, the one stderr line (or
// none) and the state of the file system afterwards.
#include <fcntl.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tools/cli_common.hpp"
#include "io/output.hpp"

namespace {

namespace fs = std::filesystem;

const std::string kUniform = std::string(CMR_SOURCE_DIR) + "/examples/uniform.json";
const std::string kClamped = std::string(CMR_SOURCE_DIR) + "/examples/clamped.json";
const std::string kLavapipe = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

/// Every entry under `dir`, relative, sorted (folders end in '/').
std::vector<std::string> tree(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    std::string name = fs::relative(it->path(), dir).string();
    if (it->is_directory(ec) && !it->is_symlink(ec)) name += '/';
    names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : " ") + x;
  return s;
}

/// A binary PGM ("P5") of w x h with 255 levels and exactly w*h bytes after the header.
bool valid_pgm(const std::string& bytes, int w, int h) {
  const std::string header = "P5\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
  return bytes.size() == header.size() + static_cast<std::size_t>(w) * h && bytes.compare(0, header.size(), header) == 0;
}

bool is_png(const std::string& bytes) { return bytes.size() > 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0; }

struct Outcome {
  int code = -1;
  std::string out, err;
};

/// One row of the table.
struct Case {
  Case(const char* n, std::string c) : name(n), command(std::move(c)) {}
  const char* name;
  /// Shell command; CMR is the binary, DIR the row's fresh folder. Run as
  /// `exec COMMAND` unless `compound` (so that cmr keeps the child's pid).
  std::string command;
  int code = 0;
  /// A part of the one stderr line; empty: stderr must be empty.
  std::string err_part;
  /// Prepares DIR; returns a reason to skip the row, or "".
  std::function<std::string(const fs::path&)> setup = [](const fs::path&) { return std::string(); };
  /// Checks DIR (and stdout) afterwards.
  std::function<void(const fs::path&, const Outcome&)> check = [](const fs::path&, const Outcome&) {};
  /// Runs in the forked child before exec (its pid is cmr's).
  std::function<void(const fs::path&)> in_child;
  bool compound = false;
  /// Cleanup after the check (unmount).
  std::function<void(const fs::path&)> teardown;
};

std::string substitute(std::string text, const fs::path& dir) {
  for (std::size_t at; (at = text.find("CMR")) != std::string::npos;) text.replace(at, 3, CMR_BINARY);
  for (std::size_t at; (at = text.find("DIR")) != std::string::npos;) text.replace(at, 3, dir.string());
  return text;
}

Outcome run_case(const Case& c, const fs::path& dir, const fs::path& io) {
  const std::string command = (c.compound ? "" : "exec ") + substitute(c.command, dir);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open((io / "stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open((io / "stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0) ::_exit(120);
    if (c.in_child) c.in_child(dir);
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(121);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  Outcome r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(io / "stdout");
  r.err = slurp(io / "stderr");
  return r;
}

/// gtest prints a failing row by its name.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Outputs : public ::testing::TestWithParam<Case> {};

TEST_P(Outputs, ExitCodeOneStderrLineAndFiles) {
  const Case& c = GetParam();
  const fs::path root = fs::temp_directory_path() / ("cmr_outputs_test_" + std::to_string(::getpid()));
  const fs::path dir = root / c.name, io = root / (std::string(c.name) + ".io");
  fs::remove_all(dir);
  fs::remove_all(io);
  fs::create_directories(dir);
  fs::create_directories(io);
  const std::string skip = c.setup(dir);
  if (!skip.empty()) GTEST_SKIP() << skip;
  const Outcome r = run_case(c, dir, io);
  EXPECT_EQ(r.code, c.code) << c.name << ": stderr: " << r.err;
  if (c.err_part.empty()) {
    // A success prints nothing on stderr but notes (an empty region, say).
    std::istringstream lines(r.err);
    for (std::string line; std::getline(lines, line);)
      EXPECT_EQ(line.rfind("note: ", 0), 0u) << c.name << ": not a note on stderr: " << line;
  } else {
    EXPECT_NE(r.err.find(c.err_part), std::string::npos) << c.name << ": expected '" << c.err_part << "' in: " << r.err;
    EXPECT_TRUE(!r.err.empty() && r.err.find('\n') == r.err.size() - 1) << c.name << ": not one line: " << r.err;
  }
  c.check(dir, r);
  if (c.teardown) c.teardown(dir);
}

// ------------------------------------------------------------------ helpers --

/// A region command on the CPU backend (32x32 images unless --size is given).
std::string region(const std::string& rest) {
  return "CMR region " + kUniform + " --backend cpu " + (rest.find("--size") == std::string::npos ? "--size 32x32 " : "") +
         rest;
}

/// A name longer than NAME_MAX: creating it fails with ENAMETOOLONG after
/// everything before it was computed and staged.
const std::string kTooLong = std::string(300, 'n') + ".png";

auto old_file(const std::string& name, const std::string& text = "OLD") {
  return [name, text](const fs::path& dir) {
    put(dir / name, text);
    return std::string();
  };
}

/// Mounts a 64 KiB tmpfs at DIR/small, filled so that nothing of size fits.
std::string small_tmpfs(const fs::path& dir) {
  const fs::path mnt = dir / "small";
  fs::create_directories(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0)
    return std::string("cannot mount a tmpfs here (") + std::strerror(errno) +
           "): the disk-full row needs root, as in CI on Debian 12";
  put(mnt / "labels.pgm", "OLD");
  return {};
}

void unmount(const fs::path& dir) { ::umount((dir / "small").c_str()); }

const std::vector<Case>& cases() {
  static const std::vector<Case> table = [] {
    std::vector<Case> t;

    // ---- outputs never lost or mixed
    {
      Case c{"directory_as_output", region("--point 2 --labels DIR/out")};
      c.code = 2;
      c.setup = [](const fs::path& dir) {
        fs::create_directory(dir / "out");
        return std::string();
      };
      c.check = [](const fs::path& dir, const Outcome& r) {
        EXPECT_EQ(joined(tree(dir)), "out/") << "no temporary left, the folder untouched";
        EXPECT_TRUE(r.out.empty());
      };
      c.err_part = "is a directory";
      t.push_back(c);
    }
    {
      Case c{"failing_second_output_keeps_existing_first",
             region("--point 2 --labels DIR/labels.pgm --png DIR/" + kTooLong)};
      c.code = 2;
      c.err_part = "File name too long";
      c.setup = old_file("labels.pgm");
      c.check = [](const fs::path& dir, const Outcome&) {
        EXPECT_EQ(slurp(dir / "labels.pgm"), "OLD") << "the existing first output was replaced or deleted";
        EXPECT_EQ(joined(tree(dir)), "labels.pgm");
      };
      t.push_back(c);
    }
    {
      Case c{"point_all_failure_keeps_earlier_per_point_files",
             region("--point all --labels DIR/l.pgm --png DIR/" + kTooLong)};
      c.code = 2;
      c.err_part = "File name too long";
      c.setup = [](const fs::path& dir) {
        for (int k = 0; k < 6; ++k) put(dir / ("l.P" + std::to_string(k) + ".pgm"), "OLD" + std::to_string(k));
        return std::string();
      };
      c.check = [](const fs::path& dir, const Outcome&) {
        for (int k = 0; k < 6; ++k)
          EXPECT_EQ(slurp(dir / ("l.P" + std::to_string(k) + ".pgm")), "OLD" + std::to_string(k)) << "point " << k;
        EXPECT_EQ(tree(dir).size(), 6u) << joined(tree(dir));
      };
      t.push_back(c);
    }
    {
      Case c{"point_all_success_writes_every_point", region("--point all --labels DIR/l.pgm --png DIR/r.png")};
      c.check = [](const fs::path& dir, const Outcome&) {
        for (int k = 0; k < 6; ++k)
          EXPECT_TRUE(valid_pgm(slurp(dir / ("l.P" + std::to_string(k) + ".pgm")), 32, 32)) << "point " << k;
        EXPECT_TRUE(is_png(slurp(dir / "r.png")));
        EXPECT_EQ(tree(dir).size(), 7u) << joined(tree(dir));
      };
      t.push_back(c);
    }
    {
      // Two runs at once onto the same outputs: both succeed, and what is
      // left is one whole, valid set (the lock serialises the commits).
      const std::string one = region("--point all --size 96x96 --labels DIR/l.pgm --png DIR/r.png");
      Case c{"two_concurrent_writers_same_paths",
             one + " >/dev/null & p=$!; " + one + " >/dev/null; b=$?; wait $p; a=$?; echo $a $b; exit $((a | b))"};
      c.compound = true;
      c.check = [](const fs::path& dir, const Outcome& r) {
        EXPECT_EQ(r.out, "0 0\n") << "exit codes of the two runs";
        for (int k = 0; k < 6; ++k)
          EXPECT_TRUE(valid_pgm(slurp(dir / ("l.P" + std::to_string(k) + ".pgm")), 96, 96)) << "point " << k;
        EXPECT_TRUE(is_png(slurp(dir / "r.png")));
        EXPECT_EQ(tree(dir).size(), 7u) << "temporaries left: " << joined(tree(dir));
      };
      t.push_back(c);
    }
    {
      const std::string one = "CMR report " + kUniform + " " + kClamped + " --backend cpu --no-thumbnails --out DIR/rep";
      const std::string two = "CMR report " + kClamped + " --backend cpu --no-thumbnails --out DIR/rep";
      Case c{"two_concurrent_reports_same_folder",
             one + " >/dev/null 2>>DIR.err & p=$!; " + two + " >/dev/null 2>>DIR.err; b=$?; wait $p; a=$?; echo $a $b; " +
                 "[ $a = 0 ] || [ $b = 0 ]"};
      c.compound = true;
      c.check = [](const fs::path& dir, const Outcome& r) {
        // Serialised by the lock; when one committed while the other ran,
        // the later one writes nothing and says so (exit 3, one line).
        EXPECT_TRUE(r.out == "0 0\n" || r.out == "0 3\n" || r.out == "3 0\n") << "exit codes of the two runs: " << r.out;
        const std::string err = slurp(dir.string() + ".err");
        std::istringstream lines(err);
        int said = 0;
        for (std::string line; std::getline(lines, line);)
          if (line.rfind("note: ", 0) != 0) {
            EXPECT_NE(line.find("another cmr run wrote this folder while this one ran"), std::string::npos) << line;
            ++said;
          }
        EXPECT_EQ(said, r.out == "0 0\n" ? 0 : 1) << err;
        const auto doc = nlohmann::json::parse(slurp(dir / "rep/report.json"));
        const std::string html = slurp(dir / "rep/index.html");
        const bool has_uniform = html.find("uniform.json") != std::string::npos;
        ASSERT_TRUE(doc.contains("splines")) << doc.dump();
        EXPECT_EQ(doc["splines"].size(), has_uniform ? 2u : 1u) << "report.json and index.html of different runs";
        EXPECT_EQ(joined(tree(dir)), "rep/ rep/.cmr-manifest rep/index.html rep/report.json");  // the manifest: an owned folder
      };
      t.push_back(c);
    }
    {
      // Each child creates links at the first temporary names cmr will try
      // (its pid is cmr's: exec keeps it); they must be skipped, not followed.
      Case c{"symlink_at_temporary_name_not_followed", region("--point 2 --labels DIR/labels.pgm")};
      c.setup = old_file("victim.txt", "precious");
      c.in_child = [](const fs::path& dir) {
        const fs::path out = dir / "labels.pgm";
        if (::symlink((dir / "victim.txt").c_str(), cmr::temp_name_for(out, 0).c_str()) != 0) ::_exit(122);
        if (::symlink((dir / "absent.txt").c_str(), cmr::temp_name_for(out, 1).c_str()) != 0) ::_exit(122);
      };
      c.check = [](const fs::path& dir, const Outcome&) {
        EXPECT_EQ(slurp(dir / "victim.txt"), "precious") << "a link at a temporary name was followed";
        EXPECT_FALSE(fs::exists(dir / "absent.txt")) << "a dangling link at a temporary name was followed";
        EXPECT_TRUE(valid_pgm(slurp(dir / "labels.pgm"), 32, 32));
        EXPECT_FALSE(fs::is_symlink(dir / "labels.pgm"));
        EXPECT_EQ(tree(dir).size(), 4u) << joined(tree(dir));  // labels, victim, the two links
      };
      t.push_back(c);
    }
    {
      Case c{"disk_full_is_exit_3_and_keeps_the_old_file",
             region("--point 2 --size 400x400 --labels DIR/small/labels.pgm")};
      c.code = 3;
      c.err_part = "labels.pgm: No space left on device";
      c.setup = small_tmpfs;
      c.teardown = unmount;
      c.check = [](const fs::path& dir, const Outcome&) {
        EXPECT_EQ(slurp(dir / "small/labels.pgm"), "OLD");
        EXPECT_EQ(joined(tree(dir / "small")), "labels.pgm") << "the temporary was not removed";
      };
      t.push_back(c);
    }
    {
      Case c{"report_failure_keeps_the_previous_report",
             "CMR report " + kUniform + " --backend cpu --no-thumbnails --out DIR/rep"};
      c.code = 2;
      c.err_part = "report.json: is a directory";
      c.setup = [](const fs::path& dir) {
        fs::create_directories(dir / "rep/report.json");
        put(dir / "rep/index.html", "OLD");
        return std::string();
      };
      c.check = [](const fs::path& dir, const Outcome&) {
        EXPECT_EQ(slurp(dir / "rep/index.html"), "OLD") << "index.html replaced though report.json failed";
        EXPECT_EQ(joined(tree(dir)), "rep/ rep/index.html rep/report.json/");
      };
      t.push_back(c);
    }
    {
      Case c{"report_failure_leaves_no_new_folder",
             "CMR report " + kUniform + " --backend cpu --no-thumbnails --out DIR/new/rep/" + kTooLong};
      c.code = 2;
      c.err_part = "File name too long";
      c.check = [](const fs::path& dir, const Outcome&) { EXPECT_EQ(joined(tree(dir)), ""); };
      t.push_back(c);
    }
    {
      // A file name that is not UTF-8 (Latin-1 "é" = 0xE9): the HTML and the
      // JSON stay valid UTF-8, the byte shown as U+FFFD. (The glob passes the
      // raw byte through the shell.)
      Case c{"report_non_utf8_file_name", "CMR report DIR/caf*.json --backend cpu --no-thumbnails --out DIR/rep"};
      c.setup = [](const fs::path& dir) {
        fs::copy_file(kUniform, dir / "caf\xe9.json");
        return std::string();
      };
      c.check = [](const fs::path& dir, const Outcome&) {
        const std::string json = slurp(dir / "rep/report.json"), html = slurp(dir / "rep/index.html");
        nlohmann::json doc;
        ASSERT_NO_THROW(doc = nlohmann::json::parse(json)) << "report.json is not valid JSON";
        EXPECT_NE(doc.dump().find("caf\xEF\xBF\xBD"), std::string::npos) << json.substr(0, 300);
        EXPECT_EQ(html.find("caf\xe9"), std::string::npos) << "a raw non-UTF-8 byte in index.html";
        EXPECT_NE(html.find("caf\xEF\xBF\xBD"), std::string::npos);
      };
      t.push_back(c);
    }
    {
      Case c{"figures_without_vulkan_device_leaves_no_files",
             "env VK_DRIVER_FILES=/nonexistent CMR figures --backend vulkan --size 64 --out DIR/figs"};
      c.code = 3;
      c.err_part = "--backend cpu";
      c.check = [](const fs::path& dir, const Outcome&) { EXPECT_EQ(joined(tree(dir)), "") << "files were left"; };
      t.push_back(c);
    }
    {
      Case c{"figures_without_vulkan_device_keeps_existing_folder",
             "env VK_DRIVER_FILES=/nonexistent CMR figures --backend vulkan --size 64 --out DIR/figs"};
      c.code = 3;
      c.err_part = "--backend cpu";
      c.setup = [](const fs::path& dir) {
        fs::create_directories(dir / "figs");
        put(dir / "figs/index.html", "OLD");
        return std::string();
      };
      c.check = [](const fs::path& dir, const Outcome&) {
        EXPECT_EQ(slurp(dir / "figs/index.html"), "OLD");
        EXPECT_EQ(joined(tree(dir)), "figs/ figs/index.html");
      };
      t.push_back(c);
    }

    // ---- input files
    {
      Case c{"fifo_without_writer_is_exit_2_at_once", "timeout 20 CMR analyze DIR/in.json"};
      c.code = 2;
      c.err_part = "in.json: empty (nothing came through the FIFO)";
      c.setup = [](const fs::path& dir) {
        return ::mkfifo((dir / "in.json").c_str(), 0600) == 0 ? std::string() : std::string("mkfifo failed");
      };
      t.push_back(c);
    }
    {
      Case c{"dev_zero_is_exit_2_at_once", "timeout 20 CMR region /dev/zero --point 1 --backend cpu"};
      c.code = 2;
      c.err_part = "/dev/zero: not a regular file (a character device)";
      t.push_back(c);
    }
    {
      Case c{"folder_as_input_is_exit_2", "CMR segments DIR"};
      c.code = 2;
      c.err_part = "not a regular file (a folder)";
      t.push_back(c);
    }
    {
      Case c{"input_over_the_size_limit_is_exit_2", "CMR analyze DIR/huge.json"};
      c.code = 2;
      c.err_part = "huge.json: larger than the 64 MiB input limit";
      c.setup = [](const fs::path& dir) {
        std::ofstream(dir / "huge.json") << "{}";
        fs::resize_file(dir / "huge.json", (std::uintmax_t{64} << 20) + 1);  // sparse: no 64 MiB written
        return std::string();
      };
      t.push_back(c);
    }
    {
      Case c{"kcurve_points_fifo_is_exit_2", "timeout 20 CMR kcurve DIR/p.json"};
      c.code = 2;
      c.err_part = "p.json: empty (nothing came through the FIFO)";
      c.setup = [](const fs::path& dir) {
        return ::mkfifo((dir / "p.json").c_str(), 0600) == 0 ? std::string() : std::string("mkfifo failed");
      };
      t.push_back(c);
    }

    // ---- --backend auto
    {
      Case c{"backend_auto_on_lavapipe_is_cpu",
             "env VK_DRIVER_FILES=" + kLavapipe + " CMR region " + kUniform + " --point 2 --size 16x16 --stats"};
      c.check = [](const fs::path&, const Outcome& r) {
        EXPECT_EQ(nlohmann::json::parse(r.out).at("backend"), "cpu") << "lavapipe is a CPU device: " << r.out;
        // A 16x16 one-shot frame: no device could win it (vk/backend_choice.hpp),
        // so the loader is not even asked and nothing is announced.
        EXPECT_EQ(r.err, "") << "no device could win a 256-pixel frame";
      };
      t.push_back(c);
    }
    {
      Case c{"backend_auto_without_vulkan_is_cpu",
             "env VK_DRIVER_FILES=/nonexistent CMR region " + kUniform + " --point 2 --size 16x16"};
      c.check = [](const fs::path&, const Outcome& r) { EXPECT_EQ(nlohmann::json::parse(r.out).at("backend"), "cpu"); };
      t.push_back(c);
    }
    {
      // Without thumbnails nothing renders: no region backend is made, so a
      // run with no Vulkan device at all (even with --backend vulkan) says
      // nothing about one.
      Case c{"report_without_thumbnails_needs_no_vulkan_device",
             "env VK_DRIVER_FILES=/nonexistent CMR report " + std::string(CMR_SOURCE_DIR) +
                 "/examples/ufo/Sans.ufo --backend vulkan --no-thumbnails --quiet --out DIR/rep"};
      c.check = [](const fs::path& dir, const Outcome& r) {
        EXPECT_EQ(r.err, "") << "no backend note without thumbnails";
        EXPECT_TRUE(fs::exists(dir / "rep" / "report.json"));
      };
      t.push_back(c);
    }
    {
      Case c{"backend_vulkan_on_lavapipe_says_vulkan",
             "env VK_DRIVER_FILES=" + kLavapipe + " CMR region " + kUniform + " --point 2 --size 16x16 --backend vulkan"};
      c.check = [](const fs::path&, const Outcome& r) {
        EXPECT_EQ(nlohmann::json::parse(r.out).at("backend"), "vulkan");
        EXPECT_EQ(r.err, "") << "an explicit backend is no fallback";
      };
      t.push_back(c);
    }

    // ---- CLI polish
    {
      Case c{"region_requires_point", "CMR region " + kUniform + " --backend cpu --labels DIR/l.pgm"};
      c.code = 2;
      c.err_part = "--point is required (see cmr region --help)";
      c.check = [](const fs::path& dir, const Outcome&) { EXPECT_EQ(joined(tree(dir)), ""); };
      t.push_back(c);
    }
    {
      Case c{"unknown_option_is_named", "CMR analyze " + kUniform + " --bogus"};
      c.code = 2;
      c.err_part = "unknown option or extra argument: --bogus (see cmr analyze --help)";
      t.push_back(c);
    }
    {
      Case c{"figures_help_names_the_figures_it_makes", "CMR figures --help"};
      c.check = [](const fs::path&, const Outcome& r) {
        EXPECT_NE(r.out.find("Figs. 1-13"), std::string::npos) << r.out;
        EXPECT_EQ(r.out.find("figures 2-10"), std::string::npos) << r.out;
      };
      t.push_back(c);
    }
    {
      Case c{"unknown_command_points_to_help", "CMR frobnicate"};
      c.code = 2;
      c.err_part = "unknown command 'frobnicate' (commands: ";
      t.push_back(c);
    }
    for (const auto& [name, args, message] : std::vector<std::tuple<const char*, std::string, std::string>>{
             {"range_analyze_depth", "analyze " + kUniform + " --depth 99", "--depth: 99 is outside 0..30"},
             {"range_region_depth", "region " + kUniform + " --point 1 --depth 31", "--depth: 31 is outside 0..30"},
             {"range_report_region_size", "report " + kUniform + " --out DIR/r --region-size 3",
              "--region-size: 3 is outside 8..1024"},
             {"range_figures_size", "figures --out DIR/f --size 10", "--size: 10 is outside 64..4096"},
             {"range_knots_times", "knots " + kUniform + " insert 3 --times 0", "--times: 0 is outside 1..30"},
             {"range_not_a_number", "analyze " + kUniform + " --depth many", "--depth: many is not a number"}}) {
      Case c{name, "CMR " + args};
      c.code = 2;
      c.err_part = message + " (see cmr ";
      c.check = [](const fs::path& dir, const Outcome&) { EXPECT_EQ(joined(tree(dir)), "") << "files written"; };
      t.push_back(c);
    }
    {
      Case c{"json_compact_by_default", "CMR analyze " + kUniform};
      c.check = [](const fs::path&, const Outcome& r) {
        EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "not one line: " << r.out.substr(0, 200);
        EXPECT_TRUE(nlohmann::json::parse(r.out).is_object());
      };
      t.push_back(c);
    }
    {
      Case c{"json_pretty_is_indented", "CMR segments " + kUniform + " --pretty"};
      c.check = [](const fs::path&, const Outcome& r) {
        EXPECT_EQ(r.out, nlohmann::ordered_json::parse(r.out).dump(2) + "\n");
      };
      t.push_back(c);
    }
    {
      Case c{"knots_out_compact_and_pretty",
             "CMR knots " + kUniform + " refine --out DIR/a.json && CMR knots " + kUniform +
                 " refine --pretty --out DIR/b.json"};
      c.compound = true;
      c.check = [](const fs::path& dir, const Outcome&) {
        const std::string a = slurp(dir / "a.json"), b = slurp(dir / "b.json");
        EXPECT_EQ(a, nlohmann::ordered_json::parse(a).dump() + "\n");
        EXPECT_EQ(b, nlohmann::ordered_json::parse(a).dump(2) + "\n");
      };
      t.push_back(c);
    }
    {
      Case c{"install_puts_cmr_into_the_prefix",
             std::string("\"") + CMAKE_COMMAND + "\" --install \"" + CMR_BUILD_DIR +
                 "\" --prefix DIR/prefix >/dev/null && DIR/prefix/bin/cmr --version"};
      c.compound = true;
      c.check = [](const fs::path& dir, const Outcome& r) {
        EXPECT_TRUE(fs::is_regular_file(dir / "prefix/bin/cmr"));
        EXPECT_EQ(r.out.rfind("cmr ", 0), 0u) << r.out;
      };
      t.push_back(c);
    }
    return t;
  }();
  return table;
}

INSTANTIATE_TEST_SUITE_P(Table, Outputs, ::testing::ValuesIn(cases()),
                         [](const auto& p) { return std::string(p.param.name); });

}  // namespace
