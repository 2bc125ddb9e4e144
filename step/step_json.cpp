// The parts of the STEP importer that need no OpenCASCADE (step/step.hpp).
#include "step/step.hpp"

#include <cstdio>
#include <utility>

#include "spline/errors.hpp"
#include "spline/fields.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <unordered_map>

namespace cmr::import {

nlohmann::ordered_json step_curve_json(const StepCurve& c) {
  nlohmann::ordered_json doc;
  doc["name"] = c.name;
  doc["degree"] = c.degree;
  if (c.closed) doc["closed"] = true;
  doc["knots"] = c.knots;
  nlohmann::ordered_json pts = nlohmann::ordered_json::array();
  for (const glm::dvec3& p : c.points) pts.push_back({p.x, p.y, p.z});
  doc["points"] = std::move(pts);
  if (!c.weights.empty()) doc["weights"] = c.weights;
  return doc;
}

StepScan step_scan(std::string_view text) {
  StepScan scan;
  int depth = 0, line = 1;
  long long entity = 0;
  const auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
  const auto is_name = [&](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || is_digit(c) || c == '_'; };
  // Skips to the `close` that ends what starts at i (a string, binary or
  // comment), counting its lines; false when it is not closed.
  const auto skip = [&](std::size_t& i, std::string_view close, std::size_t from) {
    const std::size_t end = text.find(close, from);
    if (end == std::string_view::npos) return false;
    line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
    i = end + close.size() - 1;
    return true;
  };
  // An instance's parameters close once: "#1 = A(...);" or "#1 = (A(...) B(...));",
  // then ';' (OCCT's parser recovered from "#1 = A(3) B(4) );" with a null
  // entity that its model loader then dereferenced: fuzz_step).
  bool closed = false;
  std::unordered_map<long long, int> defined;  // instance -> its line
  const auto bad_syntax = [&](const char* what) {
    if (scan.syntax.empty()) scan.syntax = what, scan.syntax_line = line;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '\'') {  // a string: '' inside it is a quote, so a scan to the next quote is enough
      if (!skip(i, "'", i + 1)) break;
    } else if (c == '"') {  // a binary
      if (!skip(i, "\"", i + 1)) break;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      if (!skip(i, "*/", i + 2)) break;
    } else if (c == '(') {
      if (closed) bad_syntax("a '(' after a closed parameter list (expected ';')");
      if (++depth > scan.depth) scan.depth = depth, scan.line = line;
    } else if (c == ')') {
      if (depth == 0) bad_syntax("a ')' without its '('");
      depth = std::max(depth - 1, 0);
      if (depth == 0) closed = true;
      continue;
    } else if (c == ';') {
      if (depth > 0) bad_syntax("a ';' inside parentheses");
      depth = 0, closed = false;
    } else if (closed && c != ' ' && c != '\t' && c != '\r') {
      bad_syntax("more after a closed parameter list (expected ';')");
    } else if (c == '#') {  // an instance name: "#12 =" starts entity 12, "#12" elsewhere refers to it
      std::size_t j = i + 1;
      long long id = 0;
      // Saturated at 10^18 (no overflow; fuzz_step found 2^60 * 10 under UBSan).
      for (; j < text.size() && is_digit(text[j]); ++j) id = id < 100'000'000'000'000'000LL ? id * 10 + (text[j] - '0') : id;
      std::size_t k = j;
      while (k < text.size() && (text[k] == ' ' || text[k] == '\t' || text[k] == '\r' || text[k] == '\n')) ++k;
      if (k < text.size() && text[k] == '=') {
        entity = id;
        // An instance defined twice (OCCT records a fail for it after
        // loading; its loader crashed on fuzz_step's inputs that had one
        // beside a malformed parameter, so it is refused before).
        if (const auto [it, fresh] = defined.emplace(id, line); !fresh && scan.syntax.empty()) {
          std::string m = "#";
          m.append(std::to_string(id)).append(" is defined twice (first on line ").append(std::to_string(it->second)).append(")");
          scan.syntax = m, scan.syntax_line = line;
        }
      }
      i = j - 1;
    } else if (is_name(c) && !is_digit(c)) {  // a keyword or enumeration (B_SPLINE_CURVE_2, .T.): not numbers
      while (i + 1 < text.size() && is_name(text[i + 1])) ++i;
    } else if (is_digit(c) || ((c == '+' || c == '-') && i + 1 < text.size() && is_digit(text[i + 1]))) {
      std::size_t j = i + 1;
      while (j < text.size() && is_digit(text[j])) ++j;
      bool real = false;
      if (j < text.size() && text[j] == '.') {
        real = true;
        for (++j; j < text.size() && is_digit(text[j]);) ++j;
      }
      if (j < text.size() && (text[j] == 'E' || text[j] == 'e')) {
        std::size_t k = j + 1;
        if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
        if (k < text.size() && is_digit(text[k])) {
          real = true;
          for (j = k; j < text.size() && is_digit(text[j]);) ++j;
        }
      }
      const std::string token(text.substr(i, j - i));
      if (scan.bad_number.empty()) {
        errno = 0;
        bool bad = false;
        if (real) {
          const double x = std::strtod(token.c_str(), nullptr);
          bad = errno == ERANGE ? std::abs(x) > 1 : !(std::abs(x) <= max_step_magnitude);  // underflow to 0 is harmless
        } else {
          const long long n = std::strtoll(token.c_str(), nullptr, 10);
          bad = errno == ERANGE || n > std::numeric_limits<int>::max() || n < std::numeric_limits<int>::min();
        }
        if (bad) scan.bad_number = token, scan.bad_entity = entity, scan.bad_line = line;
      }
      i = j - 1;
    }
  }
  return scan;
}

std::string step_edge_label(const StepCurve& c) {
  std::string s = "edge ";
  if (c.origin.entity > 0) s.append("#");
  s.append(std::to_string(c.origin.entity > 0 ? c.origin.entity : c.edge));
  return s;
}

std::string step_edge_id(const StepCurve& c) {
  return c.origin.entity > 0 ? step_edge_label(c).substr(5) : step_edge_label(c);
}

namespace {

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x == 0 ? 0.0 : x);  // no "-0"
  return buf;
}

std::string point(const glm::dvec3& p) {
  std::string s = "(";
  s.append(number(p.x)).append(", ").append(number(p.y)).append(", ").append(number(p.z)).append(")");
  return s;
}

}  // namespace

std::string step_curve_name(const StepCurve& c) {
  std::string s = step_edge_label(c);
  if (!c.origin.edge_name.empty()) s.append(" '").append(c.origin.edge_name).append("'");
  std::string context;
  for (const auto& [kind, name] : {std::pair<const char*, const std::string&>{"face", c.origin.face_name},
                                   {"shell", c.origin.shell_name}, {"product", c.origin.product_name}})
    if (!name.empty()) context.append(context.empty() ? "" : ", ").append(kind).append(" '").append(name).append("'");
  if (!context.empty()) context.append("; ");
  context.append("box ").append(point(c.box_min)).append("..").append(point(c.box_max));
  s.append(" (").append(context).append(")");
  return s;
}

std::string step_curve_stem(const StepCurve& c) {
  if (c.origin.entity > 0) return std::to_string(c.origin.entity);
  std::string s = "edge";
  return s.append(std::to_string(c.edge));
}

std::vector<long long> parse_step_edge_ids(const std::string& spec) {
  std::vector<long long> ids;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = spec.find(',', start);
    std::string item = spec.substr(start, end == std::string::npos ? std::string::npos : end - start);
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    const bool digits = item.size() > 1 && item.size() <= 19 && item[0] == '#' &&
                        std::all_of(item.begin() + 1, item.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
    if (!digits) {
      std::string m = field("edges");
      m.append(": \"").append(item).append(
          "\" is not a STEP entity id (expected #1234, comma separated: '#1234,#1240')");
      throw InputFieldError(m);
    }
    const long long id = std::stoll(item.substr(1));
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(id);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return ids;
}

StepCurves select_step_edges(const StepCurves& curves, const std::vector<long long>& ids, const std::string& where) {
  StepCurves out = curves;
  out.curves.clear();
  out.chains.clear();
  std::map<std::size_t, std::size_t> index;  // old -> new
  for (const long long id : ids) {
    const auto it = std::find_if(curves.curves.begin(), curves.curves.end(),
                                 [id](const StepCurve& c) { return c.origin.entity == id; });
    if (it != curves.curves.end()) {
      index[static_cast<std::size_t>(it - curves.curves.begin())] = out.curves.size();
      out.curves.push_back(*it);
      continue;
    }
    std::string m = field("edges");
    m.append(": #").append(std::to_string(id));
    if (const auto s = curves.skipped_entities.find(id); s != curves.skipped_entities.end())
      m.append(" is a ").append(s->second).append(" edge of ").append(where).append(", skipped (cmr judges B-spline and Bezier edges)");
    else {
      m.append(" is not a B-spline or Bezier edge of ").append(where).append(" (they are ");
      for (std::size_t i = 0; i < curves.curves.size() && i < 6; ++i)
        m.append(i ? ", " : "").append(step_edge_id(curves.curves[i]));
      if (curves.curves.size() > 6) m.append(", ... ").append(std::to_string(curves.curves.size())).append(" in all");
      m.append(")");
    }
    throw InputFieldError(m);
  }
  for (const StepChain& chain : curves.chains) {
    StepChain kept = chain;
    bool all = true;
    for (std::size_t& i : kept.curves) {
      const auto it = index.find(i);
      all = all && it != index.end();
      if (it != index.end()) i = it->second;
    }
    if (all) out.chains.push_back(kept);
  }
  return out;
}

std::string chain_edge_label(const StepCurves& curves, const StepChain& chain, std::size_t i) {
  std::string s;
  if (chain.reversed[i]) s.append("-");
  return s.append(step_edge_id(curves.curves[chain.curves[i]]));
}

ChainVerdict chain_verdict(const StepCurves& curves, const StepChain& chain, const ChainTolerances& tol) {
  ChainVerdict v;
  for (std::size_t i = 0; i < chain.curves.size(); ++i) {
    std::string d = curves.curves[chain.curves[i]].curvature;
    if (chain.reversed[i]) d = d == "increasing" ? "decreasing" : d == "decreasing" ? "increasing" : d;
    // analyze_space's "none" is not monotone (part_verdict; all constant is "increasing").
    if (d != "increasing" && d != "decreasing")
      v.not_monotone.push_back(chain_edge_label(curves, chain, i).append(" ").append(d == "none" ? "not monotone" : d));
    v.directions.push_back(d);
  }
  if (!v.not_monotone.empty()) return v;
  v.one_way = true;
  for (const std::string& d : v.directions) {
    if (v.way.empty()) v.way = d;
    v.one_way = v.one_way && d == v.way;
  }
  // A junction's kappa jump against that direction breaks it.
  for (const StepJunction& j : chain.junctions) {
    const double jump = j.kappa_right - j.kappa_left, slack = tol.curvature_rel * std::max(j.kappa_left, j.kappa_right);
    if ((v.way == "increasing" && jump < -slack) || (v.way == "decreasing" && jump > slack)) v.one_way = false;
  }
  if (chain.closed) v.one_way = false;  // a closed chain's kappa cannot grow all the way round
  if (!v.one_way) v.way.clear();
  return v;
}

std::vector<std::string> step_chain_report(const StepCurves& curves, const StepChain& chain, int index,
                                           const ChainTolerances& tol) {
  std::vector<std::string> lines;
  const std::size_t n = chain.curves.size();
  const auto label = [&](std::size_t i) { return chain_edge_label(curves, chain, i); };
  const ChainVerdict v = chain_verdict(curves, chain, tol);
  std::string line = "chain ";
  line.append(std::to_string(index)).append(": ");
  for (std::size_t i = 0; i < n; ++i) line.append(i ? " > " : "").append(label(i));
  line.append(" (").append(std::to_string(n)).append(" edges, ").append(chain.closed ? "closed" : "open").append("): ");
  if (!v.not_monotone.empty()) {
    line.append("not monotone: ");
    for (std::size_t i = 0; i < v.not_monotone.size(); ++i) line.append(i ? ", " : "").append(v.not_monotone[i]);
  } else {
    line.append("each edge monotone; whole chain: ");
    if (v.one_way)
      line.append("kappa ").append(v.way);
    else
      line.append("not monotone");
  }
  lines.push_back(line);
  for (std::size_t i = 0; i < chain.junctions.size(); ++i) {
    const StepJunction& j = chain.junctions[i];
    std::string s = "  ";
    s.append(label(i)).append(" > ").append(label((i + 1) % n)).append(" at ").append(point(j.at)).append(": ");
    if (j.level == 0)
      s.append("not G1");
    else
      s.append("G").append(std::to_string(j.level));
    s.append(" (gap ").append(number(j.gap)).append(", angle ").append(number(j.angle_deg)).append(" deg, kappa ");
    s.append(number(j.kappa_left)).append(" | ").append(number(j.kappa_right)).append(", dkappa/ds ");
    s.append(number(j.dkds_left)).append(" | ").append(number(j.dkds_right)).append(", tau ");
    s.append(number(j.tau_left)).append(" | ").append(number(j.tau_right)).append(")");
    lines.push_back(s);
  }
  return lines;
}

std::vector<std::string> step_chain_report(const StepCurves& curves, const ChainTolerances& tol) {
  std::vector<std::string> lines;
  int index = 0;
  for (const StepChain& chain : curves.chains)
    for (std::string& l : step_chain_report(curves, chain, ++index, tol)) lines.push_back(std::move(l));
  return lines;
}

double step_time_budget(std::uintmax_t bytes) {
  return 5.0 + 4.0 * static_cast<double>(bytes) / 1e6;
}

std::string skipped_summary(const StepCurves& curves) {
  std::string out;
  for (const auto& [type, n] : curves.skipped) out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + type;
  return out;
}

}  // namespace cmr::import
