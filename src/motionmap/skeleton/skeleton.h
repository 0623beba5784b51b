#pragma once
// The data model: a Skeleton (joints in parent-before-child order) and a Motion (frames-major
// arrays of local joint transforms), bundled with their provenance in a Clip.
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
  /// True when both have the same joint names and parents in the same order (offsets may differ).
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
  double fps() const { return frame_time > 0 ? 1.0 / frame_time : 0.0; }
  double duration() const { return num_frames * frame_time; }

 private:
  std::size_t index(int frame, int joint) const {
    return static_cast<std::size_t>(frame) * static_cast<std::size_t>(num_joints) +
           static_cast<std::size_t>(joint);
  }
};

/// The joint that carries the body's motion: the first root, or — where exporters put a static
/// joint above the hips (Bandai Namco's joint_Root) — the first joint down the chain of single
/// children whose local transform changes during `motion`. Heading and floor position are read
/// from it.
int motion_root(const Skeleton& skeleton, const Motion& motion);

/// A loaded clip: what it is called, its skeleton and motion, and the loader's warnings.
struct Clip {
  std::string path;
  Skeleton skeleton;
  Motion motion;
  std::vector<std::string>
      warnings;  ///< non-fatal findings, formatted like "path:line: warning: …"
};

}  // namespace motionmap
