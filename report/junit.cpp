#include "report/junit.hpp"

#include <cstdio>

namespace cmr::report {

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    if (c < 0x80) {
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default:
          if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') out += "\xEF\xBF\xBD";  // not an XML 1.0 Char
          else out += static_cast<char>(c);
      }
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence (RFC 3629: no overlongs, no surrogates, <= U+10FFFF).
    int len = 0;
    std::uint32_t cp = 0;
    if (c >= 0xC2 && c <= 0xDF) len = 2, cp = c & 0x1F;
    else if (c >= 0xE0 && c <= 0xEF) len = 3, cp = c & 0x0F;
    else if (c >= 0xF0 && c <= 0xF4) len = 4, cp = c & 0x07;
    bool ok = len > 0 && i + len <= n;
    for (int k = 1; ok && k < len; ++k) {
      ok = (s[i + k] & 0xC0) == 0x80;
      cp = (cp << 6) | (s[i + k] & 0x3F);
    }
    ok = ok && !(len == 3 && cp < 0x800) && !(len == 4 && (cp < 0x10000 || cp > 0x10FFFF)) &&
         !(cp >= 0xD800 && cp <= 0xDFFF) && cp != 0xFFFE && cp != 0xFFFF;
    if (ok) {
      out.append(text.substr(i, len));
      i += len;
    } else {
      out += "\xEF\xBF\xBD";
      ++i;
    }
  }
  return out;
}

std::string junit_header() { return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"cmr report\">\n"; }

std::string junit_footer() { return "</testsuites>\n"; }

std::string junit_suite(const FileRecord& file, int id, const std::string& timestamp, const std::string& hostname) {
  int failures = 0, errors = 0;
  for (const CaseRecord& c : file.cases) {
    if (!c.error.empty()) ++errors;
    else if (!c.pass) ++failures;
  }
  char time[32];
  std::snprintf(time, sizeof time, "%.3f", file.seconds);
  const double per_case = file.cases.empty() ? 0.0 : file.seconds / static_cast<double>(file.cases.size());
  char case_time[32];
  std::snprintf(case_time, sizeof case_time, "%.4f", per_case);
  std::string out = "  <testsuite id=\"" + std::to_string(id) + "\" package=\"cmr\" name=\"" + xml_escape(file.path) +
                    "\" timestamp=\"" + xml_escape(timestamp) + "\" hostname=\"" + xml_escape(hostname) +
                    "\" tests=\"" + std::to_string(file.cases.size()) + "\" failures=\"" + std::to_string(failures) +
                    "\" errors=\"" + std::to_string(errors) + "\" time=\"" + time + "\">\n    <properties/>\n";
  for (const CaseRecord& c : file.cases) {
    out += "    <testcase name=\"" + xml_escape(c.name) + "\" classname=\"" + xml_escape(file.path) + "\" time=\"" +
           case_time + "\"";
    if (c.error.empty() && c.pass) {
      out += "/>\n";
      continue;
    }
    out += ">\n";
    if (!c.error.empty()) {
      out += "      <error message=\"" + xml_escape(c.error) + "\" type=\"invalid-input\">" + xml_escape(c.error) +
             "</error>\n";
    } else {
      // The first finding's text as the message, each finding on a line of the body.
      const std::string first = c.findings.empty() ? std::string("fails") : c.findings.front().message;
      const std::string type = c.findings.empty() ? std::string("check") : c.findings.front().gate;
      std::string body;
      for (const Finding& f : c.findings) body += f.gate + ": " + f.message + "\n";
      out += "      <failure message=\"" + xml_escape(std::to_string(c.findings.size()) +
                                                      (c.findings.size() == 1 ? " violation: " : " violations; first: ") +
                                                      first) +
             "\" type=\"" + xml_escape(type) + "\">" + xml_escape(body) + "</failure>\n";
    }
    out += "    </testcase>\n";
  }
  out += "    <system-out/>\n    <system-err/>\n  </testsuite>\n";
  return out;
}

}  // namespace cmr::report
