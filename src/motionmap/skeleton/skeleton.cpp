#include "motionmap/skeleton/skeleton.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "motionmap/core/error.h"

namespace motionmap {

namespace {
constexpr std::array<std::string_view, 6> kChannelNames = {"Xposition", "Yposition", "Zposition",
                                                           "Xrotation", "Yrotation", "Zrotation"};
}

std::string_view channel_name(ChannelType c) {
  return kChannelNames[static_cast<int>(c)];
}

std::optional<ChannelType> parse_channel_name(std::string_view name) {
  for (std::size_t i = 0; i < kChannelNames.size(); ++i) {
    if (kChannelNames[i] == name) return static_cast<ChannelType>(i);
  }
  return std::nullopt;
}

int Skeleton::num_channels() const {
  int n = 0;
  for (const auto& j : joints) n += static_cast<int>(j.channels.size());
  return n;
}

int Skeleton::num_end_sites() const {
  int n = 0;
  for (const auto& j : joints) n += static_cast<int>(j.end_sites.size());
  return n;
}

std::vector<int> Skeleton::roots() const {
  std::vector<int> r;
  for (int i = 0; i < num_joints(); ++i) {
    if (joints[i].parent < 0) r.push_back(i);
  }
  return r;
}

int Skeleton::find(std::string_view name) const {
  for (int i = 0; i < num_joints(); ++i) {
    if (joints[i].name == name) return i;
  }
  return -1;
}

bool Skeleton::same_hierarchy(const Skeleton& other) const {
  if (joints.size() != other.joints.size()) return false;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].name != other.joints[i].name || joints[i].parent != other.joints[i].parent ||
        joints[i].end_sites.size() != other.joints[i].end_sites.size()) {
      return false;
    }
  }
  return true;
}

void Skeleton::validate() const {
  std::unordered_set<std::string_view> names;
  for (int i = 0; i < num_joints(); ++i) {
    const Joint& j = joints[i];
    if (j.parent >= i || j.parent < -1) {
      throw Error("joint '" + j.name + "' (index " + std::to_string(i) + ") has parent index " +
                  std::to_string(j.parent) + ": parents must come before their children");
    }
    if (!names.insert(j.name).second) {
      throw Error("joint name '" + j.name + "' is used twice");
    }
  }
}

void Motion::resize(int frames, int joints) {
  num_frames = frames;
  num_joints = joints;
  const auto n = static_cast<std::size_t>(frames) * static_cast<std::size_t>(joints);
  rotations.assign(n, Eigen::Quaterniond::Identity());
  translations.assign(n, Eigen::Vector3d::Zero());
}

Motion Motion::frames(int first, int end) const {
  if (first < 0 || first > end || end > num_frames) {
    throw ParameterError("Motion::frames: frames " + std::to_string(first) + " to " +
                         std::to_string(end) + " (end excluded) of a motion of " +
                         std::to_string(num_frames) + " frames");
  }
  Motion out;
  out.frame_time = frame_time;
  out.num_frames = end - first;
  out.num_joints = num_joints;
  const auto J = static_cast<std::ptrdiff_t>(num_joints);
  out.rotations.assign(rotations.begin() + first * J, rotations.begin() + end * J);
  out.translations.assign(translations.begin() + first * J, translations.begin() + end * J);
  return out;
}

namespace {
// A whole number of frames as an int, beyond its range the nearest end (NaN: 0).
int frame_count(double whole) {
  if (std::isnan(whole)) return 0;
  return static_cast<int>(std::clamp(whole, double(std::numeric_limits<int>::min()),
                                     double(std::numeric_limits<int>::max())));
}
}  // namespace

int frames_at_least(double seconds, double fps) {
  return frame_count(std::ceil(seconds * fps * (1.0 - kFrameCountSlack)));
}

int frames_at_most(double seconds, double fps) {
  return frame_count(std::floor(seconds * fps * (1.0 + kFrameCountSlack)));
}

int motion_root(const Skeleton& skeleton, const Motion& motion) {
  check_motion(skeleton, motion, "motion_root", MotionCheck::Sizes);
  const auto roots = skeleton.roots();
  int joint = roots.empty() ? 0 : roots.front();
  for (;;) {
    int child = -1, children = 0;
    for (int j = joint + 1; j < skeleton.num_joints(); ++j) {
      if (skeleton.joints[j].parent == joint) {
        child = j;
        ++children;
      }
    }
    if (children != 1 || motion.num_frames == 0) return joint;
    const Eigen::Quaterniond q0 = motion.rotation(0, joint);
    const Eigen::Vector3d t0 = motion.translation(0, joint);
    for (int f = 1; f < motion.num_frames; ++f) {
      if (rotation_angle(motion.rotation(f, joint), q0) > 1e-12 ||
          (motion.translation(f, joint) - t0).norm() > 1e-12 * (1.0 + t0.norm())) {
        return joint;
      }
    }
    joint = child;
  }
}

PoseView Motion::pose(int frame) const {
  const std::size_t begin = index(frame, 0);
  const auto n = static_cast<std::size_t>(num_joints);
  return {std::span<const Eigen::Quaterniond>(rotations).subspan(begin, n),
          std::span<const Eigen::Vector3d>(translations).subspan(begin, n)};
}

std::vector<std::string> joint_name_words(std::string_view name) {
  const auto cut = name.find_last_of(":|");
  if (cut != std::string_view::npos) name = name.substr(cut + 1);
  std::vector<std::string> words;
  std::string word;
  const auto flush = [&] {
    if (!word.empty()) words.push_back(word);
    word.clear();
  };
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (!std::isalnum(c)) {
      flush();
      continue;
    }
    if (!word.empty()) {
      const auto prev = static_cast<unsigned char>(name[i - 1]);
      const bool next_lower =
          i + 1 < name.size() && std::islower(static_cast<unsigned char>(name[i + 1]));
      const bool camel =
          std::isupper(c) && (std::islower(prev) || (std::isupper(prev) && next_lower));
      const bool digit_change = (std::isdigit(c) != 0) != (std::isdigit(prev) != 0);
      if (camel || digit_change) flush();
    }
    word += static_cast<char>(std::tolower(c));
  }
  flush();
  return words;
}

}  // namespace motionmap
