#include "report/baseline.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "report/gates.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/limits.hpp"

namespace cmr::report {

std::string Finding::key() const {
  return file + "|" + glyph + "|c" + std::to_string(contour) + "|" + node + "|" + gate;
}

std::vector<std::string> read_baseline(const std::filesystem::path& path) {
  const std::string name = field("baseline") + " " + path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputFieldError(name + ": not a file");
  // Bounded like every input (a 300 MB baseline took 1.9 GB as a tree:
  // issue 42): checked before reading, and again on what was read (a file
  // that grows meanwhile).
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  const auto too_large = [&] {
    return InputError(name + ": larger than the limit of " + std::to_string(kMaxInputBytes >> 20) +
                      " MiB for an input file (cmr::kMaxInputBytes)");
  };
  if (!ec && size > kMaxInputBytes) throw too_large();
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputFieldError(name + ": cannot be read");
  if (text.view().size() > kMaxInputBytes) throw too_large();
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception&) {
    throw InputFieldError(name + ": not JSON (a report.json of cmr report is expected)");
  }
  const std::string schema = doc.is_object() ? doc.value("schema", std::string()) : std::string();
  if (!doc.is_object() || (schema != kSchema && schema != kSchemaPrevious) || !doc.contains("splines") ||
      !doc["splines"].is_array())
    throw InputFieldError(name + ": not a " + std::string(kSchema) + " report");
  std::vector<std::string> keys;
  for (const auto& s : doc["splines"]) {
    if (!s.is_object()) throw InputFieldError(name + ": a spline entry is not an object");
    if (s.value("status", std::string()) == "invalid") continue;
    if (!s.contains("findings") || !s["findings"].is_array())
      throw InputFieldError(name + ": spline '" + s.value("name", std::string("?")) +
                            "' has no findings (a report from before baselines: run cmr report again to make one)");
    for (const auto& f : s["findings"]) {
      if (!f.is_object() || !f.contains("key") || !f["key"].is_string())
        throw InputFieldError(name + ": a finding of spline '" + s.value("name", std::string("?")) + "' has no key");
      // A baseline accepted before the gate's rename names it by its alias
      // (extrema-at-nodes): the gate is the key's last field.
      std::string key = f["key"].get<std::string>();
      const std::size_t bar = key.rfind('|');
      if (bar != std::string::npos) key = key.substr(0, bar + 1) + canonical_gate_name(key.substr(bar + 1));
      keys.push_back(std::move(key));
    }
  }
  return keys;
}

BaselineComparison::BaselineComparison(const std::vector<std::string>& keys) {
  std::set<std::string> files;
  for (const std::string& k : keys) {
    ++left_[k];
    files.insert(k.substr(0, k.find('|')));
  }
  files_.assign(files.begin(), files.end());
}

namespace {

/// Whether one name's path components end the other's ("../x/A.ufo" and
/// "x/A.ufo", "A.ufo").
bool same_tail(const std::string& a, const std::string& b) {
  const std::filesystem::path pa(a), pb(b);
  std::vector<std::string> ca, cb;
  for (const auto& c : pa) ca.push_back(c.string());
  for (const auto& c : pb) cb.push_back(c.string());
  if (ca.empty() || cb.empty()) return false;
  const std::size_t n = std::min(ca.size(), cb.size());
  return std::equal(ca.end() - static_cast<std::ptrdiff_t>(n), ca.end(), cb.end() - static_cast<std::ptrdiff_t>(n));
}

}  // namespace

const std::string& BaselineComparison::baseline_file(const std::string& file) {
  if (const auto it = file_of_.find(file); it != file_of_.end()) return it->second;
  std::string match;
  if (std::binary_search(files_.begin(), files_.end(), file)) {
    match = file;
  } else {
    int found = 0;
    for (const std::string& b : files_)
      if (same_tail(b, file)) match = b, ++found;
    if (found != 1) match.clear();
  }
  return file_of_[file] = match;
}

const char* BaselineComparison::judge(const Finding& f) {
  const std::string& file = baseline_file(f.file);
  if (file.empty()) return "new";
  Finding as = f;
  as.file = file;
  const auto it = left_.find(as.key());
  if (it == left_.end() || it->second == 0) return "new";
  --it->second;
  return "unchanged";
}

int BaselineComparison::fixed() const {
  int n = 0;
  for (const auto& [k, c] : left_) n += c;
  return n;
}

}  // namespace cmr::report
