#pragma once
/// A region's export files, written the same way by `cmr region` and the
/// editor's export-region: the label map as a binary PGM (one label code per
/// pixel, code() of region/region.hpp), one file per point when there are
/// several (PATH.PK.EXT), and the composite PNG (every point's region over
/// the curve, each point in its own colour when there are several, with the
/// legend). Staged on an OutputSet (io/output.hpp): all files or none.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "region/region.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"

namespace cmr::draw {

/// A binary PGM (P5) of `values`, one byte per pixel of a width x height
/// image, row 0 at the top; `maxval` is the largest value a pixel can take
/// (PGM viewers scale 0..maxval to black..white, so a depth map of levels
/// 0..D is visible with maxval D).
std::string pgm(int width, int height, const std::vector<std::uint8_t>& values, int maxval = 255);
/// The label map of a region: pgm of its label codes (RegionResult::codes).
std::string label_pgm(const RegionResult& image);

/// PATH with ".PK" before its extension: "out/r.pgm", 3 -> "out/r.P3.pgm"
/// (one file per point of `--point all`).
std::filesystem::path with_point_suffix(const std::filesystem::path& path, int point);

/// The region picture of `cmr region --png`: the spline, every layer (the
/// region of requests[i].point) with a ring on its point, the labels of the
/// requests' kind (plain, split, alternating), the legend, and per-point
/// colours when there are several layers. Keeps pointers to the spline and
/// the layers.
RegionPicture layers_picture(const BSpline& spline, const std::vector<RegionResult>& layers,
                             const std::vector<RegionRequest>& requests);

/// Stages the label PGM of each layer at `path` (one layer), or at
/// with_point_suffix(path, requests[i].point) (several).
void stage_label_pgms(OutputSet& out, const std::filesystem::path& path, const std::vector<RegionResult>& layers,
                      const std::vector<RegionRequest>& requests);

}  // namespace cmr::draw
