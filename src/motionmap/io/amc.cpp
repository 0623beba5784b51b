#include "motionmap/io/amc.h"

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/text_cursor.h"
#include "motionmap/io/detail/acclaim.h"

namespace motionmap::io {

namespace {

using Mark = TextCursor::Mark;

// AMC is line-oriented, with `#` comments (whole lines or line tails).
constexpr char kComment = '#';

// Acclaim composes Euler triples "first listed, first applied" (column vectors): angles (a, b, c)
// about axes (i, j, k) give R = Rk(c)·Rj(b)·Ri(a). Measured against CMU's BVH conversion.
Eigen::Quaterniond acclaim_euler(const std::array<Axis, 3>& order, const Eigen::Vector3d& angles) {
  const std::array<Axis, 3> reversed{order[2], order[1], order[0]};
  const std::array<double, 3> values{angles[2], angles[1], angles[0]};
  return euler_to_quat(reversed, values);
}

// Angles of an `axis`/`orientation` triple are indexed by axis (x y z), whatever the order.
Eigen::Vector3d axis_angles_in_order(const std::array<Axis, 3>& order, const Eigen::Vector3d& xyz) {
  return {xyz[static_cast<int>(order[0])], xyz[static_cast<int>(order[1])],
          xyz[static_cast<int>(order[2])]};
}

// Per-joint conversion data, joint 0 = root, joint b+1 = bone b.
struct JointDofs {
  std::vector<Dof> dofs;
  Eigen::Quaterniond c = Eigen::Quaterniond::Identity();  // the `axis` (root: `orientation`)
  Eigen::Matrix3d c_matrix = Eigen::Matrix3d::Identity();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // for `l`
  std::vector<int> children;                            // joints moved by `l`
};

}  // namespace

Motion parse_amc(std::string_view text, const AsfSkeleton& asf, double fps,
                 const std::string& path) {
  if (!(fps > 0.0) || !std::isfinite(fps)) {
    throw ParameterError("AMC frame rate must be positive and finite, got " + std::to_string(fps));
  }
  const Skeleton skel = asf_to_skeleton(asf);
  const int joints = skel.num_joints();

  std::vector<JointDofs> info(joints);
  std::unordered_map<std::string_view, int> index;
  info[0].dofs = asf.root_order;
  index.emplace("root", 0);
  for (int j = 1; j < joints; ++j) {
    const AsfBone& bone = asf.bones[j - 1];
    info[j].dofs = bone.dofs;
    info[j].direction = bone.direction;
    index.emplace(bone.name, j);
    if (bone.parent >= 0) info[bone.parent + 1].children.push_back(j);
  }
  const double asf_angle = asf.angles_in_degrees ? deg_to_rad(1.0) : 1.0;
  const auto rest_rotation = [&](const std::array<Axis, 3>& order, const Eigen::Vector3d& xyz) {
    return acclaim_euler(order, axis_angles_in_order(order, xyz) * asf_angle);
  };
  info[0].c = rest_rotation(asf.root_axis_order, asf.root_orientation);
  for (int j = 1; j < joints; ++j) {
    info[j].c = rest_rotation(asf.bones[j - 1].axis_order, asf.bones[j - 1].axis_angles);
  }
  for (auto& d : info) d.c_matrix = d.c.toRotationMatrix();

  Motion motion;
  motion.frame_time = 1.0 / fps;
  motion.num_joints = joints;
  std::vector<Eigen::Vector3d> rest(joints);
  for (int j = 0; j < joints; ++j) rest[j] = skel.joints[j].offset;

  TextCursor c(text, path);
  double amc_angle = asf_angle;
  bool unit_declared = false;
  long long frame_number = -1;
  std::vector<int> seen_in_frame(joints, -1);
  std::vector<double> values;
  std::vector<Axis> rot_axes;
  std::vector<double> rot_angles;

  while (c.skip_to_content(kComment)) {
    const Mark at = c.mark_next();
    const std::string_view token = c.peek_token();
    if (token.front() == ':') {
      if (motion.num_frames > 0) c.fail_expected("a frame number or a bone line");
      if (ascii_iequals(token, ":FULLY-SPECIFIED")) {
        // Every frame lists every bone; nothing to do (absent bones would keep their rest pose).
      } else if (ascii_iequals(token, ":DEGREES") || ascii_iequals(token, ":RADIANS")) {
        const double unit = ascii_iequals(token, ":DEGREES") ? deg_to_rad(1.0) : 1.0;
        if (unit_declared && unit != amc_angle) c.fail_expected_at(at, "one angle unit");
        amc_angle = unit;
        unit_declared = true;
      } else {
        c.fail_expected("':FULLY-SPECIFIED', ':DEGREES' or ':RADIANS'");
      }
      c.next_token();
      c.expect_line_end(kComment);
      continue;
    }
    if (all_digits(token)) {
      const long long n =
          c.next_integer("a frame number", 0, std::numeric_limits<int>::max(), true);
      if (frame_number >= 0 && n != frame_number + 1) {
        c.fail_expected_at(at, "frame number " + std::to_string(frame_number + 1));
      }
      c.expect_line_end(kComment, "end of line after the frame number");
      if (motion.num_frames == std::numeric_limits<int>::max()) {
        c.fail_expected_at(at, "at most " + std::to_string(motion.num_frames) + " frames");
      }
      frame_number = n;
      // A new frame starts at the rest pose; bone lines overwrite it (rows grow with the file).
      motion.rotations.insert(motion.rotations.end(), joints, Eigen::Quaterniond::Identity());
      motion.translations.insert(motion.translations.end(), rest.begin(), rest.end());
      ++motion.num_frames;
      continue;
    }
    if (motion.num_frames == 0) c.fail_expected("a frame number");
    const auto it = index.find(token);
    if (it == index.end()) c.fail_expected("a bone of the skeleton or a frame number");
    const int j = it->second;
    if (seen_in_frame[j] == motion.num_frames) {
      c.fail_expected_at(at, "each bone once per frame",
                         " again in frame " + std::to_string(frame_number));
    }
    seen_in_frame[j] = motion.num_frames;
    c.next_token();

    const JointDofs& d = info[j];
    values.clear();
    for (std::size_t k = 0; k < d.dofs.size(); ++k) {
      values.push_back(c.next_number_on_line([&] {
        return "value " + std::to_string(k + 1) + " of " + std::to_string(d.dofs.size()) +
               " for '" + quote_token(token) + "' (" + std::string(dof_name(d.dofs[k])) + ")";
      }));
    }
    if (!c.at_line_end_or_comment(kComment)) {
      c.fail_expected("end of line after the " + std::to_string(d.dofs.size()) + " values of '" +
                      quote_token(token) + "'");
    }

    const std::size_t base = static_cast<std::size_t>(motion.num_frames - 1) * joints;
    rot_axes.clear();
    rot_angles.clear();
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
    double stretch = 0.0;
    for (std::size_t k = 0; k < d.dofs.size(); ++k) {
      const Dof dof = d.dofs[k];
      if (is_rotation(dof)) {
        // First listed, first applied: R = R(last)·…·R(first).
        rot_axes.insert(rot_axes.begin(), static_cast<Axis>(dof_axis(dof)));
        rot_angles.insert(rot_angles.begin(), values[k] * amc_angle);
      } else if (is_translation(dof)) {
        if (j == 0) {
          motion.translations[base][dof_axis(dof)] = values[k];  // replaces `position`
        } else {
          shift[dof_axis(dof)] = values[k];
        }
      } else {
        stretch = values[k];
      }
    }
    if (!rot_axes.empty()) {
      motion.rotations[base + j] =
          (d.c * euler_to_quat(rot_axes, rot_angles) * d.c.conjugate()).normalized();
    }
    if (j > 0) {
      // Increments, so a child's own tx ty tz and its parent's `l` add up in any line order.
      motion.translations[base + j] += d.c_matrix * shift;
      for (const int child : d.children) {
        motion.translations[base + child] += d.direction * stretch;
      }
    }
  }
  if (motion.num_frames == 0) c.fail_expected("a frame number");
  return motion;
}

Clip load_asf_amc(const std::string& asf_path, const std::string& amc_path, double fps) {
  return load_asf_amc_text(asf_path, amc_path, read_text_file(amc_path), fps);
}

Clip load_asf_amc_text(const std::string& asf_path, const std::string& amc_path,
                       std::string_view amc_text, double fps) {
  AsfSkeleton asf = read_asf(asf_path);
  Clip clip;
  clip.path = amc_path;
  clip.motion = parse_amc(amc_text, asf, fps, amc_path);
  clip.skeleton = asf_to_skeleton(asf);
  clip.warnings = std::move(asf.warnings);
  return clip;
}

}  // namespace motionmap::io
