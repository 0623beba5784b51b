#pragma once
// Posing by dragging a joint: the map point whose blended pose brings a joint (a hand, a foot, the
// head) closest to a target in space, found only among valid map points, so every pose reached is
// a blend of real data. Other joints can be pinned: each pin adds the weighted squared distance of
// its joint from the position it should keep.
//
//   motionmap::synth::Reacher reacher(blender);                 // each sample's joints, once
//   motionmap::synth::ReachGoal goal;
//   goal.joint = motionmap::synth::find_joint(blender.skeleton(), "LeftHand");
//   goal.target = Eigen::Vector3d(20, 95, 30);                  // in the pose's frame (placement)
//   goal.pins.push_back({right_foot, foot_position, 1.0});
//   auto r = reacher.reach(goal);     // r.point, r.pose (one frame), r.error, r.error_fraction
//   goal.start = r.point;             // a drag: the next step starts from this one's answer
//
// The search: over the 2-D map coordinates p, minimise
//   E(p) = ‖x_joint(q) − target‖² + Σ_pins weight·‖x_pin(q) − position‖² + λ·‖p − q‖²,
// q = MapBlender::locate(p).validity.point (p itself inside the data, else moved to the data's
// edge, the rule every pose of a map follows), x(q) the joints' positions by forward kinematics
// of the pose blended at q and placed with the goal's RootPlacement, λ = (height / reach)² so
// that leaving the data costs more than any pose gains. Starts: the goal's start point (a drag),
// then the map points of the samples whose own pose scores best on E (every sample's joint
// positions are computed once, by the Reacher), taken at least one reach distance apart; from
// each, a Nelder–Mead simplex (derivative-free: the blend weights have kinks at the samples)
// with a hard cap on evaluations, each one a locate + blend + forward kinematics. The answer is
// the best local optimum, except that the one from the goal's start is kept unless another is
// better by more than ReachOptions::keep_margin of the body's height: a drag does not jump
// across the map for a negligible gain. docs/synthesis.md, "Reaching".
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blender.h"

namespace motionmap::synth {

/// A joint held in place while another is dragged.
struct ReachPin {
  int joint = 0;                                       ///< joint index in the blender's skeleton
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< where it should stay (as the target)
  double weight = 1.0;                                 ///< against the target's 1; finite, ≥ 0
};

/// What to reach: a joint, its target and the pins, in the frame of a pose placed with `placement`
/// (MapBlender::pose(weights, placement); the default is MapBlender::pose's frame: the motion root
/// at the floor origin, heading 0).
struct ReachGoal {
  int joint = 0;  ///< joint index in the blender's skeleton
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  std::vector<ReachPin> pins;
  RootPlacement placement;
  /// Where a drag's previous step ended (its ReachResult::point): searched first, and kept unless
  /// another start does clearly better, so consecutive steps move the pose smoothly.
  std::optional<Eigen::Vector2d> start;
};

struct ReachOptions {
  /// Starts from the best-scoring samples (besides the goal's start), in [1, 64].
  int starts = 4;
  /// Pose evaluations (locate + blend + forward kinematics) in all, shared by the starts,
  /// in [8, 1000000]: what bounds a drag step's time.
  int max_evaluations = 200;
  /// The local optimum from the goal's start stays unless another has an objective √E smaller by
  /// more than this fraction of the body's height (Reacher::height()); in [0, 1].
  double keep_margin = 0.01;
  /// A local search ends when its simplex is smaller than this fraction of the map's median step,
  /// in (0, 1].
  double tolerance = 1e-3;

  /// @throws ParameterError naming the option, its value and its range.
  void validate() const;
};

struct ReachResult {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< the map point found, inside the data
  /// The pose there: one frame of the blender's skeleton, placed with the goal's placement.
  Motion pose;
  Eigen::Vector3d reached = Eigen::Vector3d::Zero();  ///< where the joint is in that pose
  double error = 0.0;              ///< ‖reached − target‖, in the skeleton's units
  double error_fraction = 0.0;     ///< error ÷ the body's height (Reacher::height())
  std::vector<double> pin_errors;  ///< per pin: its joint's distance from its position
  double height = 0.0;             ///< the body's height used for error_fraction
  PointValidity validity;          ///< of `point` (never clamped: the point is inside the data)
  int evaluations = 0;             ///< pose evaluations spent
  bool from_start = false;         ///< the answer is the local optimum from the goal's start
};

/// The index of the joint called `name`: the exact name, else the one joint whose name matches
/// ignoring case. @throws ParameterError naming `name`, the names that nearly match it ("LeftHand"
///   for "lefthnd"; "Hand_L" for "LeftHand": left/right and l/r, case, '_' and word order
///   ignored) and every joint of the skeleton.
int find_joint(const Skeleton& skeleton, std::string_view name);

/// Reaching over one blender. Keeps every candidate sample's joint positions (in the heading-0,
/// floor-origin frame of MapBlender::pose), computed in the constructor; reach() then costs
/// O(#candidates) to score the samples plus ReachOptions::max_evaluations pose evaluations at
/// most. The blender must outlive it. Its const members are thread-safe.
class Reacher {
 public:
  /// Most samples scored for starts: above this, every ⌈N / kMaxCandidates⌉-th sample.
  static constexpr int kMaxCandidates = 20000;

  /// Blends each candidate sample's own pose (a blender reading its clips on demand reads them
  /// here, a clip at a time). Reports the stage "reach set-up" and polls `control`.
  /// @throws what MapBlender::pose throws; Cancelled.
  explicit Reacher(const MapBlender& blender, const Control& control = {});
  ~Reacher();
  Reacher(Reacher&&) noexcept;
  Reacher& operator=(Reacher&&) noexcept;

  /// The valid map point whose pose brings goal.joint closest to goal.target, the pins weighed
  /// in (see the top of this file). @throws ParameterError for a joint out of range, a
  ///   non-finite target, pin, placement or start, a negative pin weight, or bad options
  ///   (naming which); Cancelled (polled between starts).
  ReachResult reach(const ReachGoal& goal, const ReachOptions& options = {},
                    const Control& control = {}) const;

  const MapBlender& blender() const;
  /// The body's height: the median, over the candidate samples, of the extent of their pose's
  /// joints and End Sites along the up axis (a map of standing and walking poses: the standing
  /// height; rest poses are no guide, Bandai Namco's lie along X). 1 if that is 0.
  double height() const;
  /// Samples scored for starts (all of them up to kMaxCandidates).
  int num_candidates() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// Reacher(blender).reach(goal, options): for one query; a drag keeps a Reacher.
ReachResult reach(const MapBlender& blender, const ReachGoal& goal,
                  const ReachOptions& options = {}, const Control& control = {});

}  // namespace motionmap::synth
