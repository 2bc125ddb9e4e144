#pragma once
/// Numbers as cmr's messages and reports print them: the shortest of
/// std::ostream's default (%g-like) forms with `significant` digits
/// ("0.0478", "1e-09", "3"). 17 digits give back the same double when read.
#include <sstream>
#include <string>

namespace cmr {

inline std::string format_number(double v, int significant = 6) {
  std::ostringstream s;
  s.precision(significant);
  s << v;
  return s.str();
}

}  // namespace cmr
