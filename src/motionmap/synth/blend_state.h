#pragma once
// The arithmetic of a blend on its own: one sample's state as a blend reads it (sample_state) and
// the weighted blend of such states into one frame (blend_states). synth::MapBlender blends with
// them, from its precomputed tables or from clips read on demand, and so does
// mapfile::SavedMap::pose_at without a blender: the same states and weights blend to the same
// frame, bit for bit, whoever blends them.
//
//   using namespace motionmap::synth;
//   const SampleState a = sample_state(clip.motion, 10, root, Axis::Y, moving);
//   const SampleState b = sample_state(clip.motion, 11, root, Axis::Y, moving);
//   const std::array<SampleStateView, 2> states = {a.view(), b.view()};
//   const std::array<double, 2> weights = {0.25, 0.75};
//   const BlendedFrame f = blend_states(states, weights, fixed, moving, root, Axis::Y);
//
// `root` is the motion root and `moving` the joints other than it whose translations the blend
// averages (ClipsSummary in blender.h: the map's, so that every blend over a map treats the same
// joints alike); `fixed` the #joints translations the other joints keep (a blender's: its first
// sample's). `ancestors` are the motion root's ancestors (root_ancestors()), folded into it: a
// library whose clips carry their travel in different joints (Bandai Namco's runs in a joint_Root
// above the hips, its walks in the hips) blends the same world transform of the body's root, and
// the blend leaves the ancestors at rest (identity rotation, zero translation).
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::synth {

/// The motion root's transform with its ancestors' folded in: with A₀ … A_k the ancestors from
/// the top and R the root, rotation q_A₀·…·q_A_k·q_R and translation t_A₀ + q_A₀(t_A₁ + …
/// q_A_k(t_R)) — the root's world transform below the ancestors' parent. No ancestors: the root's
/// own local transform.
struct RootTransform {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};
/// @throws ParameterError if `frame`, `root` or an ancestor is out of range.
RootTransform root_transform(const Motion& motion, int frame, int root,
                             std::span<const int> ancestors);

/// The ancestors of joint `root` in `skeleton`, from the top down (empty for a root joint).
/// @throws ParameterError if `root` is out of range.
std::vector<int> root_ancestors(const Skeleton& skeleton, int root);

/// Frame `frame` of `motion` with `ancestors` folded into `root` (root_transform) and left at
/// rest: what a blend of that frame alone gives, placed where the frame stands.
void fold_root(Motion& motion, int frame, int root, std::span<const int> ancestors);

/// One blended frame before root motion is applied.
struct BlendedFrame {
  /// #joints local rotations; the motion root's is its tilt (rotation with the heading removed).
  std::vector<Eigen::Quaterniond> rotations;
  /// #joints local translations; the motion root's has floor components 0 and the blended height
  /// along the up axis.
  std::vector<Eigen::Vector3d> translations;
  /// Blended root floor velocity in the heading frame (units per second, up component 0).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// Blended turning: the change of the heading averaged over a stride, radians per second about
  /// the up axis (synth/detail/root_motion.h).
  double yaw_rate = 0.0;
  double heading_offset = 0.0;  ///< blended sway of the heading about the turning, radians
};

/// A sample's state where it is kept (a SampleState, or a blender's tables), as blend_states()
/// reads it: `rotations` points at #joints rotations, `translations` at the moving joints'.
struct SampleStateView {
  const Eigen::Quaterniond* rotations = nullptr;
  const Eigen::Vector3d* translations = nullptr;
  double height = 0.0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double yaw_rate = 0.0;
  double heading_offset = 0.0;
};

/// One sample (a frame of a clip) as a blend reads it.
struct SampleState {
  /// #joints local rotations, normalised; the motion root's is its tilt (heading removed).
  std::vector<Eigen::Quaterniond> rotations;
  /// The moving joints' local translations, in the order of `moving`.
  std::vector<Eigen::Vector3d> translations;
  double height = 0.0;  ///< the motion root's translation along the up axis
  /// The motion root's floor velocity in the frame's heading frame, units per second (a forward
  /// difference to the next frame; see synth/detail/root_motion.h).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// The turning's change (the clip's heading averaged over a stride), radians per second about
  /// the up axis (synth/detail/root_motion.h).
  double yaw_rate = 0.0;
  double heading_offset = 0.0;  ///< the heading's sway about the turning, radians

  /// Whether every value is finite.
  bool finite() const;
  SampleStateView view() const {
    return {rotations.data(), translations.data(), height, velocity, yaw_rate, heading_offset};
  }
};

/// The state of frame `frame` of `motion` for a blend whose motion root is `root` and whose
/// averaged translations are those of the joints `moving`.
/// @throws ParameterError if `frame`, `root` or a joint of `moving` is out of range.
/// The root's `ancestors` are folded into it (root_transform), their rotations identity.
SampleState sample_state(const Motion& motion, int frame, int root, Axis up,
                         std::span<const int> moving, std::span<const int> ancestors = {});
/// The same, written where a caller keeps it: #joints rotations at `rotations`, moving.size()
/// translations at `translations`. @throws as above.
void sample_state(const Motion& motion, int frame, int root, Axis up, std::span<const int> moving,
                  std::span<const int> ancestors, Eigen::Quaterniond* rotations,
                  Eigen::Vector3d* translations, double& height, Eigen::Vector3d& velocity,
                  double& yaw_rate, double& heading_offset);

/// sample_state() of frame `frame` of a clip a blend has read (a blender from its ClipSource,
/// SavedMap::pose_at), checked before it is blended.
/// @throws NumericalError naming the clip and frame when a value is not finite; as above.
SampleState clip_sample_state(const Clip& clip, int frame, int root, Axis up,
                              std::span<const int> moving, std::span<const int> ancestors = {});

/// Checks the motion root and moving joints a blend is given (a clips' summary, a map file's
/// blend record) against the first clip, `clip_path`, of `joints` joints: the root one of them,
/// the moving joints increasing, others than the root. `named_by` begins the messages, e.g.
/// "map: the clips' summary". @throws ParameterError.
void check_blend_joints(int motion_root, std::span<const int> moving, int joints,
                        const std::string& named_by, const std::string& clip_path);

/// The blend of `states` with `weights` (one each, finite, any sign, summing to about 1), with
/// #joints = fixed_translations.size() (each state holding #joints rotations and moving.size()
/// translations):
///  - rotations: per joint, core's weighted_average, aligned to the largest-weight state's (the
///    first of equal ones); then any trace of heading left in the motion root's blended tilt is
///    removed, so the frame faces heading 0 (a no-op at a sample);
///  - translations: the moving joints' weighted sums over the weights' sum; every other joint's
///    is its entry of `fixed_translations`, the motion root's 0 on the floor and the blended
///    height along `up`;
///  - velocity, yaw rate and heading offset: weighted sums over the weights' sum;
///  - the motion root's `ancestors` (folded into the states' root) at rest: identity rotation,
///    zero translation.
/// The states are summed in the order given: the same states and weights in the same order give
/// the same frame, bit for bit.
/// @throws ParameterError for no states, as many weights as states, a weight that is not finite,
///   weights summing to about 0, or `motion_root` or a joint of `moving` out of range.
BlendedFrame blend_states(std::span<const SampleStateView> states, std::span<const double> weights,
                          std::span<const Eigen::Vector3d> fixed_translations,
                          std::span<const int> moving, int motion_root, Axis up,
                          std::span<const int> ancestors = {});

}  // namespace motionmap::synth
