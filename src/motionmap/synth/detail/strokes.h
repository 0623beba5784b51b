#pragma once
// A stroke of a sketch between two points on a clip's curve, drawn at about that clip's timing,
// follows the clip's curve rather than the straight line between the points (docs/synthesis.md,
// "Path → motion").
//
// A gait's curve on a map loops once a cycle, and a stroke drawn through the take's region with a
// point every third of a second cuts across each loop; a golf swing's, from impact to the
// follow-through, cuts past the address pose, out of the data. Along the chord the path passes
// the curve's samples at other times than its own, or other takes' curves inside the loop: the
// old walk's sketch followed the tired walk at a third of its pace with a foot held up 0.83 s (the
// captures lift one for 0.33–0.40 s), and the normal run's became a walk in the middle and
// covered 1.0 m of the capture's 2.0 (bench/traced_walks.py).
//
// So, for a stroke (two consecutive points a, b of the timed path, at t_a < t_b, with frames
// between them), every pair of clip times τ_a, τ_b on one run of samples whose points on the
// trajectory lie within kFollowFar median steps of a and of b, τ_b later, is a candidate. It
// plays the clip at the rate r = (τ_b − τ_a)/(t_b − t_a); its cost is the mean squared distance
// of the two ends, plus (log₂ r)² × (kFollowNear steps)² (a stroke drawn at the clip's own timing
// is preferred to one that fits a faster or slower playing: a curve that crosses itself offers
// both), plus (1 − f) × (kFollowFar steps)², f being 1 for rates within [kFollowMinRate,
// kFollowMaxRate] and falling to 0 over a further factor of kStrokeRateMargin. As with
// locate_path()'s fits (blender.h), the candidates within a tie of the least cost share the
// stroke (kFollowTie, kFollowTieSteps), and its frames move onto their curves by a share that is 1
// while the least cost, as an RMS, is within kFollowNear steps and falls to 0 at kFollowFar (so the
// frames move continuously as a point is dragged off the curve). A candidate's curve at time t is
// T(τ_a + r·(t − t_a)) plus the offsets of the stroke's ends from their points on the curve,
// shared linearly, so the frames still meet the drawn points.
// A stroke between two consecutive samples of a clip at its timing is already its curve; a path
// drawn point by point, a point a frame, has no frames between its points and stays as drawn.
#include <span>

#include <Eigen/Core>

#include "motionmap/synth/detail/map_index.h"
#include "motionmap/synth/path.h"

namespace motionmap::synth::detail {

/// A stroke's candidates' rates are let off from the follow's bounds to nothing over this
/// further factor (so a stroke redrawn a little faster or slower moves its frames continuously).
inline constexpr double kStrokeRateMargin = 1.25;

/// Moves `points` (timed.points resampled every `dt` seconds from timed.times.front(), as
/// resample_path() makes them) onto the clips' curves along the strokes that join them (above).
void follow_strokes(const MapIndex& index, const MapPath& timed, double dt,
                    std::span<Eigen::Vector2d> points);

}  // namespace motionmap::synth::detail
