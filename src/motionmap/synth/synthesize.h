#pragma once
// Path → motion: a new clip whose every frame is the blend at a point of a path on the map,
// with root motion integrated from the samples' own heading-local velocities, so a sketched walk
// walks.
//
//   motionmap::synth::MapBlender blender(clips, set, coords);
//   auto path = motionmap::synth::read_path_csv("sketch.csv");
//   auto result = motionmap::synth::synthesize(blender, path);
//   motionmap::io::write_bvh(motionmap::io::from_motion(blender.skeleton(), result.motion),
//   "new.bvh");
//
// Per output frame k (at t0 + k/fps along the path, MapBlender::path_points: in the local mode a
// stroke between two points on a clip's curve at about its pace follows the curve,
// detail/strokes.h): weights at the path point (MapBlender::locate_path: where the path around the
// frame follows a clip's trajectory, that clip's own frames at the fitted time; where a run of
// frames lies outside the data or farther than half the reach from it, or within half a second of a
// frame whose gait stalls (its legs held while the path moves on), in the local mode, a route
// through the clips' own frames that tracks the path there, faded in over the blend where the run
// meets the data: detail/outside_route.h; optionally smoothed over time with a Gaussian, each
// neighbouring frame's weights moved back in their clips by its distance in time:
// MapBlender::later_in_clip), joint rotations and root height and tilt blended with them
// (MapBlender::blend), and the blended heading-local root velocity v_k and yaw rate ω_k integrated
// forward from the origin, heading 0:
//   position_{k+1} = position_k + yaw(θ_k)·v_k·Δt,   θ_{k+1} = θ_k + ω_k·Δt.
// The samples' velocities are forward differences, so a path that retraces the clip's own map
// trajectory at its own timing reproduces the clip (up to the start's position and heading).
// Then, by default, the feet are cleaned (clean_feet.h): the root is led by the planted feet (a
// foot most of the frame's blend weight plants stays where it stands: detail/root_motion.h,
// root_step) and each foot is held still through its contacts with the floor, the legs bent to
// reach; a skeleton without feet (find_feet) is left as blended, with a note. Set
// SynthOptions::clean_feet = false to get the blend as it is.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/clean_feet.h"
#include "motionmap/synth/path.h"

namespace motionmap::synth {

/// Longest synthesized clip, in frames (50 minutes at 120 fps).
inline constexpr long long kMaxSynthFrames = 360000;
/// Longest temporal smoothing (Gaussian σ), in seconds.
inline constexpr double kMaxSmoothSeconds = 10.0;
/// The temporal smoothing (Gaussian σ, seconds) synthesis uses unless told otherwise: the
/// weights located along a path between two runs hop between the runs' cycles from frame to
/// frame (a run's cycles lie on top of each other on the map), so the blended stance foot never
/// stands; ±0.15 s of smoothing lets it (docs/synthesis.md, "Clean feet").
inline constexpr double kDefaultSmoothSeconds = 0.05;

struct SynthOptions {
  /// Untimed paths: map units per second; 0 = the clip's median map speed
  /// (MapBlender::median_speed()).
  double speed = 0.0;
  /// Output frames per second in (0, 1000]; 0 = the source clip's frame rate.
  double fps = 0.0;
  /// σ in seconds of a Gaussian smoothing of the weights over time, in [0, kMaxSmoothSeconds];
  /// 0 = none. The neighbours' weights are moved in their clips by their distance in time first,
  /// so a retraced trajectory still reproduces the clip: smoothing softens a path's jumps and
  /// jitter between clips, not a clip's own motion.
  double smooth = kDefaultSmoothSeconds;
  /// When the skeleton has feet (find_feet(), along BlendOptions::up): lead the root by the
  /// planted feet (where the blender knows its samples' contacts) and hold each foot still through
  /// its contacts with the floor (clean_feet()); false: the blend as it is (a retraced trajectory
  /// then reproduces the clip).
  bool clean_feet = true;

  /// @throws ParameterError naming `speed`, `fps` or `smooth`, its value and the valid range.
  void validate() const;
};

struct SynthResult {
  Motion motion;  ///< #frames by #joints of MapBlender::skeleton(), at the output frame rate
  std::vector<PointValidity> validity;  ///< per frame: where it was evaluated, distance, variance
  int clamped_frames = 0;               ///< frames whose path point was outside the data
  /// Of those, the frames played by a route through the clips' own frames
  /// (detail/outside_route.h); the others are blended at the data's edge.
  int routed_frames = 0;
  /// Per frame of a path synthesized in the local mode: 1 where the gait's blend located there
  /// stalled (detail::stalled_frames: its legs held while the path moves on); the frames around
  /// such a frame play a route through the clips' own frames. edit_path() reads it. Empty in the
  /// other modes and for weights given.
  std::vector<char> stalled;
  bool feet_cleaned = false;  ///< SynthOptions::clean_feet and the skeleton has feet
  /// The contacts the clean-up held (left, right); empty when the feet were not cleaned.
  std::vector<FootContacts> contacts;
  /// Frames the clean-up changed, over the whole motion (after edit_path() too: recounted from
  /// feet_changed).
  int feet_frames_changed = 0;
  /// Per frame: 1 where the clean-up changed the frame from the blend (CleanFeetResult::changed);
  /// empty when the feet were not cleaned.
  std::vector<char> feet_changed;
  /// Per frame, per foot (left, right): the share of the frame's blend weight on samples whose
  /// foot is on the floor (MapBlender::contact_share); empty when the blender does not know its
  /// samples' contacts. The clean-up takes its contacts from these (contacts_from_shares): a
  /// blended foot slides too fast to be found by its own speed.
  std::vector<std::array<double, 2>> contact_shares;
  /// Notes for the user: why the feet were not cleaned, a root lowered to reach, …
  std::vector<std::string> notes;
  /// The options it was made with (edit_path() re-synthesizes a part of it with them).
  SynthOptions options;
  /// Per frame: the integrated root's floor position (up component 0; led by the planted feet
  /// with clean feet) and heading (radians about the up axis, not wrapped), before the feet were
  /// held — where edit_path() starts and rejoins the root motion.
  std::vector<Eigen::Vector3d> root_positions;
  std::vector<double> headings;
  /// Per frame: the blend's sway of the heading about its turning (BlendedFrame::heading_offset),
  /// part of `headings`; edit_path() integrates the turning from a frame's heading less it.
  std::vector<double> heading_offsets;
  /// The local mode's fits of the path's frames (MapBlender::locate_path), which edit_path()
  /// reuses where the path around a frame is unchanged; empty in the other modes. 0.1–0.8 KB a
  /// frame (the Bandai sketch and the 10 000-sample benchmark map), against 1.7 KB for the
  /// motion of a 31-joint skeleton.
  PathFits fits;
};

/// How a result's frames outside the data were played, in words for the user (the CLI's and
/// Python's note): "R play the clips' own frames along the path there, E were blended at the
/// nearest edge of the data", either part alone when the other count is 0; empty when no frame
/// was outside (clamped_frames 0).
std::string outside_frames_note(const SynthResult& result);

/// Synthesizes the motion along `path` (see above).
/// @throws ParameterError for bad options or an invalid path (MapPath::validate, path_points),
///         an untimed path with speed 0 on a map without motion, more than kMaxSynthFrames
///         frames, or smoothing whose window would hold more than 5e7 kriging weights;
///         Cancelled if `control` says so (polled between blocks of frames). Reports "blending
///         frames".
SynthResult synthesize(const MapBlender& blender, const MapPath& path,
                       const SynthOptions& options = {}, const Control& control = {});

/// The same, one frame per entry of `weights` (as MapBlender::locate gives them, or any weights
/// over the map's samples: in-betweening blends two consecutive frames of a clip route this way),
/// at options.fps (0: the blender's frame rate); options.speed is not used. Each frame's validity
/// is its weights'.
/// @throws ParameterError for bad options, no frames or more than kMaxSynthFrames, a frame whose
///         weights are empty, not one per sample, not finite or not of increasing samples of the
///         map; as above.
SynthResult synthesize(const MapBlender& blender, std::span<const MapWeights> weights,
                       const SynthOptions& options = {}, const Control& control = {});

}  // namespace motionmap::synth
