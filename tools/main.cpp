// The cmr command. Exit codes: 0 success, 1 a --require gate failed,
// 2 invalid input or usage (one line on stderr), 3 environment failure.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include <CLI/CLI.hpp>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "io/stdout_error.hpp"
#include "tools/cli_common.hpp"
#include "tools/keep_freed_memory.hpp"

namespace {

/// stdout is an output too: after the command, everything printed is flushed
/// and checked. A write error (a full disk, /dev/full) is exit 3 with one
/// line; a closed pipe (a consumer such as `head` stopped reading) ends
/// quietly with the command's own exit code. SIGPIPE is ignored (main), so
/// that a closed pipe is an EPIPE here, never a kill in the middle of an
/// output set's commit.
int finish_stdout(int exit_code) {
  errno = 0;
  std::cout.flush();  // through stdio (sync_with_stdio): fflush(stdout), whose errno is the one to report
  int error = errno;
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  if (error == 0) error = errno;
  if (flushed && !std::ferror(stdout) && std::cout.good()) return exit_code;
  struct stat st {};
  const bool pipe = ::fstat(STDOUT_FILENO, &st) == 0 && S_ISFIFO(st.st_mode);
  if (error == 0) error = cmr::first_stdout_error().load();  // a streamed command's write failed earlier
  if (error == EPIPE || (error == 0 && pipe)) return exit_code;  // the error was EPIPE, seen by an earlier write
  std::cerr << "cmr: stdout: " << (error != 0 ? std::strerror(error) : "write error") << '\n';
  return exit_code == cmr::cli::kOk || exit_code == cmr::cli::kFail ? cmr::cli::kEnvironment : exit_code;
}

int run(int argc, char** argv);

/// A standard descriptor closed at start (`cmr analyze - <&-`) is filled with
/// /dev/null opened read-only, so that no file cmr opens lands on it (and a
/// write to a closed stdout still fails, as EBADF); a closed stdin is noted,
/// and reading "-" says "stdin: closed".
void fill_closed_standard_descriptors() {
  for (int fd = 0; fd <= 2; ++fd) {
    if (::fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
    const int got = ::open("/dev/null", O_RDONLY | O_NOCTTY);  // the lowest free number: fd itself
    if (got >= 0 && got != fd) {
      (void)::dup2(got, fd);
      ::close(got);
    }
    if (fd == 0) cmr::note_stdin_closed();
  }
}

}  // namespace

int main(int argc, char** argv) {
  fill_closed_standard_descriptors();
  std::signal(SIGPIPE, SIG_IGN);
  cmr::cli::keep_freed_memory();
  cmr::cli::read_environment();
  return finish_stdout(run(argc, argv));
}

namespace {

int run(int argc, char** argv) {
  using namespace cmr::cli;
  CLI::App app{"cmr: curvature monotonicity regions of B-spline curves"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cmr 0.1.0");
  int exit_code = kOk;
  add_segments_command(app, exit_code);
  add_analyze_command(app, exit_code);
  add_region_command(app, exit_code);
  add_figures_command(app, exit_code);
  add_report_command(app, exit_code);
  add_knots_command(app, exit_code);
  add_kcurve_command(app, exit_code);
  add_sweep_command(app, exit_code);
  add_import_command(app, exit_code);
  add_fix_command(app, exit_code);
#ifdef CMR_WITH_EDITOR
  add_edit_command(app, exit_code);
#endif
  std::string help = "cmr --help";  // where a usage error points to
  if (argc >= 2 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "cmr: unknown command '" << argv[1] << "' (commands: " << names << "; see cmr --help)\n";
      return kInvalid;
    }
    help = std::string("cmr ") + argv[1] + " --help";
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kOk;
  } catch (const CLI::CallForVersion&) {
    std::cout << app.version() << '\n';
    return kOk;
  } catch (const CLI::ExtrasError& e) {
    // CLI11: "The following argument(s) was/were not expected: --bogus x"
    std::string what = e.what();
    const auto colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    std::cerr << "cmr: unknown option or extra argument: " << what << " (see " << help << ")\n";
    return kInvalid;
  } catch (const CLI::ParseError& e) {
    std::cerr << "cmr: " << e.what() << " (see " << help << ")\n";
    return kInvalid;
  } catch (const cmr::InputError& e) {
    std::cerr << "cmr: " << cmr::cli::shown_message(e) << '\n';  // the libraries' fields as flags
    return kInvalid;
  } catch (const EnvironmentError& e) {
    std::cerr << "cmr: " << cmr::cli::shown_message(e) << '\n';
    return kEnvironment;
  } catch (const std::bad_alloc&) {
    std::cerr << "cmr: out of memory\n";
    return kEnvironment;
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "cmr: " << e.what() << '\n';
    return kEnvironment;
  } catch (const std::exception& e) {
    std::cerr << "cmr: unexpected error: " << e.what() << '\n';
    return kEnvironment;
  }
  return exit_code;
}

}  // namespace
