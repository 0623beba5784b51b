#pragma once
// Matching the joints of clips from different skeletons: the joint names all clips share (what
// FeatureOptions::joints = JointSelection::Common maps by), and a description of how two joint
// hierarchies differ, for the error that asks for it.
//
//   auto names = motionmap::features::common_joint_names(clips);  // first clip's order
//   std::string why = motionmap::features::hierarchy_difference(clips[0], clips[3]);
//   // "it has 23 joints, 64_08.bvh 31; the first that differs is joint 1: 'Spine' (parent
//   //  'Hips') where 64_08.bvh has 'LHipJoint' (parent 'Hips')"
#include <span>
#include <string>
#include <vector>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::features {

/// The names of the joints that every clip's skeleton has (exact, case-sensitive match), in the
/// order of the first clip's joints. Parents are not compared. Empty when `clips` is.
std::vector<std::string> common_joint_names(std::span<const Clip> clips);

/// How `other`'s joint hierarchy differs from `reference`'s, in words for a message naming
/// `other` first: the joint counts when they differ, then the first joint index whose name or
/// parent's name differs (or, when one hierarchy is the other's prefix, the first joint only one
/// has). Empty when they have the same hierarchy (Skeleton::same_hierarchy). The reference is
/// named by the last part of its path.
std::string hierarchy_difference(const Clip& reference, const Clip& other);

}  // namespace motionmap::features
