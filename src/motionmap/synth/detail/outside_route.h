#pragma once
// A path outside the data, or far inside it, or where a gait's blend stalls, follows the clips'
// own frames (docs/synthesis.md, "Outside the data").
//
// Where a path leaves the data (MapBlender::inside() false) each of its frames is moved to the
// data's edge, where the blend mixes the phases of a gait cycle (or, between two clips, flips
// from one clip's edge to the other's): such a stretch skated 0.92 of its transitions, 151 cm/s
// in contact, between two captured walks. Inside the data but farther than half the reach from
// every sample, the kriging mixes the phases too (a sketch along the edge of two walks' data:
// 1.26° of joint angles changed by cleaning its feet, against 0.42° routed). So a run of such
// frames is played instead by a route through the clips' own frames that tracks the path:
// find_clip_route over the run's frames, a step per frame, each step paying kOutsideTrack ×
// ((distance from the sample to the frame's path point − the nearest sample's) / the reach)²
// besides the route's own costs (holds, skips, jumps priced by their poses as in-betweens price
// them: kPricedJumpSamples), played as in-betweens play their routes (play_clip_route).
// (Measured from the nearest sample, a path far away pulls no harder than one close by: by the
// plain distance, a path 7 reaches off a winding clip pulled the route to its bends and made it
// jump.) Where a run meets the data the route starts one frame earlier
// (ends one later) on the sample the blend of that frame is mostly on (towards it: its place and
// pose), and its share rises from 0 to 1 (smoothstep) over kFollowSeconds of frames, so the
// motion goes on from the blend in step and without a pop; at the path's own ends it plays from
// the first frame. A run with frames outside the data starts (ends) kFollowSeconds earlier
// (later), so its route plays all of it and fades over the frames beside it (outside_runs). Runs
// longer than kMaxClipRouteSteps steps are routed in pieces, each starting on the last one's
// sample. Local mode only (MapBlender::locate_path follows clips in it alone).
//
// Near the data a gait's blend can stall too: where a path runs beside two takes' curves but its
// nearest samples keep to one phase of the gait (their curves cross there, or their phases lie
// out of step), the registered phase hardly moves on while the path does (MapWeights::pace ≪ 1,
// detail/gait_phase.h), and the blend holds its legs in mid-stride as its root slows: a left foot
// off the floor for 3 s, where the captures lift one for 0.37 s at most (the tired walk drawn 30 %
// of the way to the old one). The skating measure does not see it: a foot held up never slides.
// Such a frame — its located pace below kStallPace, its point farther than kFollowNear median
// steps from every sample (on a clip's trajectory a slow pace is that clip played slowly), while
// the path moves on over the map at kStallPathSpeed × the clips' median map speed or faster (a
// path that dwells there holds the pose, as it should) — is routed too, with the frames within
// kStallSeconds of it, so that one route plays the whole stretch. So is a frame whose phase the
// registration could not read (MapWeights::lead_pace below kStallPace, near the samples too):
// its legs play its sources' own leads, and those stood still for 10–20 frames, then flipped to
// another phase, between two runs' curves (halfway from the old run to the angry one: 303 cm/s
// in contact cleaned, the capture 124; with the runs' shares smoothed, 197 and a joint still
// stepping 53 cm in a frame; routed where the leads stall, 105 cm/s and 24 cm).
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/synth/blender.h"

namespace motionmap::synth::detail {

/// Weight of the tracking cost against the route's step costs (a hold or a skip costs 0.2).
inline constexpr double kOutsideTrack = 0.1;
/// Frames farther than this fraction of the reach (MapBlender::reach_distance) from every sample
/// are routed as those outside are (and at least kFollowNear median steps away).
inline constexpr double kRouteReachFraction = 0.5;

/// A gait's blend stalls where its pace (MapWeights::pace, away from the samples) or its lead's
/// (MapWeights::lead_pace) is below this …
inline constexpr double kStallPace = 0.5;
/// … while the path moves on at this × the clips' median map speed (MapBlender::median_speed)
/// or faster (its central difference over the frames either side).
inline constexpr double kStallPathSpeed = 0.25;
/// Frames within this many seconds of a stalled frame are routed with it.
inline constexpr double kStallSeconds = 0.5;

/// Per frame of `located` (frames [first, first + located.size()) of the path `points`, dt
/// seconds apart, as MapBlender::locate_path gives them): 1 where the blend stalls (see the top of
/// the file: a frame reads its own pace and distance and the points either side), 0 elsewhere;
/// all 0 but in the local mode.
std::vector<char> stalled_frames(const MapBlender& blender, std::span<const Eigen::Vector2d> points,
                                 double dt, std::span<const MapWeights> located,
                                 std::size_t first = 0);
/// kStallSeconds in frames of dt seconds.
int stall_spread(double dt);
/// The note a result whose gait stalled gets (SynthResult::notes): how many frames `stalled`
/// marks inside the data (`validity`, one per frame: frames outside it have their own note), and
/// that the clips' own frames play around them; empty when none.
std::string stalled_note(std::span<const char> stalled, std::span<const PointValidity> validity);

/// The runs of frames of `points` to route, [first, end) each, in order: stretches of frames
/// outside the data or farther from every sample than kRouteReachFraction of the reach and
/// kFollowNear median steps (where locate_path plays no clip wholly), or within `spread` frames
/// of a frame `stalled` marks (stalled_frames of the whole path, or empty), at least two frames
/// long; one with a frame outside the data widened by `pad` frames each side (the route's fade,
/// MapBlender::follow_neighbours), runs that then meet joined; none but in the local mode, or on
/// a map whose samples never move.
using OutsideRuns = std::vector<std::pair<std::size_t, std::size_t>>;
OutsideRuns outside_runs(const MapBlender& blender, std::span<const Eigen::Vector2d> points,
                         std::span<const char> stalled = {}, int spread = 0, int pad = 0);
/// The frames of `runs` whose point was outside the data (`validity`: one per frame of the path):
/// SynthResult::routed_frames.
int routed_outside(const OutsideRuns& runs, std::span<const PointValidity> validity);

class OutsideRoutes {
 public:
  /// The routes of `runs` (outside_runs of `points`, a path, one point every dt seconds) that
  /// meet frames [first, end); a run's route depends on its own points and the blends of the
  /// frames beside it alone. `located`: the path's frames from `located_first` on, as
  /// MapBlender::locate_path gives them, where the caller has them (the frames beside a run are
  /// located again where not). Polls `control`.
  OutsideRoutes(const MapBlender& blender, std::span<const Eigen::Vector2d> points, double dt,
                const OutsideRuns& runs, std::size_t first, std::size_t end,
                const Control& control = {}, std::span<const MapWeights> located = {},
                std::size_t located_first = 0);
  /// Frame k's located weights with its run's route blended in (unchanged outside every run
  /// routed); the validity stays the located one.
  void apply(std::size_t k, MapWeights& w) const;

 private:
  struct Run {
    std::size_t first = 0, end = 0;
    std::vector<MapWeights> weights;  // per frame of the run: the route's
    std::vector<double> share;        // per frame: the route's share of the weights
  };
  // The run routed that frame k is in; null when none.
  const Run* run_at(std::size_t k) const;
  std::vector<Run> m_runs;
};

}  // namespace motionmap::synth::detail
