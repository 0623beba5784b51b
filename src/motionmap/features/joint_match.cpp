#include "motionmap/features/joint_match.h"

#include <algorithm>
#include <unordered_set>

#include "motionmap/core/files.h"

namespace motionmap::features {

std::vector<std::string> common_joint_names(std::span<const Clip> clips) {
  std::vector<std::string> names;
  if (clips.empty()) return names;
  std::vector<std::unordered_set<std::string_view>> others;
  for (std::size_t c = 1; c < clips.size(); ++c) {
    auto& set = others.emplace_back();
    for (const Joint& j : clips[c].skeleton.joints) set.insert(j.name);
  }
  for (const Joint& j : clips.front().skeleton.joints) {
    const bool everywhere = std::all_of(others.begin(), others.end(),
                                        [&](const auto& set) { return set.count(j.name) > 0; });
    if (everywhere) names.push_back(j.name);
  }
  return names;
}

namespace {

// "'Spine' (parent 'Hips')" or "'Hips' (a root)".
std::string describe_joint(const Skeleton& s, int j) {
  const Joint& joint = s.joints[static_cast<std::size_t>(j)];
  const int p = joint.parent;
  return "'" + joint.name + "' (" +
         (p < 0 || p >= s.num_joints()
              ? std::string("a root")
              : "parent '" + s.joints[static_cast<std::size_t>(p)].name + "'") +
         ")";
}

bool same_joint(const Skeleton& a, const Skeleton& b, int j) {
  const Joint& ja = a.joints[static_cast<std::size_t>(j)];
  const Joint& jb = b.joints[static_cast<std::size_t>(j)];
  return ja.name == jb.name && ja.parent == jb.parent;
}

}  // namespace

std::string hierarchy_difference(const Clip& reference, const Clip& other) {
  const Skeleton& a = reference.skeleton;
  const Skeleton& b = other.skeleton;
  if (b.same_hierarchy(a)) return {};
  const std::string ref = base_name(reference.path);
  const int na = a.num_joints(), nb = b.num_joints();
  const int shared = std::min(na, nb);
  int first = 0;
  while (first < shared && same_joint(a, b, first)) ++first;
  std::string out;
  if (na != nb) {
    out = "it has " + std::to_string(nb) + " joints, " + ref + " " + std::to_string(na) + "; ";
  }
  if (first < shared) {
    out += std::string(na != nb ? "the first that differs" : "the first joint that differs") +
           " is joint " + std::to_string(first) + ": " + describe_joint(b, first) + " where " +
           ref + " has " + describe_joint(a, first);
  } else if (na == nb) {
    // Same joints and parents: an End Site count differs.
    int j = 0;
    while (a.joints[std::size_t(j)].end_sites.size() == b.joints[std::size_t(j)].end_sites.size()) {
      ++j;
    }
    out += "joint '" + b.joints[std::size_t(j)].name + "' has " +
           std::to_string(b.joints[std::size_t(j)].end_sites.size()) + " End Site(s) where " + ref +
           " has " + std::to_string(a.joints[std::size_t(j)].end_sites.size());
  } else if (nb > na) {
    out += "its first " + std::to_string(na) + " are " + ref + "'s, then comes '" +
           b.joints[static_cast<std::size_t>(na)].name + "'";
  } else {
    out += "they are " + ref + "'s first " + std::to_string(nb) + ", without '" +
           a.joints[static_cast<std::size_t>(nb)].name + "'";
  }
  return out;
}

}  // namespace motionmap::features
