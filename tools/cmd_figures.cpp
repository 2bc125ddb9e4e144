// cmr figures [--out DIR] [--backend vulkan|cpu] [--device NAME] [--size N]:
// recomputes the paper's figures (CAD&A 2024 §4), checks every claim made
// about them, writes the PNGs, the spline files and index.html. Exit 1 when a
// claim fails.
#include <chrono>
#include <iomanip>
#include <iostream>

#include <CLI/CLI.hpp>

#include "tools/cli_common.hpp"
#include "tools/figures.hpp"

namespace cmr::cli {

namespace {

struct FiguresArgs {
  std::string out = "out/figures";
  std::string backend = "auto";
  std::string device;
  int size = 400;
};

void print_claims(const std::vector<fig::Claim>& claims) {
  std::size_t width = 5;
  for (const fig::Claim& c : claims) width = std::max(width, c.figure.size() + 2 + c.text.size());
  std::cout << std::left << std::setw(static_cast<int>(width)) << "claim" << " | result\n"
            << std::string(width, '-') << "-+-------\n";
  for (const fig::Claim& c : claims) {
    std::cout << std::setw(static_cast<int>(width)) << (c.figure + ": " + c.text) << " | "
              << (c.pass ? "PASS" : "FAIL") << '\n';
    if (!c.pass) std::cout << "    measured: " << c.detail << '\n';
  }
}

}  // namespace

void add_figures_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<FiguresArgs>();
  auto* cmd = app.add_subcommand("figures", "Recompute the paper's Figs. 1-13, check their claims, write PNGs, "
                                            "SVGs and index.html");
  cmd->add_option("--out", args->out, "output folder (created if missing)")->capture_default_str();
  add_backend_options(*cmd, args->backend, args->device);
  in_range(cmd->add_option("--size", args->size, "side of each region image in pixels"), 64, 4096)
      ->capture_default_str();
  cmd->callback([args, &exit_code] {
    fig::FiguresOptions o;
    o.out = args->out;
    o.backend = make_region_backend(args->backend, "fp64", args->device, 0);
    o.size = args->size;
    o.progress = &std::cout;
    // The backend is picked (and any note about it printed on stderr) before
    // the first line starts, so the note never lands inside it.
    const std::string backend = o.backend->name();
    std::cout << "cmr figures: " << args->size << "x" << args->size << " px regions on the " << backend
              << " backend, into " << args->out << '\n';
    const auto t0 = std::chrono::steady_clock::now();
    const fig::FiguresResult r = fig::make_figures(o);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << '\n';
    print_claims(r.claims);
    const auto failed = std::count_if(r.claims.begin(), r.claims.end(), [](const fig::Claim& c) { return !c.pass; });
    std::cout << '\n'
              << r.claims.size() - failed << " of " << r.claims.size() << " claims pass; " << r.written.size()
              << " files in " << args->out << " (" << std::fixed << std::setprecision(1) << seconds << " s)\n";
    exit_code = r.all_pass() ? kOk : kFail;
  });
}

}  // namespace cmr::cli
