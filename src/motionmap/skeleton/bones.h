#pragma once
// What a drawing of a skeleton needs, as plain data: which joints move by their own translation
// (and so hang from no bone), the bone segments of a pose, the joints of the body, each joint's
// body side and its colour. Studio's 3-D view and `motionmap keyposes`' contact sheet draw with
// these, so a skeleton looks the same in both.
#include <vector>

#include <Eigen/Core>

#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap {

/// One bone: from a joint to a child joint or to one of its end sites (world coordinates).
struct BoneSegment {
  Eigen::Vector3d from;
  Eigen::Vector3d to;
  int joint = -1;  ///< the joint whose side colours it: the child, or the end site's joint
};

/// Joints that move by their own translation channels: j (not a root) whose local translation
/// somewhere in `motion` is more than 0.25·|offset| + 1 % of the rest pose's extent away from its
/// rest offset (Bandai Namco's Hips under a static joint_Root, translated across the floor). Such
/// a joint is not where its parent's offset puts it, so it gets no bone from its parent. Joints
/// whose translation channels only repeat their offsets (files with 6 channels on every joint)
/// are not detached. One entry per joint; all false for a motion that does not fit.
std::vector<bool> detached_joints(const Skeleton& skeleton, const Motion& motion);

/// Every parent→child and joint→end-site segment of `pose` (a WorldPose of `skeleton`), skipping
/// zero-length ones (CMU's dummy joints) and the parent→child bones of `detached` joints (empty:
/// none detached).
std::vector<BoneSegment> bone_segments(const Skeleton& skeleton, const WorldPose& pose,
                                       const std::vector<bool>& detached = {});

/// Joints drawn and framed: every joint with at least one bone (to its parent, a child or an end
/// site) given `detached`, or every joint of a one-joint skeleton. A static root whose only child
/// is detached (joint_Root at the origin under a walking character) is not part of the body.
std::vector<bool> body_joints(const Skeleton& skeleton, const std::vector<bool>& detached);

/// Body side of a joint, read from its name.
enum class JointSide { Center, Left, Right };

/// Sides of every joint. A name is Left when it starts with "Left"/"left" or "L_", "L.", "L-",
/// "l_", …, or ends with "_L", ".L", "-L", " L", "_l", …, or contains "Left"/"left"; or when it is
/// "L"/"l" followed by the rest of a name that the skeleton also has with "R"/"r" in its place
/// (CMU's LHipJoint beside RHipJoint, ASF's lfemur beside rfemur, but not lowerback). Right
/// likewise. A joint with no mark takes its parent's side (fingers under a hand); roots and the
/// spine are Center.
std::vector<JointSide> joint_sides(const Skeleton& skeleton);

/// Joint colours (RGB in [0, 1]): left blue, right red, centre ochre (bones: the same hue,
/// lighter).
Eigen::Vector3f side_color(JointSide side, bool bone = false);

/// Diagonal of the bounding box of the pose's joints and end sites (1 when degenerate), the scale
/// a view sizes bones, grid and camera distance by.
double pose_extent(const WorldPose& pose);

}  // namespace motionmap
