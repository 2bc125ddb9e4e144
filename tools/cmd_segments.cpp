// cmr segments FILE: the non-empty spans in Bezier form.
#include <CLI/CLI.hpp>

#include "bezierize/extract.hpp"
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
    nlohmann::ordered_json segs = nlohmann::ordered_json::array();
    for (const BezierSegment& b : bezier_segments(spline)) {
      nlohmann::ordered_json pts = nlohmann::ordered_json::array();
      for (const Vec2& p : b.points) pts.push_back({p.x, p.y});
      segs.push_back({{"index", b.segment.index}, {"interval", {b.segment.a, b.segment.b}}, {"points", pts}});
    }
    print_json({{"segments", segs}}, args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
