// cmr segments FILE: the non-empty spans in Bezier form.
#include <CLI/CLI.hpp>

#include "report/analyze_json.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"

namespace cmr::cli {

void add_segments_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("segments", "Print every non-empty span of a spline in Bezier form (JSON)");
  struct Args {
    std::string file;
    bool pretty = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("FILE", args->file, "spline file (JSON)")->required();
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    const BSpline spline = read_spline_file(args->file);
    print_json(report::segments_json(spline), args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
