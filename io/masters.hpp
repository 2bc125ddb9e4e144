#pragma once
/// Masters and the pieces of a design space where every point moves
/// affinely (issue 37): what the interpolation gates judge
/// (report/interpolation.hpp).
///
/// A *piece* is a straight path through the design space, parametrised by
/// s in [0, 1], along which every point of every glyph is
///
///   P(s) = (1 - s) A + s B                                             (1)
///
/// for its values A at s = 0 and B at s = 1 (each a control point of a
/// contour's spline: a line's added inner points and a TrueType implied
/// midpoint are affine combinations of source points, so they move
/// affinely too).
///
///  * A designspace (io/ufo.hpp: its sources are the masters, UFOs; a source
///    in a UFO's other layer, a sparse master, is left out): along
///    each axis, between two masters whose design locations differ in that
///    axis only and with no other master on the line strictly between them
///    (adjacent masters; the other axes stay at the masters' values). s is
///    linear in the design value of the varying axis. (1) is varLib's
///    instance there when the designspace's normalisation is linear between
///    the two (both on one side of the axis's default, or one at it) and no
///    other master's value of that axis lies strictly between: its
///    variation model's tents break only at master values. Its user values
///    (what findings name) follow the axis's <map> backwards: piecewise
///    linear in s, with a break at each map point between.
///  * A variable font (fvar with gvar or CFF2; FreeType): each axis is cut
///    at -1, 0, 1 and at every region's start, peak and end on it (gvar's
///    tuple headers; CFF2's item variation store), in normalised
///    coordinates after avar; a piece runs between two adjacent cuts with
///    the other axes at 0 (the default) or at a region peak's values. A
///    tent's factor is linear between its own cuts and the other axes'
///    factors are constant on the line, so every delta's scalar, and so
///    every point, is affine there: (1) holds with A, B the instances at
///    the ends (FreeType's blend coordinates, post-avar). User values:
///    avar's map backwards, then fvar's normalisation backwards.
///  * `--between LOC1:LOC2` (axis tags and user values, "wght=400" and
///    "wght=700"; unnamed axes at their defaults): the two locations must
///    differ in one axis; the segment is cut into the pieces above that it
///    crosses (a designspace: only along a line of masters; a variable
///    font: any line along one axis), and each part is judged as the part
///    s0..s1 of its piece (Piece::s0, s1): the node's smoothness is that of
///    the piece's ends (masters, or a variable font's cuts).
///
/// Compatibility: every master's glyph must have the same contours with the
/// same control points (count, degree, knots: the same point types in the
/// same order). Otherwise the glyph is not judged: Glyph::error is one line
/// naming it and the first difference ("O: incompatible masters: contour 1
/// has 12 points in Regular, 13 in Bold"). A glyph a master lacks (a sparse
/// master) is judged on the pieces of the others. A variable font's instances
/// share their points; they differ only where the font reader dropped a line
/// of zero length at one instance (io/font.cpp), and the line says so
/// ("uni00A7: contour 0 has 67 points in the default instance, 66 in the
/// instance at wght=900: a line shrinks to zero length there, ...").
///
/// Errors (InputError, one line): a file that is neither a designspace nor a
/// variable font ("FONT: no fvar table: the interpolation gates need a
/// variable font or a designspace"), --between naming an axis the space does
/// not have, a value outside an axis's range, two locations that do not
/// differ in exactly one axis, or (a designspace) a segment off the masters'
/// lines; the designspace's own errors (io/ufo.hpp: missing sources, a
/// default outside its axis's range).
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/font.hpp"
#include "io/ufo.hpp"

namespace cmr::import {

/// One axis along a piece: its user value as a function of s in [0, 1],
/// piecewise linear through `at` ((s, user value), s ascending from 0 to 1;
/// one entry: constant).
struct PieceAxis {
  std::string name;  ///< "Weight" (a designspace's axis name; a variable font's fvar name, else its tag)
  std::string tag;   ///< "wght"
  std::vector<std::pair<double, double>> at{};
  double user(double s) const;
  bool varies() const;
};

/// A piece of the design space where every point moves affinely, (1).
struct Piece {
  /// The piece is part s0..s1 of the line between the motions' splines a
  /// (s = 0) and b (s = 1): its own parameter sigma in [0, 1] is the
  /// instance (1 - s) a + s b at s = s0 + (s1 - s0) sigma, exactly (a
  /// --between segment inside a designspace's piece keeps the masters as
  /// a and b, which are exact, rather than rounded instances). `axes` and
  /// the texts below take sigma.
  double s0 = 0, s1 = 1;
  std::string from, to;  ///< where it starts and ends: a master's name ("Regular") or a location ("wght=437.5")
  /// The masters at s = 0 and s = 1 of the line (a variable font: the cuts'
  /// locations): where the nodes judged are smooth.
  std::string master_a{}, master_b{};
  std::vector<PieceAxis> axes;
  /// The location at s: "\"Weight\": 437.5" for each varying axis, then the
  /// others ("\"Weight\": 437.5, \"Width\": 100").
  std::string location(double s) const;
  /// The varying axes over an open interval of s: "Weight in (400, 437.5)".
  std::string range(double s0, double s1) const;
};

/// One contour along one piece: its splines at s = 0 and s = 1 (the same
/// degree, knots and number of control points), and per segment whether
/// the node that starts it is marked smooth at both ends (a .glif's
/// smooth="yes"; a binary font has no such mark: true).
struct ContourMotion {
  std::shared_ptr<const Piece> piece;
  BSpline a, b;
  std::vector<bool> smooth{};
};

/// A design space read for the interpolation gates.
struct Masters {
  /// The default master's (instance's) glyphs: what the other gates judge
  /// and what findings are placed on. Font::path is the designspace or font.
  Font font;
  std::vector<std::shared_ptr<const Piece>> pieces;
  /// motions[g][c]: glyph g of `font` (its index), contour c (its index in
  /// Glyph::contours), one per piece the glyph takes part in.
  std::vector<std::vector<std::vector<ContourMotion>>> motions;
};

/// Two locations: --between LOC1:LOC2.
using Segment2 = std::pair<Location, Location>;
/// Parses "wght=400:wght=700" (InputError "--between: ..." otherwise).
Segment2 parse_between(const std::string& text);

/// Reads a designspace (its masters) or a variable font (its default
/// instance and the instances at the pieces' ends) with the glyphs
/// `which` selects (a variable font: its code points; none: every one),
/// cut into pieces as the header says: along the axes, or along `between`.
Masters read_masters(const std::filesystem::path& path, const GlyphSelection& which,
                     const std::optional<Segment2>& between = std::nullopt);

}  // namespace cmr::import
