#include "draw/svg_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cmr::draw {

std::string svg_open(const std::vector<SvgAttribute>& attributes) {
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\"";
  for (const auto& [name, value] : attributes) out.append(" ").append(name).append("=\"").append(value).append("\"");
  return out + ">";
}

std::string svg_colour(Rgb c) {
  const auto byte = [](double channel) { return static_cast<int>(std::lround(std::clamp(channel, 0.0, 1.0) * 255)); };
  char text[16];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b));
  return text;
}

}  // namespace cmr::draw
