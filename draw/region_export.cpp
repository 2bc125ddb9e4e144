#include "draw/region_export.hpp"

#include "spline/errors.hpp"

namespace cmr::draw {

std::string pgm(int width, int height, const std::vector<std::uint8_t>& values, int maxval) {
  CMR_CHECK(values.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  std::string out = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n" + std::to_string(maxval) + "\n";
  out.append(reinterpret_cast<const char*>(values.data()), values.size());
  return out;
}

std::string label_pgm(const RegionResult& image) { return pgm(image.width, image.height, image.codes()); }

std::filesystem::path with_point_suffix(const std::filesystem::path& path, int point) {
  std::filesystem::path p = path;
  p.replace_extension(".P" + std::to_string(point) + path.extension().string());
  return p;
}

RegionPicture layers_picture(const BSpline& spline, const std::vector<RegionResult>& layers,
                             const std::vector<RegionRequest>& requests) {
  CMR_CHECK(!layers.empty() && layers.size() == requests.size());
  RegionPicture picture;
  picture.spline = &spline;
  for (std::size_t i = 0; i < layers.size(); ++i) {
    picture.layers.push_back(&layers[i]);
    picture.points.push_back(requests[i].point);
  }
  picture.split = requests.front().split.has_value();
  picture.each_piece = requests.front().each_piece;
  picture.alternating = !requests.front().splits.empty() && !picture.each_piece;
  picture.max_depth = requests.front().max_depth;
  picture.legend = true;
  picture.per_point = layers.size() > 1;  // one composite picture, each point's region in its own colour
  return picture;
}

void stage_label_pgms(OutputSet& out, const std::filesystem::path& path, const std::vector<RegionResult>& layers,
                      const std::vector<RegionRequest>& requests) {
  CMR_CHECK(layers.size() == requests.size());
  for (std::size_t i = 0; i < layers.size(); ++i)
    out.stage(layers.size() > 1 ? with_point_suffix(path, requests[i].point) : path, label_pgm(layers[i]));
}

}  // namespace cmr::draw
