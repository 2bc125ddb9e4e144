#pragma once
/// Certified fixes of a chain of STEP edges (issue 40 item 4; docs/space.md,
/// "Chains of edges"; `cmr fix MODEL.step --chain N`):
///
///   fix_step_chain(curves, chain, request) -> ChainFixResult
///
/// Each edge of the chain that fails the requirement gets space_fix's nearest
/// certified move of one control point (design/space_fix.hpp), chosen among
/// the points that do not carry its ends' jets, so that every junction keeps
/// its continuity without the neighbouring edge moving.
///
/// Why holding points keeps the junctions. An open edge's polar knots are
/// k_0..k_{m+d-2}; P_i is the blossom f(k_i, ..., k_{i+d-1}). At a clamped
/// start (k_0 = ... = k_{d-1} = u, as at every edge OpenCASCADE trims) the
/// j-th derivative there is a combination of f(u^{d-j}, .) of the first span,
/// i.e. of P_0..P_j alone; likewise P_{m-1-j}..P_{m-1} at a clamped end. So
/// holding P_0..P_k and P_{m-1-k}..P_{m-1} (and the weights, never moved)
/// keeps each end's k-jet (position and first k derivatives) bit for bit:
///   keep none  k = 0  the ends stay where they are (G0);
///   keep g1    k = 1  also the end tangents (G1 kept);
///   keep g2    k = 2  also the curvature vectors (G2 kept; the default);
///   keep g3    k = 3  also dkappa/ds and torsion (G3 kept).
/// An end that is not clamped holds its whole end span's d + 1 points (its
/// jets depend on them only). A planar edge (every point within 1e-12 of its
/// size of one plane) moves in that plane, so it stays on a planar face.
///
/// Requirements: each-piece (every edge's |kappa| monotone on its own),
/// cmrwi (also the whole chain one way, as `cmr import` judges it:
/// import::chain_verdict), cmr (cmrwi and no zero curvature on any edge).
/// The ends' curvatures are held, so a monotone edge's direction is forced by
/// them (kappa at its start against kappa at its end): where they disagree
/// along the chain no move of inner points makes the whole chain monotone,
/// and the result says so.
///
/// Certificate: each moved edge is space_fix's (its point rounded to doubles,
/// judged again by analyze_space). Then OpenCASCADE computes the chain's
/// junctions again from the fixed edges (import::step_chain_junctions) and
/// compares them with the input's, computed the same way: the fix holds only
/// when every junction's level is at least min(its level before, k).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "design/space_fix.hpp"
#include "step/step.hpp"

namespace cmr::import {

struct ChainFixRequest {
  bool whole_chain = true;        ///< cmrwi, cmr; false: each-piece
  bool no_zero_curvature = true;  ///< cmr
  int keep = 2;                   ///< k: the jet order held at every edge end, 0..3
  double max_move = 0;            ///< 0: each edge's size
  double tolerance = 1e-6;        ///< relative to each edge's size
  int max_depth = kDefaultDepth;
  double time_limit = 30;  ///< seconds per edge's search
};

struct ChainEdgeFix {
  std::size_t curve = 0;       ///< index into StepCurves::curves
  std::vector<int> held;       ///< the points that carry its ends' jets
  std::string before, after;   ///< its |kappa| in its own direction (analyze_space): increasing, decreasing, not monotone, undecided
  bool searched = false;       ///< failed the requirement: space_fix ran
  std::optional<SpaceFixResult> fix;  ///< when searched
  std::string reason;          ///< one line, when searched and not fixed
};

struct ChainFixResult {
  StepCurves curves;  ///< the input's, the moved edges' points replaced
  std::vector<ChainEdgeFix> edges;  ///< in chain order
  std::vector<StepJunction> junctions_before, junctions_after;  ///< both by step_chain_junctions
  bool already = false;  ///< the input meets the requirement: nothing moves
  bool fixed = false;    ///< every edge meets it, the whole chain too where required, and the junctions held
  std::string reason;    ///< one line, when not fixed
  double seconds = 0;
};

/// `chain`: an index into curves.chains. InputError (one line) for a chain
/// index out of range, a closed edge in the chain, keep outside 0..3, or bad
/// search options (space_fix's).
ChainFixResult fix_step_chain(const StepCurves& curves, std::size_t chain, const ChainFixRequest& request,
                              const ChainTolerances& tolerances = {});

/// The points of an open edge that carry its ends' k-jets (above), sorted.
std::vector<int> chain_held_points(const StepCurve& curve, int keep);

}  // namespace cmr::import
