#pragma once
// Root motion of a sample frame, split the way the blender blends it: the motion root's heading
// (yaw about the up axis) and floor position are not blended but integrated (synthesize()), from
// the heading-local floor velocity and the yaw rate; its height along the up axis and its tilt
// (the rotation with the heading removed) are blended like the other joints.
//
// The heading is split in two: its turning, the clip's heading averaged over ±kTurnSeconds, whose
// rate (yaw_rate) is integrated; and the sway about it (heading_offset), blended like a pose. A
// walk's pelvis swings a few degrees either way with each step; integrated, the swings of blended
// sources whose weights rise and fall with the steps do not cancel, and a sketch along a straight
// walk turned 21° (bench/traced_walks.py). A single sample still retraces its clip exactly: the
// turning plus the sway is its heading.
//
//   const RootSample r = root_sample(clip.motion, f, blender_root, Axis::Y);
//   // r.tilt: no heading; r.velocity: units/s in the heading frame (up component 0)
#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::synth::detail {

/// One frame's root motion (see the top of the file).
struct RootSample {
  /// The root's rotation with its heading removed (heading_angle(tilt, up) = 0).
  Eigen::Quaterniond tilt = Eigen::Quaterniond::Identity();
  /// The root's translation along the up axis.
  double height = 0.0;
  /// Floor velocity in the frame's own heading frame, units per second (up component 0).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// The turning's change per second about the up axis, radians: the heading's change (wrapped
  /// to (−π, π]) less the sway's.
  double yaw_rate = 0.0;
  /// The sway: the heading less the clip's heading averaged over ±kTurnSeconds, radians.
  double heading_offset = 0.0;
};

/// Half the window over which a clip's heading is averaged into its turning (RootSample): a
/// whole stride of a walk (two steps, about a second) is averaged out.
inline constexpr double kTurnSeconds = 0.5;
/// Frames read either side of a sample to average its clip's heading (RootSample).
inline constexpr int kTurnSamples = 8;

/// `q` with its heading about `up` removed: yaw(−heading_angle(q, up))·q, normalised.
Eigen::Quaterniond remove_heading(const Eigen::Quaterniond& q, Axis up);

/// Root motion of frame f of `motion` at joint `root`, its `ancestors` folded in (root_transform
/// in blend_state.h). Velocity and yaw rate are forward differences to the next frame (the last
/// frame repeats its predecessor's; a one-frame motion stands still), so integrating a clip's own
/// samples (and adding the sway) retraces the clip exactly. The heading's average over the
/// window (cut to the clip) is read at 2·kTurnSamples + 1 frames evenly spread over it.
RootSample root_sample(const Motion& motion, int frame, int root, Axis up,
                       std::span<const int> ancestors = {});

/// Where a blended frame's feet stand, for the root to follow: per foot (left, right), the
/// ankle's position relative to the motion root with the root at the floor origin facing heading
/// 0 (as MapBlender blends a frame), and how planted the foot is, in [0, 1].
struct FeetFrame {
  std::array<Eigen::Vector3d, 2> ankle{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<double, 2> planted{0.0, 0.0};
  /// How much farther than the blended step a foot's step may go before root_step() takes it
  /// for a jump of the blend rather than a stride: its leg's length × the frame time (a leg per
  /// second, the contacts' speed threshold).
  std::array<double, 2> slack{0.0, 0.0};
};

/// The contact share (MapBlender::contact_share: the blend weight on samples whose foot is on the
/// floor) from which a foot starts to lead the root. The clean-up holds a foot from half a share
/// on; a foot half the blend plants is as much a foot in the air, and one that led the root
/// there would drag the body with a swing (on the Bandai walks of tests/synth, leading from half
/// a share made the root follow the blend's jumps and moved the legs of a path edit 2° from a
/// full re-synthesis).
inline constexpr double kFollowShare = 0.7;

/// How planted a blended foot is from its contact share: 0 up to kFollowShare, rising linearly
/// to 1 at a whole share.
double planted_weight(double share);

/// The FeetFrame of every frame of `motion`, blended frames whose root stands at the floor origin
/// facing heading 0 (not yet integrated), with one contact share per frame.
std::vector<FeetFrame> feet_frames(const Skeleton& skeleton, const Motion& motion, int root,
                                   const Feet& feet, std::span<const std::array<double, 2>> shares);

/// The root's floor step from a frame to the next: the blended one, `blended` (world units, the
/// heading-local velocity turned by `yaw` and times the frame time), where no foot is planted;
/// where feet are planted in both frames (the lesser of the two frames' weights), the step that
/// keeps them where they stand — the ankle at `now` turned by `yaw` and at `next` by `next_yaw`
/// land on the same floor point —, averaged over the feet by weight and mixed with the blended
/// step by the feet's total weight (at most 1). A foot whose step differs from the blended one
/// by more than the blended step's length plus its slack is left out: its ankle jumped with the
/// blend (a pose that changes at once), and the root must not jump with it.
Eigen::Vector3d root_step(const Eigen::Vector3d& blended, const Eigen::Quaterniond& yaw,
                          const Eigen::Quaterniond& next_yaw, const FeetFrame& now,
                          const FeetFrame& next, Axis up);

/// The root's floor position and heading, integrated (synthesize(), edit_path()).
struct RootState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double heading = 0.0;
};

/// Integrates the root from `start` over velocity.size() frames: frame i stands at the state
/// reached so far, facing the state's heading (the turning) plus its sway `heading_offset[i]`
/// (written to positions[i] and headings[i]), then steps by its heading-local velocity and yaw
/// rate times dt — led by its planted feet (root_step) where `standing` has frames i and i + 1
/// (empty: never). `heading_offset` has an entry for each frame of `velocity` and of `standing`.
/// Returns the state after the last frame (its heading the turning, no sway).
RootState integrate_root(RootState start, std::span<const Eigen::Vector3d> velocity,
                         std::span<const double> yaw_rate, std::span<const double> heading_offset,
                         double dt, std::span<const FeetFrame> standing, Axis up,
                         std::span<Eigen::Vector3d> positions, std::span<double> headings);

}  // namespace motionmap::synth::detail
