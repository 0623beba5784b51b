// check_skeleton, check_motion and check_clip (declared in skeleton.h).
#include "motionmap/skeleton/skeleton.h"

#include <cmath>
#include <cstddef>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"

namespace motionmap {

namespace {

std::string prefix(std::string_view who) {
  return std::string(who) + ": ";
}

std::string joint_label(const Skeleton* skeleton, int j) {
  if (skeleton) return "joint '" + skeleton->joints[static_cast<std::size_t>(j)].name + "'";
  return "joint " + std::to_string(j);
}

std::string vector_text(const Eigen::Vector3d& v) {
  return "(" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) +
         ")";
}

// "(3 frames of 4 joints, 12 rotations, 12 translations)": everything a size message needs.
std::string shape_text(const Motion& motion) {
  return "(" + std::to_string(motion.num_frames) + " frames of " +
         std::to_string(motion.num_joints) + " joints, " + std::to_string(motion.rotations.size()) +
         " rotations, " + std::to_string(motion.translations.size()) + " translations)";
}

// Counts, array sizes and frame time of `motion`.
void check_shape(const Motion& motion, std::string_view who) {
  if (motion.num_frames < 0 || motion.num_joints < 0) {
    throw ParameterError(prefix(who) + "the motion " + shape_text(motion) +
                         " has a negative frame or joint count; expected counts ≥ 0");
  }
  const std::size_t entries =
      static_cast<std::size_t>(motion.num_frames) * static_cast<std::size_t>(motion.num_joints);
  if (motion.rotations.size() != entries || motion.translations.size() != entries) {
    throw ParameterError(prefix(who) + "the motion " + shape_text(motion) +
                         " is inconsistent: #frames·#joints = " + std::to_string(entries) +
                         ", so " + std::to_string(entries) + " rotations and " +
                         std::to_string(entries) + " translations were expected");
  }
  if (!(motion.frame_time > 0.0) || !std::isfinite(motion.frame_time)) {
    throw ParameterError(prefix(who) + "frame time " + std::to_string(motion.frame_time) +
                         " is not a finite number > 0");
  }
}

// Every rotation and translation, frame by frame (the first bad one in file order is reported).
void check_values(const Motion& motion, const Skeleton* skeleton, std::string_view who) {
  const auto joints = static_cast<std::size_t>(motion.num_joints);
  const std::size_t entries = motion.rotations.size();
  for (std::size_t k = 0; k < entries; ++k) {
    const Eigen::Quaterniond& q = motion.rotations[k];
    const Eigen::Vector3d& t = motion.translations[k];
    const bool q_finite = q.coeffs().allFinite();
    if (q_finite && t.allFinite() && q.squaredNorm() > kMinRotationNorm * kMinRotationNorm) {
      continue;
    }
    const auto frame = static_cast<int>(k / joints);
    const auto joint = static_cast<int>(k % joints);
    const std::string where =
        prefix(who) + "frame " + std::to_string(frame) + ", " + joint_label(skeleton, joint);
    const std::string rotation = "rotation w x y z = " + format_number(q.w()) + " " +
                                 format_number(q.x()) + " " + format_number(q.y()) + " " +
                                 format_number(q.z());
    if (!q_finite) {
      throw NumericalError(where + " holds a NaN or infinite value (" + rotation +
                           "; expected finite numbers)");
    }
    if (!t.allFinite()) {
      throw NumericalError(where + " holds a NaN or infinite value (translation " + vector_text(t) +
                           "; expected finite numbers)");
    }
    throw NumericalError(where + " has a rotation of norm " + format_number(q.norm(), 3) + " (" +
                         rotation + "; expected a unit quaternion)");
  }
}

// At least one joint, parents before children: what forward kinematics relies on.
void check_hierarchy(const Skeleton& skeleton, std::string_view who) {
  const int n = skeleton.num_joints();
  if (n == 0) throw ParameterError(prefix(who) + "the skeleton has no joint");
  for (int j = 0; j < n; ++j) {
    const Joint& joint = skeleton.joints[static_cast<std::size_t>(j)];
    if (joint.parent < -1 || joint.parent >= j) {
      throw ParameterError(prefix(who) + "joint '" + joint.name + "' (index " + std::to_string(j) +
                           ") has parent index " + std::to_string(joint.parent) +
                           "; expected -1 (a root) or the index of an earlier joint (parents "
                           "must come before their children)");
    }
  }
}

// Finite joint offsets and End Sites.
void check_offsets(const Skeleton& skeleton, std::string_view who) {
  for (const Joint& joint : skeleton.joints) {
    if (!joint.offset.allFinite()) {
      throw NumericalError(prefix(who) + "joint '" + joint.name + "' has a non-finite offset " +
                           vector_text(joint.offset));
    }
    for (std::size_t e = 0; e < joint.end_sites.size(); ++e) {
      if (!joint.end_sites[e].allFinite()) {
        throw NumericalError(prefix(who) + "End Site " + std::to_string(e) + " of joint '" +
                             joint.name + "' has a non-finite offset " +
                             vector_text(joint.end_sites[e]));
      }
    }
  }
}

}  // namespace

void check_skeleton(const Skeleton& skeleton, std::string_view who, MotionCheck depth) {
  check_hierarchy(skeleton, who);
  if (depth == MotionCheck::Values) check_offsets(skeleton, who);
}

void check_motion(const Motion& motion, std::string_view who, MotionCheck depth) {
  check_shape(motion, who);
  if (depth == MotionCheck::Values) check_values(motion, nullptr, who);
}

void check_motion(const Skeleton& skeleton, const Motion& motion, std::string_view who,
                  MotionCheck depth) {
  // Structure before values: sizes decide whether the values can be read at all.
  check_hierarchy(skeleton, who);
  if (motion.num_joints != skeleton.num_joints()) {
    throw ParameterError(prefix(who) + "the motion " + shape_text(motion) +
                         " does not fit the skeleton of " + std::to_string(skeleton.num_joints()) +
                         " joints");
  }
  check_shape(motion, who);
  if (depth == MotionCheck::Sizes) return;
  check_offsets(skeleton, who);
  check_values(motion, &skeleton, who);
}

void check_clip(const Clip& clip, MotionCheck depth) {
  check_motion(clip.skeleton, clip.motion, clip.path.empty() ? "clip" : clip.path, depth);
}

}  // namespace motionmap
