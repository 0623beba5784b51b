#pragma once
// The data model: a Skeleton (joints in parent-before-child order) and a Motion (frames-major
// arrays of local joint transforms), bundled with their provenance in a Clip; and check_motion(),
// the one check every public function taking a skeleton and motion runs first.
//
//   motionmap::Clip clip = motionmap::io::load_clip("64_08.bvh");
//   const auto& skel = clip.skeleton;              // #joints, parents, offsets, channels
//   auto pose = clip.motion.pose(10);              // views of frame 10
//   Eigen::Quaterniond q = pose.rotations[3];       // local rotation of joint 3
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "motionmap/core/rotation.h"

namespace motionmap {

/// One BVH channel. Position channels translate, rotation channels rotate about a coordinate axis.
enum class ChannelType : std::uint8_t {
  Xposition,
  Yposition,
  Zposition,
  Xrotation,
  Yrotation,
  Zrotation
};

/// "Xposition", …, "Zrotation" as written in BVH files.
std::string_view channel_name(ChannelType c);
/// Parses a BVH channel name (exact, case-sensitive as every exporter writes it).
std::optional<ChannelType> parse_channel_name(std::string_view name);
inline bool is_rotation(ChannelType c) {
  return c >= ChannelType::Xrotation;
}
/// The coordinate axis a channel acts along (position) or about (rotation).
inline Axis channel_axis(ChannelType c) {
  return static_cast<Axis>(static_cast<int>(c) % 3);
}

struct Joint {
  std::string name;
  int parent = -1;  ///< index into Skeleton::joints, −1 for a root
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< rest translation from the parent
  std::vector<ChannelType> channels;                 ///< channel layout exactly as in the file
  std::vector<Eigen::Vector3d> end_sites;            ///< offsets of the joint's End Site blocks
};

/// Joints in an order where every parent comes before its children. Several roots are allowed.
struct Skeleton {
  std::vector<Joint> joints;

  int num_joints() const { return static_cast<int>(joints.size()); }
  /// Sum of every joint's channel count.
  int num_channels() const;
  /// Total number of end sites (over all joints).
  int num_end_sites() const;
  /// Indices of the joints without parent.
  std::vector<int> roots() const;
  /// Index of the joint called `name`, or −1.
  int find(std::string_view name) const;
  /// True when both have the same joint names and parents in the same order, and each joint the
  /// same number of End Sites (offsets may differ): the layouts of features and point clouds.
  bool same_hierarchy(const Skeleton& other) const;
  /// Checks parents come before children and names are unique.
  /// @throws Error naming the first offending joint.
  void validate() const;
};

/// A view of one frame of a Motion: #joints local rotations and #joints local translations.
struct PoseView {
  std::span<const Eigen::Quaterniond> rotations;
  std::span<const Eigen::Vector3d> translations;
};

/// Per-frame local joint transforms, frames-major: entry (f, j) is at index f·num_joints + j.
/// A joint's local translation is its rest offset, except for the components the file animates
/// (position channels, usually only on the root), which replace the offset's.
struct Motion {
  double frame_time = 1.0 / 120.0;  ///< seconds between frames
  int num_frames = 0;
  int num_joints = 0;
  std::vector<Eigen::Quaterniond> rotations;  ///< #frames·#joints unit quaternions
  std::vector<Eigen::Vector3d> translations;  ///< #frames·#joints local translations

  /// Allocates #frames·#joints identity rotations and zero translations.
  void resize(int frames, int joints);
  Eigen::Quaterniond& rotation(int frame, int joint) { return rotations[index(frame, joint)]; }
  const Eigen::Quaterniond& rotation(int frame, int joint) const {
    return rotations[index(frame, joint)];
  }
  Eigen::Vector3d& translation(int frame, int joint) { return translations[index(frame, joint)]; }
  const Eigen::Vector3d& translation(int frame, int joint) const {
    return translations[index(frame, joint)];
  }
  PoseView pose(int frame) const;
  /// Frames first … end − 1 as a motion of their own (same frame time).
  /// @throws ParameterError unless 0 ≤ first ≤ end ≤ num_frames.
  Motion frames(int first, int end) const;
  double fps() const { return frame_time > 0 ? 1.0 / frame_time : 0.0; }
  double duration() const { return num_frames * frame_time; }

 private:
  std::size_t index(int frame, int joint) const {
    return static_cast<std::size_t>(frame) * static_cast<std::size_t>(num_joints) +
           static_cast<std::size_t>(joint);
  }
};

/// The words of a joint name, lower case, for matching names across exporters: the part after
/// any `prefix:` or `prefix|` (Mixamo's `mixamorig:`), cut at every character that is not a
/// letter or digit, at a change between letters and digits, and at camel case ("LeftHand" and
/// "LHand" → left/l, hand; "Hand_L" → hand, l). Feet (skeleton/contacts.h) and `reach --joint`
/// (synth/reach.h) read names with it.
std::vector<std::string> joint_name_words(std::string_view name);

/// Whole frames in `seconds` at `fps`: at least (rounded up) or at most (rounded down), within
/// kFrameCountSlack of the count: frame times are written to a few digits (BVH's 0.0083333 s is
/// 120.0005 fps, at which 0.05 s is 6 frames, not 7; and ⌈fps/60⌉ is 2, not 3). Counts beyond an
/// int's range are its nearest end.
int frames_at_least(double seconds, double fps);
int frames_at_most(double seconds, double fps);
/// The relative slack of frames_at_least() and frames_at_most().
inline constexpr double kFrameCountSlack = 1e-4;

/// The joint that carries the body's motion: the first root, or — where exporters put a static
/// joint above the hips (Bandai Namco's joint_Root) — the first joint down the chain of single
/// children whose local transform changes during `motion`. Heading and floor position are read
/// from it. Checks sizes only (see check_motion(), MotionCheck::Sizes).
/// @throws ParameterError if `motion` does not fit `skeleton`.
int motion_root(const Skeleton& skeleton, const Motion& motion);

/// A loaded clip: what it is called, its skeleton and motion, and the loader's warnings.
struct Clip {
  std::string path;
  Skeleton skeleton;
  Motion motion;
  std::vector<std::string>
      warnings;  ///< non-fatal findings, formatted like "path:line: warning: …"
  /// SHA-256 of the file bytes the clip was parsed from (an .amc's, not its .asf's), 64 hex
  /// digits, when loaded with io::LoadOptions::sha256 (what a map file records); else empty.
  std::string sha256;
};

// ---- Checking a skeleton and motion --------------------------------------------------------
// The one check of a skeleton and its motion, called at every public entry point that takes
// them, so that a Motion whose public fields were set inconsistently ends in a clear
// motionmap::Error instead of an out-of-bounds read or NaN poses.
//
//   motionmap::check_clip(clip);  // throws naming clip.path, the first bad frame and joint
//   motionmap::check_motion(skeleton, motion, "forward_kinematics", motionmap::MotionCheck::Sizes);
//
// What is checked, in this order (the first problem found is reported):
//  1. the skeleton: at least one joint, every parent −1 (a root) or the index of an earlier joint;
//  2. the motion's shape: #frames ≥ 0, #joints equal to the skeleton's, rotations and
//     translations each holding #frames·#joints entries, a frame time that is finite and > 0;
//  3. with MotionCheck::Values only (one pass over the data): finite joint offsets and End Sites,
//     then, frame by frame, finite rotations of norm > kMinRotationNorm and finite translations.
// Sizes and structure problems throw ParameterError, non-finite or zero values NumericalError.

/// How much check_motion() looks at.
enum class MotionCheck {
  /// Skeleton structure, array sizes and frame time: O(#joints), for per-frame entry points.
  Sizes,
  /// Sizes, then every offset, End Site, rotation and translation: one pass over the motion.
  Values,
};

/// Rotations shorter than this are rejected as zero (they cannot be normalised into a rotation).
inline constexpr double kMinRotationNorm = 1e-6;

/// Checks that `skeleton` is well-formed: at least one joint, parents before children; with
/// MotionCheck::Values also finite offsets and End Sites. `who` starts every message (a clip
/// path or the name of the function checking).
/// @throws ParameterError "who: joint 'Spine' (index 1) has parent index 5; expected -1 (a root)
///         or the index of an earlier joint …" or "who: the skeleton has no joint";
///         NumericalError "who: joint 'Spine' has a non-finite offset (nan, 0, 1)" (Values only).
void check_skeleton(const Skeleton& skeleton, std::string_view who,
                    MotionCheck depth = MotionCheck::Values);

/// Checks `motion` alone (no skeleton): #frames and #joints ≥ 0, rotations and translations of
/// #frames·#joints entries each, frame time finite and > 0; with MotionCheck::Values also finite,
/// non-zero rotations and finite translations (joints named by index).
/// @throws ParameterError (sizes, frame time) or NumericalError (values), messages as
///         check_motion(skeleton, motion, …).
void check_motion(const Motion& motion, std::string_view who,
                  MotionCheck depth = MotionCheck::Values);

/// Checks that `motion` is a valid motion of `skeleton`: check_skeleton(), then motion.num_joints
/// equal to skeleton.num_joints(), then check_motion(motion), joints named by their names.
/// `who` starts every message: a clip path, or the name of the public function checking.
/// @throws ParameterError for structure and size problems, e.g.
///         "who: the motion (3 frames of 4 joints, 12 rotations, 12 translations) does not fit
///         the skeleton of 5 joints", "who: frame time 0.000000 is not a finite number > 0";
///         NumericalError for values (MotionCheck::Values only), e.g. "who: frame 7, joint
///         'LeftThumb' holds a NaN or infinite value (rotation w x y z = nan 0 0 1; expected
///         finite numbers)" or "… has a rotation of norm 0 (…; expected a unit quaternion)".
void check_motion(const Skeleton& skeleton, const Motion& motion, std::string_view who,
                  MotionCheck depth = MotionCheck::Values);

/// check_motion(clip.skeleton, clip.motion, …) with messages starting with clip.path ("clip"
/// when it is empty). @throws as check_motion().
void check_clip(const Clip& clip, MotionCheck depth = MotionCheck::Values);

}  // namespace motionmap
