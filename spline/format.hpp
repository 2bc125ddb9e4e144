#pragma once
/// Numbers as cmr's messages and reports print them: the shortest of
/// std::ostream's default (%g-like) forms with `significant` digits
/// ("0.0478", "1e-09", "3"). 17 digits give back the same double when read.
///
/// std::to_chars in the general format with a precision is specified as
/// printf's %.*g in the "C" locale, which is what std::ostream's default
/// float field writes, without an ostringstream (its locale set-up) per
/// number: a corpus report prints millions (tests/spline/format_test.cpp
/// compares the two).
#include <charconv>
#include <string>

namespace cmr {

inline std::string format_number(double v, int significant = 6) {
  char buf[64];
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, significant);
  return std::string(buf, r.ptr);
}

}  // namespace cmr
