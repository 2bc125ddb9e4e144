#pragma once
/// report.json written as text, spline by spline, without a JSON tree
/// (issue 24 item 6: building and freeing an nlohmann tree per spline was
/// about a third of a font's CPU time).
///
/// JsonStream emits exactly what nlohmann::ordered_json::dump(indent, ' ',
/// false, error_handler_t::replace) writes for the same keys and values in
/// the same order: the same separators and indentation, doubles through
/// nlohmann's own shortest round-trip formatter (NaN and infinities as null),
/// strings escaped by nlohmann unless they are plain printable ASCII.
/// write_spline_json is the stream twin of the tree that report_json and the
/// batch writer build (spline_json_tree); tests/report/json_stream_test.cpp
/// compares the two texts on seeded splines so that they cannot drift apart.
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/joint_json.hpp"
#include "report/corpus.hpp"
#include "report/report.hpp"

namespace cmr::report {

class JsonStream {
 public:
  /// Appends to `out`; indent < 0: compact, else pretty with that many spaces.
  explicit JsonStream(std::string& out, int indent = -1) : out_(out), indent_(indent) {}

  void begin_object();
  void end_object();
  void begin_array();
  void end_array();
  /// The next member's key (inside an object).
  JsonStream& key(std::string_view k);

  void null();
  void value(bool b);
  void value(double d);
  void value(std::string_view s);
  void value(const char* s) { value(std::string_view(s)); }
  void value(const std::string& s) { value(std::string_view(s)); }
  template <typename T, std::enable_if_t<std::is_integral_v<T> && !std::is_same_v<T, bool>, int> = 0>
  void value(T v) {
    if constexpr (std::is_signed_v<T>) integer(static_cast<std::int64_t>(v));
    else unsigned_integer(static_cast<std::uint64_t>(v));
  }
  /// A whole tree, written element by element (the rare parts: fixes, poles).
  void value(const nlohmann::ordered_json& j);

  /// key(k) then value(v).
  template <typename T>
  void member(std::string_view k, const T& v) {
    key(k);
    value(v);
  }

 private:
  void before_value();
  void newline_indent();
  void integer(std::int64_t v);
  void unsigned_integer(std::uint64_t v);
  void string(std::string_view s);

  std::string& out_;
  int indent_;
  std::vector<char> first_;  // per open container: no element written yet
  std::vector<char> array_;  // per open container: is an array
};

/// What the batch writer adds to a spline's object (report/corpus.cpp).
struct SplineJsonExtras {
  const std::string* source = nullptr;                  ///< "source" (with glyph and contour), when set
  std::string glyph;                                    ///< "glyph"
  int contour = 0;                                      ///< "contour"
  const std::vector<std::string>* point_names = nullptr;  ///< the font's point names in "certified_fixes"
  const std::vector<Finding>* findings = nullptr;       ///< "findings" (valid splines only), when set
};

/// One spline's object of report.json, streamed; `index` names it "s<index>".
void write_spline_json(JsonStream& out, const SplineReport& r, int index, const SplineJsonExtras& extras = {});

/// The same object as a tree (report_json's spline with the batch writer's
/// additions): the reference the stream is tested against.
nlohmann::ordered_json spline_json_tree(const SplineReport& r, int index, const SplineJsonExtras& extras = {});

}  // namespace cmr::report
