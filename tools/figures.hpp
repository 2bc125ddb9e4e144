#pragma once
// The paper's figures (CAD&A 2024: Fig. 1 of §3; Figs. 2-7 for Bezier
// curves and 8, 9, 10 for B-splines of §4; Figs. 11, 12 of §5.1, each piece on its own; Fig. 13 of §5.2), recomputed and drawn, with every statement the
// paper makes about them checked as a claim on the region label maps and on
// analyze(). The paper gives no coordinates; the curves are chosen in
// figures.cpp (one line each on why) and kept in examples/figures/.
#include <filesystem>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "spline/bspline.hpp"
#include "draw/draw.hpp"

#include "region/region.hpp"
#include "spline/limits.hpp"

namespace cmr::fig {

/// What make_figures computes and where it writes.
struct FiguresOptions {
  std::filesystem::path out = "out/figures";  ///< created if missing
  std::shared_ptr<RegionBackend> backend;     ///< where regions are rendered (required)
  int size = 400;                             ///< side of every region image, pixels
  int depth = kDefaultDepth;                  ///< D of Algorithms 1 and 2
  std::ostream* progress = nullptr;           ///< one line per step when set
};

/// One checked statement. `detail` gives the measured values, so that a
/// failure says what was found.
struct Claim {
  std::string figure;  ///< "Fig. 8a"
  std::string text;
  bool pass = false;
  std::string detail;
};

/// One figure of the page: its PNG and SVG and its texts.
struct FigureFile {
  std::string id;       ///< "fig8" (the files are id + ".png" and id + ".svg")
  std::string title;
  std::string caption;  ///< with the one-line reasons for the chosen curves
  std::vector<std::vector<draw::TextBox>> labels;  ///< the labels drawn in each panel (draw::figure_png)
  std::vector<std::string> panels;  ///< each panel's caption, row by row ("(a) ...", "curvature plot of (a)")
};

/// The figures, the checked claims and every file written.
struct FiguresResult {
  std::vector<FigureFile> figures;
  std::vector<Claim> claims;
  std::vector<std::filesystem::path> written;  ///< PNGs, spline files, index.html
  bool all_pass() const;  ///< every claim passes
};

/// Every curve the figures show (base curves and their edited states), named
/// as their files in examples/figures/ ("fig8b" -> fig8b.json).
std::vector<BSpline> figure_splines();

/// Computes the regions on options.backend, checks the claims, writes one PNG
/// per figure, the spline files and index.html into options.out, all
/// together at the end (one cmr::OutputSet): on any failure no file is
/// written or replaced. Throws InputError for bad options or an unwritable
/// folder; what the backend throws (EnvironmentError, BackendError)
/// propagates.
FiguresResult make_figures(const FiguresOptions& options);

}  // namespace cmr::fig
