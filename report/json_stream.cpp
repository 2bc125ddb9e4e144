#include "report/json_stream.hpp"

#include <charconv>
#include <cmath>

#include "bezierize/analyze.hpp"
#include "report/certified_fix.hpp"
#include "report/extremum.hpp"
#include "report/gates.hpp"

namespace cmr::report {

// ---------------------------------------------------------------- JsonStream

void JsonStream::newline_indent() {
  out_ += '\n';
  out_.append(first_.size() * static_cast<std::size_t>(indent_), ' ');
}

void JsonStream::before_value() {
  if (array_.empty() || !array_.back()) return;  // top level, or after key()
  if (!first_.back()) out_ += ',';
  first_.back() = 0;
  if (indent_ >= 0) newline_indent();
}

JsonStream& JsonStream::key(std::string_view k) {
  if (!first_.back()) out_ += ',';
  first_.back() = 0;
  if (indent_ >= 0) newline_indent();
  string(k);
  out_ += indent_ >= 0 ? ": " : ":";
  return *this;
}

void JsonStream::begin_object() {
  before_value();
  out_ += '{';
  first_.push_back(1);
  array_.push_back(0);
}

void JsonStream::begin_array() {
  before_value();
  out_ += '[';
  first_.push_back(1);
  array_.push_back(1);
}

void JsonStream::end_object() {
  const bool empty = first_.back();
  first_.pop_back();
  array_.pop_back();
  if (!empty && indent_ >= 0) newline_indent();
  out_ += '}';
}

void JsonStream::end_array() {
  const bool empty = first_.back();
  first_.pop_back();
  array_.pop_back();
  if (!empty && indent_ >= 0) newline_indent();
  out_ += ']';
}

void JsonStream::null() {
  before_value();
  out_ += "null";
}

void JsonStream::value(bool b) {
  before_value();
  out_ += b ? "true" : "false";
}

void JsonStream::integer(std::int64_t v) {
  before_value();
  char buf[32];
  out_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

void JsonStream::unsigned_integer(std::uint64_t v) {
  before_value();
  char buf[32];
  out_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

void JsonStream::value(double d) {
  before_value();
  if (!std::isfinite(d)) {  // as nlohmann's dump: NaN and infinities print as null
    out_ += "null";
    return;
  }
  char buf[64];  // nlohmann's serializer: its shortest round-trip digits, "1.0" for integers
  out_.append(buf, ::nlohmann::detail::to_chars(buf, buf + sizeof buf, d));
}

void JsonStream::value(std::string_view s) {
  before_value();
  string(s);
}

void JsonStream::string(std::string_view s) {
  bool plain = true;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f || c == '"' || c == '\\') {
      plain = false;
      break;
    }
  }
  if (plain) {
    out_ += '"';
    out_.append(s);
    out_ += '"';
    return;
  }
  // Escapes, UTF-8 and invalid bytes (replaced by U+FFFD): nlohmann's own.
  out_ += nlohmann::ordered_json(std::string(s)).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void JsonStream::value(const nlohmann::ordered_json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::object:
      begin_object();
      for (const auto& [k, v] : j.items()) {
        key(k);
        value(v);
      }
      end_object();
      return;
    case nlohmann::json::value_t::array:
      begin_array();
      for (const auto& v : j) value(v);
      end_array();
      return;
    case nlohmann::json::value_t::string: value(j.get_ref<const std::string&>()); return;
    case nlohmann::json::value_t::boolean: value(j.get<bool>()); return;
    case nlohmann::json::value_t::number_integer: integer(j.get<std::int64_t>()); return;
    case nlohmann::json::value_t::number_unsigned: unsigned_integer(j.get<std::uint64_t>()); return;
    case nlohmann::json::value_t::number_float: value(j.get<double>()); return;
    default:  // null, discarded, binary: as dump writes them
      before_value();
      out_ += j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      return;
  }
}

// ---------------------------------------------------------------- one spline

namespace {

using Json = nlohmann::ordered_json;

void write_root(JsonStream& o, const SpanRoot& r, bool extremum) {
  o.begin_object();
  o.member("t", r.t);
  o.key("enclosure");
  o.begin_array();
  o.value(r.t_lo);
  o.value(r.t_hi);
  o.end_array();
  o.member("exact", r.exact);
  o.member("multiplicity", r.multiplicity);
  if (extremum) {
    o.member("kind", root_kind_word(r.sign_before, r.sign_after));
    o.member("kappa", r.kappa);
  } else {
    o.member("kind", r.sign_before == r.sign_after ? "touch" : "sign change");
  }
  o.member("at", root_at_word(r.at));
  o.end_object();
}

void write_roots(JsonStream& o, const char* key, const std::vector<SpanRoot>& roots, bool extremum) {
  o.key(key);
  o.begin_array();
  for (const SpanRoot& x : roots) write_root(o, x, extremum);
  o.end_array();
}

void write_segments(JsonStream& o, const SplineReport& r) {
  o.key("segments");
  o.begin_array();
  for (const SpanReport& sp : r.spans) {
    o.begin_object();
    o.member("index", sp.segment.index);
    o.key("interval");
    o.begin_array();
    o.value(sp.segment.a);
    o.value(sp.segment.b);
    o.end_array();
    if (!r.analysis.judged(sp.segment.index)) {  // --segments: not judged, its roots still listed
      o.member("ignored", true);
      o.member("curvature", "ignored");
      o.member("inflection", "ignored");
      o.member("lambda_zero", sp.lambda_zero);
      o.member("eta_zero", sp.eta_zero);
      write_roots(o, "extrema", sp.extrema, true);
      write_roots(o, "inflections", sp.inflections, false);
      o.end_object();
      continue;
    }
    o.member("class", shape_class(sp.shape));
    o.member("curvature", to_string(sp.classification.monotonicity.curvature));
    o.member("inflection", to_string(sp.shape.inflection));
    o.member("zero_curvature_at", kappa_zero_at(sp.shape));
    o.member("algorithm2", to_string(sp.classification.inflection.inflection));
    o.member("depth", sp.classification.monotonicity.depth);
    o.member("inflection_depth", sp.classification.inflection.depth);
    o.member("exact", sp.classification.exact_used);
    o.member("lambda_zero", sp.lambda_zero);
    o.member("eta_zero", sp.eta_zero);
    o.member("kappa_spread", sp.kappa_spread);  // not finite: null
    o.member("turning_deviation", sp.turning_deviation);
    o.member("near_constant", sp.near_constant);
    write_roots(o, "extrema", sp.extrema, true);
    write_roots(o, "inflections", sp.inflections, false);
    if (sp.shape.pole) o.member("poles", Json(sp.shape.poles));
    o.end_object();
  }
  o.end_array();
}

// The report's joint: joint_json's fields with "corner" (not G1).
void write_joint(JsonStream& o, const Joint& j, bool corner) {
  o.begin_object();
  write_joint_members(o, j, {corner, false, false});
  o.end_object();
}

void write_place(JsonStream& o, const CurveEvent& e) {
  o.member("on_joint", e.joint >= 0);
  o.key("segment");
  if (e.segment >= 0) o.value(e.segment);
  else o.null();
  o.key("joint");
  if (e.joint >= 0) o.value(e.joint);
  else o.null();
}

void write_fixes(JsonStream& o, const SplineReport& r) {
  o.key("fixes");
  if (!r.fixes) {
    o.null();
    return;
  }
  o.begin_array();
  for (const Fix& f : *r.fixes) {
    o.begin_object();
    o.member("point", f.point);
    o.member("region_pixels", f.pixels);
    o.key("example");
    if (f.example) {
      o.begin_array();
      o.value(f.example->x);
      o.value(f.example->y);
      o.end_array();
    } else {
      o.null();
    }
    o.member("verified", f.verified);
    o.end_object();
  }
  o.end_array();
}

void write_batch_tail(JsonStream& o, const SplineReport& r, const SplineJsonExtras& x) {
  if (!x.source) return;
  o.member("source", *x.source);
  o.member("glyph", x.glyph);
  o.member("contour", x.contour);
  if (r.error.empty() && x.findings) {
    o.key("findings");
    o.begin_array();
    for (const Finding& f : *x.findings) {
      o.begin_object();
      o.member("gate", f.gate);
      o.member("node", f.node);
      o.member("message", f.message);
      o.member("key", f.key());
      if (f.severity >= 0) {  // --min-severity: the smallest certified move that removes it (null: none found)
        o.key("severity");
        if (std::isfinite(f.severity)) o.value(f.severity);
        else o.null();
        if (!f.severity_note.empty()) o.member("severity_note", f.severity_note);  // why null
        o.member("level", f.info ? "info" : "error");
      }
      o.end_object();
    }
    o.end_array();
  }
}

}  // namespace

void write_spline_json(JsonStream& o, const SplineReport& r, int index, const SplineJsonExtras& x) {
  o.begin_object();
  std::string id = "s";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string
  id += std::to_string(index);
  o.member("id", id);
  o.member("file", r.file);
  o.member("name", r.name);
  o.member("status", status_word(r));
  if (!r.error.empty()) {
    o.member("error", r.error);
    write_batch_tail(o, r, x);
    o.end_object();
    return;
  }
  const BSpline& s = *r.spline;
  o.member("degree", s.degree());
  o.member("control_points", s.unique_point_count());
  o.key("domain");
  o.begin_array();
  o.value(s.domain_begin());
  o.value(s.domain_end());
  o.end_array();

  o.key("verdict");
  o.begin_object();
  o.member("cmrwi", verdict_label(r, r.analysis.cmrwi));
  o.member("cmr", verdict_label(r, r.analysis.cmr));
  o.member("cmr_algorithm2", to_string(r.analysis.cmr_algorithm2));
  if (r.analysis.split) o.member("split", to_string(*r.analysis.split));
  if (r.analysis.range != SegmentRange{0, s.segment_count() - 1}) {
    o.key("segments");
    o.begin_array();
    o.value(r.analysis.range.first);
    o.value(r.analysis.range.last);
    o.end_array();
  }
  o.member("joint_conflicts", r.analysis.joint_conflicts);
  o.end_object();

  o.key("curvature");
  o.begin_object();
  o.member("cusp", r.cusp);
  o.key("min");
  o.begin_object();
  o.member("kappa", r.kappa_min);
  o.member("t", r.t_min);
  o.end_object();
  o.key("max");
  o.begin_object();
  o.member("kappa", r.kappa_max);
  o.member("t", r.t_max);
  o.end_object();
  o.member("monotone_pieces", r.monotone_pieces);
  o.key("extrema");
  o.begin_array();
  for (const CurveEvent& e : r.extrema) {
    o.begin_object();
    o.member("t", e.t);
    o.member("kind", to_string(event_kind(r, e)));
    o.member("direction", e.kind > 0 ? "maximum" : "minimum");
    o.member("kappa", e.kappa);
    write_place(o, e);
    o.end_object();
  }
  o.end_array();
  o.key("inflections");
  o.begin_array();
  for (const CurveEvent& e : r.inflections) {
    o.begin_object();
    o.member("t", e.t);
    o.member("kappa_sign_after", e.kind);
    write_place(o, e);
    o.end_object();
  }
  o.end_array();
  if (r.analysis.pole) o.member("pole", true);
  o.end_object();

  write_segments(o, r);
  o.key("joints");
  o.begin_array();
  for (const JointReport& jr : r.joints) write_joint(o, jr.joint, jr.corner);
  o.end_array();
  write_fixes(o, r);
  if (!r.certified_fixes.empty()) {
    o.key("certified_fixes");
    o.begin_array();
    for (const CertifiedFix& f : r.certified_fixes) o.value(certified_fix_json(f, x.point_names));
    o.end_array();
  }
  if (s.closed()) o.member("closed", true);
  if (!r.gates.empty()) {
    o.key("gates");
    o.begin_array();
    for (const GateResult& g : r.gates) {
      o.begin_object();
      o.member("gate", to_string(g.gate));
      o.member("pass", g.pass());
      o.key("violations");
      o.begin_array();
      for (const GateViolation& v : g.violations) {
        o.begin_object();
        o.member("t", v.t);
        o.member("message", v.message);
        if (v.segment >= 0) {
          o.member("segment", v.segment);
          o.member("local_t", v.local_t);
        }
        if (v.joint >= 0) o.member("joint", v.joint);
        o.end_object();
      }
      o.end_array();
      o.end_object();
    }
    o.end_array();
  }
  write_batch_tail(o, r, x);
  o.end_object();
}

nlohmann::ordered_json spline_json_tree(const SplineReport& r, int index, const SplineJsonExtras& x) {
  std::vector<SplineReport> one;  // report_json takes a list: its one spline, renamed "s<index>"
  one.push_back(r);
  Json j = std::move(report_json(one, ReportOptions{})["splines"][0]);
  std::string id = "s";
  id += std::to_string(index);
  j["id"] = id;
  if (!x.source) return j;
  // The batch writer's additions, as report/corpus.cpp made them before the stream.
  j["source"] = *x.source;
  j["glyph"] = x.glyph;
  j["contour"] = x.contour;
  if (x.point_names && j.contains("certified_fixes")) {
    j["certified_fixes"] = Json::array();
    for (const CertifiedFix& f : r.certified_fixes) j["certified_fixes"].push_back(certified_fix_json(f, x.point_names));
  }
  if (r.error.empty() && x.findings) {
    Json fj = Json::array();
    for (const Finding& f : *x.findings) {
      Json item = {{"gate", f.gate}, {"node", f.node}, {"message", f.message}, {"key", f.key()}};
      if (f.severity >= 0) {
        item["severity"] = std::isfinite(f.severity) ? Json(f.severity) : Json(nullptr);
        if (!f.severity_note.empty()) item["severity_note"] = f.severity_note;
        item["level"] = f.info ? "info" : "error";
      }
      fj.push_back(item);
    }
    j["findings"] = fj;
  }
  return j;
}

}  // namespace cmr::report
