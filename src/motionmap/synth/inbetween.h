#pragma once
// Key poses and in-betweening: a motion that passes through given key poses exactly, at their
// times, following between consecutive keys a route on the map (route.h): by default through the
// clips' own frames (RouteMode::Clips, find_clip_route), or the cheapest route through the valid
// region of the map (RouteMode::Grid, find_route) — Shin & Lee's motion-map in-betweening.
//
//   using namespace motionmap::synth;
//   MapBlender blender(clips, set, coords);
//   std::vector<Key> keys{sample_key(blender, find_sample(set, 0, 9), clips[0].motion, 9),
//                         sample_key(blender, find_sample(set, 0, 40), clips[0].motion, 40)};
//   InbetweenOptions options;
//   options.frames_between = 20;
//   auto result = inbetween(blender, set, keys, options);
//   // result.motion: 22 frames; result.key_frames = {0, 21}; result.routes[0]: the route drawn
//
// A key is a map point and, optionally, a pose (one frame of the blender's skeleton, standing
// where it stood in its clip) and a time. A clip frame that is a sample of the map sits on its
// sample's point; any other frame of a clip of the map's skeleton is placed on the map first (as
// `motionmap map --onto` places frames: mapfile::place_clips), so its blended pose differs from
// its own. A key without a pose (a map point) takes the blended pose there and leaves the root
// free.
//
// The motion, segment by segment between consecutive keys i and i + 1 at frames f_i < f_{i+1}:
//  1. map points: a clip route's samples, one per step, the steps spread evenly over the
//     segment's frames (the root then follows the route's pace: 0 on a hold, twice on a skip);
//     or the grid route (find_route) from key i's point to key i + 1's, walked so that the
//     frames fall at equal steps of the samples' own time along it: ∫ ds / v(s), v the mean map
//     speed of the 8 samples nearest s (at least a tenth of MapBlender::median_speed());
//  2. poses: synthesize() along those points, every frame on its point (a path timed at the
//     frames; a clip route's weights), which blends the pose and integrates the blended root
//     velocities, the weights smoothed over time as a sketch's are (kDefaultSmoothSeconds);
//  3. poses through the keys: a displacement map. At each key, per joint the rotation
//     d_j = q_key·q_blend⁻¹ (the motion root: of the tilts, its heading removed) and, for the
//     translations, key − blend (the root: its height only); faded by slerp (lerp) from key i's
//     to key i + 1's across the segment; a key without a pose takes the blend at its point
//     (MapBlender::pose_at) as its pose here;
//  4. root: the blended root motion integrated from key i's root placement (position on the
//     floor and heading), and the position and heading error it ends with at key i + 1 spread
//     linearly over the segment — so each key's root stands exactly where the key's did, and
//     key-to-key animation lines up in world space (InbetweenOptions::free_roots: only the
//     first key's; the rest pass the root on). Keys without a pose pass the root on;
//     before the first key with a pose and after the last one the motion moves rigidly with it;
//     without any, it starts at the origin with heading 0 as synthesize() does.
// So at every key the pose is the key's to rounding (joint rotations, root position and heading;
// with free_roots, after the first key, all but the root's position and heading).
//
// Timing: InbetweenOptions::frames_between = N puts N frames between consecutive keys; keys with
// times (Key::time, seconds from the first key) are put at the nearest frames of the blender's
// frame rate; neither: each segment takes the samples' own time along its route, rounded to
// whole frames (at least one) — between two keys with poses at least the time the root takes to
// cover their floor distance at the mean root speed over ±0.5 s of the clip of each key's nearest
// sample (unless those samples stand; with free_roots, unless those samples are of two clips):
// keys of a walk at one phase lie close on the map. A clip route between keys whose nearest
// samples are of one clip, the later one later in it, takes that clip's own time between them
// where that is 0.7–1.4 times the time above (the clip plays between them as captured); one
// between keys whose nearest samples are of two clips takes at least kJumpFadeSeconds (its jump's
// crossfade), and where both clips have a gait phase (MapBlender::gait_phase), the time nearest
// that at which the later key's phase comes round.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/features/features.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/route.h"

namespace motionmap::synth {

/// Most frames between two keys that frames_between may ask for.
inline constexpr int kMaxFramesBetween = 100000;
struct Key {
  /// Where the key lies on the map.
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  /// The pose passed through: one frame of the blender's skeleton, its motion root where it
  /// stood; no frames (the default) = a map-point key: the blended pose, the root free.
  Motion pose;
  /// Seconds; either every key has one or none does.
  std::optional<double> time;
  /// For messages, which name a key by its number from 1 and this: "key 2 (walk.bvh:120)".
  /// E.g. "walk.bvh:120", "1.5:-0.3".
  std::string label;

  bool has_pose() const { return pose.num_frames > 0; }
};

struct InbetweenOptions {
  /// Frames between consecutive keys, ≥ 0; −1 = not given (the keys' times, or the samples' own
  /// speed along the routes).
  int frames_between = -1;
  RouteOptions route;
  /// Hold each foot still through its contacts (clean_feet(), as synthesize() does) with the
  /// key frames fixed, so the keys stay exact; false: the blend as it is.
  bool clean_feet = true;
  /// Only the first key with a pose places the root (where it stood in its clip); every later
  /// key's pose is still hit exactly, but its root stands where the clips carry it from there, its
  /// position and heading left free — for keys of takes captured in different places, between
  /// which the root would otherwise glide. Untimed, keys whose nearest samples are of two
  /// clips then take their route's own time (at least kJumpFadeSeconds on a clip route).
  bool free_roots = false;
  /// On a blender reading its clips on demand (a saved map's), a clip route's jumps are priced by
  /// their poses, every sample's read first, where it has at most this many samples; on a larger
  /// one by their map distance alone (a bridge's one jump by its poses).
  int priced_jump_samples = kPricedJumpSamples;

  /// @throws ParameterError naming `frames_between`, `priced_jump_samples` or `grid`, the value
  /// and the valid range.
  void validate() const;
};

struct InbetweenResult {
  /// The in-betweened motion of MapBlender::skeleton(), at the blender's frame time.
  Motion motion;
  /// Per frame: where it was blended (synthesize()'s validity).
  std::vector<PointValidity> validity;
  /// Per frame: the map point of the route it was blended at.
  std::vector<Eigen::Vector2d> points;
  /// The frame of each key.
  std::vector<int> key_frames;
  /// Per segment (key i to key i + 1): the route polyline, from key i's point to key i + 1's.
  std::vector<std::vector<Eigen::Vector2d>> routes;
  /// The grid the routes were found on.
  RouteGrid grid;
  /// Frames whose map point is outside the valid region (a key placed outside the data).
  int outside_frames = 0;
  /// The feet were cleaned (InbetweenOptions::clean_feet and the skeleton has feet).
  bool feet_cleaned = false;
  /// Notes for the user: keys standing further apart than the clips walk in their time, a root
  /// gliding or turning where the clips carry it elsewhere, a time out of step with the keys'
  /// gait (with the time in step), why the feet were not cleaned.
  std::vector<std::string> notes;
};

/// The key of frame `frame` of `motion` (a motion of the blender's skeleton) that is the map's
/// sample `sample`: its point and pose. Label left empty.
/// @throws ParameterError if sample or frame is out of range or the joint counts differ.
Key sample_key(const MapBlender& blender, int sample, const Motion& motion, int frame);

/// The sample of the map that is frame `frame` of clip `clip` (FeatureSet::clip_of/frame_of), or
/// −1 when that frame is not a sample (left out by the frame selection, or a clip not in it).
int find_sample(const features::FeatureSet& samples, int clip, int frame);

/// The motion through `keys` (see the top of the file). `samples` are the blender's (clip_of and
/// frame_of give the samples' own speeds). Reports "routes" and "blending frames" through
/// `control`.
/// @throws ParameterError for fewer than 2 keys, a key of another joint count or with more than
///         one frame, a non-finite point, times on some keys but not all, times not increasing
///         or two keys closer than a frame apart, both times and frames_between, more than
///         kMaxSynthFrames frames, no route between two keys; as synthesize(); Cancelled.
InbetweenResult inbetween(const MapBlender& blender, const features::FeatureSet& samples,
                          std::span<const Key> keys, const InbetweenOptions& options = {},
                          const Control& control = {});

}  // namespace motionmap::synth
