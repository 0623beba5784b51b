#pragma once
// Key poses of a clip picked from the shape of its map trajectory (after Assa et al., "Action
// Synopsis: Pose Selection and Illustration", SIGGRAPH 2005: embed the motion, then take the
// salient points of the embedded curve), and the measure that says whether they summarise the
// motion: rebuild the clip by interpolating between its key poses and compare.
//
//   const auto map = motionmap::pipeline::map_clips(clips, options);
//   const auto rows = motionmap::pipeline::clip_key_rows(map, 0, 8);   // map rows of clip 0's keys
//   std::vector<int> keys;                                              // their file frames
//   for (int r : rows) keys.push_back(map.features->frame_of[r]);
//   const Motion rebuilt = motionmap::pipeline::interpolate_keys(clips[0].motion, keys);
//   double err = motionmap::pipeline::rms_rotation_error(clips[0].motion, rebuilt, keys.front(),
//                                                        keys.back());  // degrees
//
// The rule (select_key_poses): the first and the last point are keys, and the others are the
// ones for which moving from key to key in a straight line at constant speed — for point t
// between keys a < t < b, p_a + (t − a)/(b − a)·(p_b − p_a) — stays closest to the trajectory:
// the least sum of squared distances, found exactly by dynamic programming over every choice
// (O(count · #points²); above kExactPoints points, over every k-th point). Turning points and
// extremes of the curve are far from any chord that skips them, and so are pauses and speed
// changes along a straight stretch: what interpolating between key poses would miss. On the PCA
// map (keyposes' default), a linear projection of the poses' features, that error is the
// projection of the error of rebuilding the motion from its keys as interpolate_keys() does.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "motionmap/pipeline/clip_map.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::pipeline {

/// Above this many points, select_key_poses considers every k-th (k = ⌈#points / kExactPoints⌉)
/// and the last: 2 000 points, 2 · 10⁶ chord costs per key.
inline constexpr int kExactPoints = 2000;

/// `count` rows of `points` (one row per frame, in time order, ≥ 1 column) picked by the rule
/// above, increasing, the first and last rows among them; all rows when count ≥ #rows (or
/// #rows considered). Ties go to the earliest choice.
/// @throws ParameterError if count < 2 or points has < 2 rows or a non-finite value.
std::vector<int> select_key_poses(const Eigen::MatrixXd& points, int count);

/// `count` evenly spaced indices of [0, frames): round(i·(frames − 1)/(count − 1)), the baseline
/// key poses are measured against. @throws ParameterError if count < 2 or frames < 2.
std::vector<int> uniform_key_poses(int frames, int count);

/// The rows of `map` that are clip `clip`'s samples, in time order.
std::vector<int> clip_rows(const ClipMap& map, int clip);
/// The same for any map's samples given each one's clip (a saved map's clip_of): the rows whose
/// clip is `clip`, in order.
std::vector<int> clip_rows(std::span<const int> clip_of, int clip);

/// The key poses of clip `clip` of `map`: select_key_poses on its rows of the map (clip_rows), as
/// rows of the map (their file frames: map.features->frame_of). @throws ParameterError if the
/// clip has fewer than 2 samples in the map, or as select_key_poses.
std::vector<int> clip_key_rows(const ClipMap& map, int clip, int count);

/// `motion` rebuilt from its frames `keys` (increasing, in range): between consecutive keys a and
/// b each joint's local rotation is slerped and its translation interpolated linearly at
/// (f − a)/(b − a); frames before the first key and after the last hold those keys.
/// @throws ParameterError if keys is empty, not increasing or out of range.
Motion interpolate_keys(const Motion& motion, std::span<const int> keys);

/// The RMS, over frames first…last and every joint, of the angle between the local rotations of
/// `a` and `b`, in degrees. @throws ParameterError for motions of different sizes or a bad range.
double rms_rotation_error(const Motion& a, const Motion& b, int first, int last);

}  // namespace motionmap::pipeline
