#include "tools/edit/script.hpp"

#include <cstdlib>
#include <map>
#include <sstream>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

namespace cmr::edit {
namespace {

struct Arity {
  std::size_t min, max;
};

const std::map<std::string, Arity>& commands() {
  static const std::map<std::string, Arity> table = {
      {"mouse", {2, 2}},   {"press", {1, 2}},  {"release", {1, 1}},  {"scroll", {1, 2}},
      {"key", {1, 2}},     {"drag", {3, 4}},   {"select", {1, 1}},   {"group", {0, 64}},
      {"all", {1, 1}},     {"mode", {1, 1}},   {"depth", {1, 1}},    {"shading", {1, 1}},
      {"split", {1, 1}},   {"chain", {1, 1}},  {"comb", {1, 1}},     {"ui", {1, 1}},
      {"overlay", {1, 1}}, {"view", {4, 4}},   {"fit", {0, 0}},      {"knot", {2, 2}},
      {"insert", {1, 2}},  {"remove", {1, 2}}, {"elevate", {0, 0}},  {"clamp", {0, 0}},
      {"uniform", {0, 0}}, {"undo", {0, 0}},   {"redo", {0, 0}},     {"save", {0, 1}},
      {"export-region", {1, 1}}, {"screenshot", {1, 1}}, {"wait", {1, 1}}, {"quit", {0, 0}},
      {"drag-knot", {2, 3}}, {"kcurve", {1, 1}}, {"closed", {1, 1}},
      {"segments", {1, 1}}, {"weight", {2, 2}}, {"weight-region", {1, 1}}, {"resize", {2, 2}}, {"export-view", {1, 1}},
      {"fix", {0, 0}}, {"snap", {0, 0}}, {"status", {0, 0}},
      {"type", {2, 2}}, {"legend", {0, 0}}, {"fit-region", {0, 0}}, {"show-point", {2, 2}}, {"comb-size", {1, 1}},
      {"graph", {1, 1}}, {"contour", {1, 1}}, {"glyph", {1, 1}}, {"save-all", {0, 0}}, {"constrain", {1, 1}},
      {"legend-dock", {1, 1}}, {"comb-all", {1, 1}}, {"fix-grid", {0, 1}},
      {"orbit", {2, 2}}, {"zoom", {1, 1}}, {"pan", {2, 2}}, {"plane", {1, 1}},
  };
  return table;
}

std::string where(const ScriptCommand& c) { return "script line " + std::to_string(c.line) + " (" + c.name + ")"; }

}  // namespace

std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source) {
  std::vector<ScriptCommand> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    ScriptCommand c;
    c.line = number;
    if (!(words >> c.name)) continue;
    for (std::string w; words >> w;) c.args.push_back(w);
    const auto it = commands().find(c.name);
    if (it == commands().end())
      throw InputError(source + ":" + std::to_string(number) + ": unknown command '" + c.name + "'");
    if (c.args.size() < it->second.min || c.args.size() > it->second.max)
      throw InputError(source + ":" + std::to_string(number) + ": '" + c.name + "' takes " +
                       std::to_string(it->second.min) +
                       (it->second.max != it->second.min ? ".." + std::to_string(it->second.max) : "") +
                       " arguments, got " + std::to_string(c.args.size()));
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<ScriptCommand> read_script(const std::filesystem::path& path) {
  return parse_script(read_input_file(path), path.string());
}

double number_arg(const ScriptCommand& c, std::size_t i) {
  const std::string& w = c.args.at(i);
  char* end = nullptr;
  const double x = std::strtod(w.c_str(), &end);
  if (w.empty() || end != w.c_str() + w.size()) throw InputError(where(c) + ": '" + w + "' is not a number");
  return x;
}

int int_arg(const ScriptCommand& c, std::size_t i) {
  const std::string& w = c.args.at(i);
  char* end = nullptr;
  const long x = std::strtol(w.c_str(), &end, 10);
  if (w.empty() || end != w.c_str() + w.size() || x < -1'000'000 || x > 1'000'000)
    throw InputError(where(c) + ": '" + w + "' is not an integer");
  return static_cast<int>(x);
}

bool switch_arg(const ScriptCommand& c, std::size_t i) {
  const std::string& w = c.args.at(i);
  if (w == "on") return true;
  if (w == "off") return false;
  throw InputError(where(c) + ": expected on or off, got '" + w + "'");
}

}  // namespace cmr::edit
