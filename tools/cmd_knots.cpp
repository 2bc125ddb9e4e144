// cmr knots FILE OP [args] [--out FILE] [--conventional]: knot operations
// (bezierize/knot_ops.hpp). The new spline goes to stdout or, written
// atomically, to --out.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <optional>

#include "bezierize/knot_ops.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"

#include <CLI/CLI.hpp>

namespace cmr::cli {

namespace {

struct KnotsArgs {
  std::string file;
  std::string out;
  bool conventional = false;
  double u = 0;
  int times = 1;
  std::optional<double> tolerance;
  int index = 0;
  bool pretty = false;
};

/// The operation named by the chosen sub-command, applied to `spline`.
BSpline apply(const std::string& op, const KnotsArgs& a, const BSpline& spline) {
  if (op == "insert") return insert_knot(spline, a.u, a.times);
  if (op == "remove")
    return remove_knot(spline, a.u, a.tolerance.value_or(kRemovalRelativeTolerance * extent(spline))).spline;
  if (op == "set") return set_knot(spline, a.index, a.u);
  if (op == "clamp") return clamp(spline);
  if (op == "uniform") return make_uniform(spline);
  if (op == "elevate") return elevate_degree(spline);
  CMR_CHECK(op == "refine");
  return refine(spline);
}

void add_operations(CLI::App& cmd, KnotsArgs& a) {
  auto* insert = cmd.add_subcommand("insert", "Insert knot U (same curve)");
  insert->add_option("U", a.u, "knot value in the domain")->required();
  in_range(insert->add_option("--times", a.times, "how many copies (multiplicity stays <= degree)"), 1, kMaxDegree)
      ->capture_default_str();
  auto* remove = cmd.add_subcommand("remove", "Remove one copy of the interior knot U if the curve moves by <= --tol");
  remove->add_option("U", a.u, "knot value strictly inside the domain")->required();
  remove->add_option("--tol", a.tolerance,
                     "largest accepted deviation (absolute; default 1e-9 x the control points' extent)");
  auto* set = cmd.add_subcommand("set", "Set knot I to U (the curve changes)");
  set->add_option("I", a.index, "knot index 0..K-1")->required();
  set->add_option("U", a.u, "new value (order and multiplicity are checked)")->required();
  cmd.add_subcommand("clamp", "End knots of multiplicity degree (same curve on its domain)");
  cmd.add_subcommand("uniform", "Knots 0, 1, 2, ... with the same control points (the curve changes)");
  cmd.add_subcommand("elevate", "Raise the degree by one (same curve)");
  cmd.add_subcommand("refine", "Insert the midpoint of every segment (same curve)");
}

}  // namespace

void add_knots_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<KnotsArgs>();
  auto* cmd = app.add_subcommand("knots", "Knot operations; prints the new spline (JSON)");
  cmd->add_option("FILE", args->file, "spline file (JSON)")->required();
  cmd->add_option("--out", args->out, "write the spline here (atomically) instead of stdout");
  cmd->add_flag("--conventional", args->conventional,
                "FILE's knots are the conventional (full) vector: drop its first and last knot");
  add_pretty_flag(*cmd, args->pretty);
  cmd->require_subcommand(0, 1);  // none: the error below names the operations
  cmd->fallthrough();
  add_operations(*cmd, *args);
  cmd->callback([cmd, args, &exit_code] {
    if (cmd->get_subcommands().empty())
      throw InputError("knots: name an operation: insert U, remove U, set I U, clamp, uniform, elevate or refine");
    if (!args->out.empty()) check_output_path(args->out, "--out");
    const BSpline spline = read_spline_file(args->file, {.conventional = args->conventional});
    const BSpline result = apply(cmd->get_subcommands().front()->get_name(), *args, spline);
    const std::string text = json_text(spline_to_json(result), args->pretty);
    if (args->out.empty()) std::cout << text;
    else write_file_atomic(args->out, text);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
