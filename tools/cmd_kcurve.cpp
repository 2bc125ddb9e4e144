// cmr kcurve POINTS.json [--closed] [--cubic] [--out SPLINE.json]: the κ-curve
// (Yan et al. 2017) through the points as a quadratic Bézier chain, or with
// --cubic the subdivided, degree-elevated chain of CAD&A 2024 §5.2.
#include <cmath>
#include <iostream>
#include <sstream>

#include "design/kcurve.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"

#include <CLI/CLI.hpp>

namespace cmr::cli {

namespace {

struct KCurveArgs {
  std::string file;
  bool closed = false;
  bool cubic = false;
  std::string out;
  KCurveOptions options;
  bool pretty = false;
};

double coordinate(const nlohmann::json& v, const std::string& where) {
  if (!v.is_number()) throw InputError(where + " is not a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw InputError(where + " is not a finite number");
  return x;
}

}  // namespace

KCurvePoints kcurve_points_from_json(const nlohmann::json& doc) {
  if (!doc.is_object()) throw InputError("the document is not a JSON object with \"points\"");
  for (const auto& [key, value] : doc.items())
    if (key != "points" && key != "closed")
      throw InputError("unknown field \"" + key + "\" (expected points, closed)");
  if (!doc.contains("points")) throw InputError("points: missing");
  const nlohmann::json& pts = doc["points"];
  if (!pts.is_array()) throw InputError("points: not an array of [x, y] pairs");
  KCurvePoints r;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "]";
    if (!pts[i].is_array() || pts[i].size() != 2) throw InputError(where + " is not an [x, y] pair");
    r.points.emplace_back(coordinate(pts[i][0], where + "[0]"), coordinate(pts[i][1], where + "[1]"));
  }
  if (doc.contains("closed")) {
    if (!doc["closed"].is_boolean()) throw InputError("closed: not true or false");
    r.closed = doc["closed"].get<bool>();
  }
  return r;
}

KCurvePoints read_kcurve_points_file(const std::filesystem::path& path) {
  const std::string text = read_input_file(path);
  try {
    return kcurve_points_from_json(nlohmann::json::parse(text));
  } catch (const nlohmann::json::exception& e) {
    std::string what = e.what();  // "[json.exception.parse_error.101] parse error at ..."
    const auto pos = what.find("] ");
    if (pos != std::string::npos) what = what.substr(pos + 2);
    throw InputError(input_name(path) + ": malformed JSON: " + what);
  } catch (const InputError& e) {
    throw InputError(input_name(path) + ": " + shown_message(e));
  }
}

void add_kcurve_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<KCurveArgs>();
  auto* cmd = app.add_subcommand("kcurve", "Interpolate points with a kappa-curve (curvature maxima at the points)");
  cmd->add_option("POINTS", args->file, "points file: {\"points\": [[x,y],...], \"closed\": false}")->required();
  cmd->add_flag("--closed", args->closed, "close the curve (also when the file says \"closed\": true)");
  cmd->add_flag("--cubic", args->cubic, "the cubic chain split at the curvature maxima (CAD&A 2024 section 5.2)");
  cmd->add_option("--out", args->out, "spline file to write (default: stdout)");
  cmd->add_option("--tolerance", args->options.tolerance, "convergence tolerance (relative, in (0, 1))")
      ->capture_default_str();
  in_range(cmd->add_option("--max-iterations", args->options.max_iterations, "iteration cap per start"), 1, 1e6)
      ->capture_default_str();
  args->options.time_limit = 60;
  in_range(cmd->add_option("--max-work", args->options.max_point_iterations,
                           "work budget: iterations x points over every start (the 15 starts and their polish); "
                           "a run that spends it is refused unless it converged. 1000000: 100 points get "
                           "--max-iterations, 1000 points 1000 iterations in all (seconds)"),
           1, 1e12)
      ->capture_default_str();
  in_range(cmd->add_option("--time-limit", args->options.time_limit,
                           "seconds of wall-clock time for the whole solve, a backstop to --max-work"),
           0.1, 86400.0)
      ->capture_default_str();
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    if (!args->out.empty()) check_output_path(args->out, "--out");
    const KCurvePoints input = read_kcurve_points_file(args->file);
    KCurveOptions options = args->options;
    options.closed = args->closed || input.closed;
    KCurve curve;
    try {
      curve = kcurve(input.points, options);
    } catch (const InputError& e) {
      throw InputError(args->file + ": " + shown_message(e));
    }
    if (!curve.converged()) {
      std::ostringstream why;
      why << args->file << ": the kappa-curve did not converge in " << curve.iterations << " iterations (residual "
          << curve.residual << " > tolerance " << curve.tolerance << ")";
      if (curve.budget_spent)
        why << " within its budget of " << options.max_point_iterations << " point-iterations (--max-work: "
            << options.max_point_iterations / std::max<std::size_t>(1, input.points.size()) << " iterations of "
            << input.points.size() << " points) or " << options.time_limit << " s (--time-limit)";
      why << "; very sharp turns and nearly collinear points converge slowly: spread the points or raise --tolerance";
      throw InputError(why.str());
    }
    // A piece of zero length (its joints coincide) is no curve a designer
    // can use: refused, never a silent success (issue 42 E3).
    if (const std::vector<int> flat = kcurve_degenerate_pieces(curve); !flat.empty())
      throw InputError(args->file + ": quadratic " + std::to_string(flat.front()) +
                       " of the kappa-curve has zero length (its two joints coincide" +
                       (flat.size() > 1 ? ", and " + std::to_string(flat.size() - 1) + " more" : std::string()) +
                       "): spread the points or lower --tolerance");
    if (args->cubic) {
      const std::vector<int> uncertified = kcurve_cubic_uncertified(curve);
      if (!uncertified.empty())
        throw InputError(args->file + ": piece " + std::to_string(uncertified.front()) +
                         " of the cubic chain could not be certified monotone (its curvature maximum is not on a joint)");
    }
    // One line per point whose quadratic does not peak on it (docs/kcurve.md).
    for (const std::string& line : kcurve_off_point_notes(curve, input.points))
      std::cerr << "note: " << args->file << ": " << line << "\n";
    const BSpline spline = args->cubic ? kcurve_cubic_chain(curve) : kcurve_quadratic_spline(curve);
    const std::string text = json_text(spline_to_json(spline), args->pretty);
    if (args->out.empty()) std::cout << text;
    else write_file_atomic(args->out, text);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
