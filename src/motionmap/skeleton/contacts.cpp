#include "motionmap/skeleton/contacts.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <limits>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/stats.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap {

namespace {

enum class Part { None, Ankle, Toe };

struct NameClass {
  std::optional<FootSide> side;
  Part part = Part::None;
};

Part part_of(std::string_view s) {
  if (s == "foot" || s == "ankle") return Part::Ankle;
  if (s == "toe" || s == "toes" || s == "toebase" || s == "ball") return Part::Toe;
  return Part::None;
}

std::optional<FootSide> side_word(std::string_view w) {
  if (w == "left" || w == "l") return FootSide::Left;
  if (w == "right" || w == "r") return FootSide::Right;
  return std::nullopt;
}

NameClass classify(std::string_view name) {
  NameClass out;
  std::string rest;
  for (const std::string& w : joint_name_words(name)) {
    if (auto s = side_word(w); s && !out.side) {
      out.side = s;
    } else {
      rest += w;
    }
  }
  out.part = part_of(rest);
  if (out.part == Part::None && !out.side) {
    // A side glued in front: "lfoot", "rtoes", "leftfoot".
    for (const char* prefix : {"left", "right", "l", "r"}) {
      const std::string_view p(prefix);
      if (rest.size() > p.size() && rest.compare(0, p.size(), p) == 0 &&
          part_of(std::string_view(rest).substr(p.size())) != Part::None) {
        out.side = side_word(p);
        out.part = part_of(std::string_view(rest).substr(p.size()));
        break;
      }
    }
  }
  return out;
}

// Rest-pose (identity rotations) world positions: the sums of offsets down the hierarchy.
std::vector<Eigen::Vector3d> rest_positions(const Skeleton& skeleton) {
  std::vector<Eigen::Vector3d> p(skeleton.joints.size());
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
    const Joint& joint = skeleton.joints[j];
    p[j] = joint.parent < 0 ? joint.offset : Eigen::Vector3d(p[joint.parent] + joint.offset);
  }
  return p;
}

double skeleton_scale(const Skeleton& skeleton) {
  double s = 0.0;
  for (const Joint& j : skeleton.joints) s = std::max(s, j.offset.norm());
  return s;
}

// The nearest ancestor of `joint` at a distance from it in the rest pose, or −1.
int distant_ancestor(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& rest, int joint,
                     double eps) {
  for (int p = skeleton.joints[joint].parent; p >= 0; p = skeleton.joints[p].parent) {
    if ((rest[p] - rest[joint]).norm() > eps) return p;
  }
  return -1;
}

std::vector<std::vector<int>> children_of(const Skeleton& skeleton) {
  std::vector<std::vector<int>> children(skeleton.joints.size());
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    if (skeleton.joints[j].parent >= 0) children[skeleton.joints[j].parent].push_back(j);
  }
  return children;
}

// Completes a leg from its ankle (knee, hip, toe); false if the ankle has no two ancestors.
bool complete_leg(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& rest,
                  const std::vector<std::vector<int>>& children, double eps, Leg& leg) {
  leg.knee = distant_ancestor(skeleton, rest, leg.ankle, eps);
  if (leg.knee < 0) return false;
  leg.hip = distant_ancestor(skeleton, rest, leg.knee, eps);
  if (leg.hip < 0) return false;
  if (leg.toe < 0) {
    for (int c : children[leg.ankle]) {
      if (classify(skeleton.joints[c].name).part == Part::Toe) {
        leg.toe = c;
        break;
      }
    }
  }
  if (leg.toe < 0) {
    for (int c : children[leg.ankle]) {
      if ((rest[c] - rest[leg.ankle]).norm() > eps) {
        leg.toe = c;
        break;
      }
    }
  }
  return true;
}

bool legs_distinct(const Feet& feet) {
  const Leg& a = feet.legs[0];
  const Leg& b = feet.legs[1];
  for (int x : {a.hip, a.knee, a.ankle}) {
    for (int y : {b.hip, b.knee, b.ankle}) {
      if (x == y) return false;
    }
  }
  return true;
}

std::optional<Feet> feet_by_name(const Skeleton& skeleton, const std::vector<Eigen::Vector3d>& rest,
                                 const std::vector<std::vector<int>>& children, double eps) {
  Feet feet;
  feet.legs[0].side = FootSide::Left;
  feet.legs[1].side = FootSide::Right;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const NameClass c = classify(skeleton.joints[j].name);
    if (c.part != Part::Ankle || !c.side) continue;
    Leg& leg = feet.legs[*c.side == FootSide::Left ? 0 : 1];
    if (leg.ankle < 0) leg.ankle = j;
  }
  for (Leg& leg : feet.legs) {
    if (leg.ankle < 0 || !complete_leg(skeleton, rest, children, eps, leg)) return std::nullopt;
  }
  if (!legs_distinct(feet)) return std::nullopt;
  feet.by_name = true;
  return feet;
}

std::optional<Feet> feet_by_hierarchy(const Skeleton& skeleton,
                                      const std::vector<Eigen::Vector3d>& rest,
                                      const std::vector<std::vector<int>>& children, double eps,
                                      Axis up) {
  struct Chain {
    std::vector<int> joints;  // leaf first, distinct positions only
  };
  std::vector<Chain> chains;
  for (int leaf = 0; leaf < skeleton.num_joints(); ++leaf) {
    if (!children[leaf].empty()) continue;
    Chain chain;
    for (int j = leaf; j >= 0; j = skeleton.joints[j].parent) {
      if (j != leaf && children[j].size() > 1) break;
      if (skeleton.joints[j].parent < 0) break;
      // A joint at its parent's position (zero offset) adds no bone.
      if (skeleton.joints[j].offset.norm() > eps) chain.joints.push_back(j);
    }
    if (chain.joints.size() >= 3) chains.push_back(std::move(chain));
  }
  if (chains.size() < 2) return std::nullopt;
  const int axis = static_cast<int>(up);
  std::stable_sort(chains.begin(), chains.end(), [&](const Chain& a, const Chain& b) {
    return rest[a.joints.front()][axis] < rest[b.joints.front()][axis];
  });
  Feet feet;
  for (int i = 0; i < 2; ++i) {
    const Chain& c = chains[static_cast<std::size_t>(i)];
    Leg& leg = feet.legs[static_cast<std::size_t>(i)];
    if (c.joints.size() >= 4) {
      leg.toe = c.joints[0];
      leg.ankle = c.joints[1];
    } else {
      leg.ankle = c.joints[0];
    }
    if (!complete_leg(skeleton, rest, children, eps, leg)) return std::nullopt;
  }
  if (rest[feet.legs[0].ankle].x() < rest[feet.legs[1].ankle].x()) {
    std::swap(feet.legs[0], feet.legs[1]);
  }
  feet.legs[0].side = FootSide::Left;
  feet.legs[1].side = FootSide::Right;
  if (!legs_distinct(feet)) return std::nullopt;
  feet.by_name = false;
  return feet;
}

int window_half(double fps) {
  return std::max(1, frames_at_least(1.0 / 60.0, fps));
}

void check_range(std::string_view name, double value, double lo, double hi, bool open_lo,
                 std::string_view what) {
  const bool ok = (open_lo ? value > lo : value >= lo) && value <= hi;
  if (!ok) {
    throw ParameterError(std::string(name) + ": " + format_number(value) + " is out of range (" +
                         std::string(what) + ", must be in " + (open_lo ? "(" : "[") +
                         format_number(lo) + ", " + format_number(hi) + "])");
  }
}

}  // namespace

std::string_view foot_side_name(FootSide side) {
  return side == FootSide::Left ? "left" : "right";
}

std::optional<Feet> try_find_feet(const Skeleton& skeleton, Axis up, std::string* why) {
  check_skeleton(skeleton, "find_feet", MotionCheck::Sizes);
  const std::vector<Eigen::Vector3d> rest = rest_positions(skeleton);
  const auto children = children_of(skeleton);
  const double eps = 1e-6 * std::max(skeleton_scale(skeleton), 1e-300);
  if (auto feet = feet_by_name(skeleton, rest, children, eps)) return feet;
  if (auto feet = feet_by_hierarchy(skeleton, rest, children, eps, up)) return feet;
  if (why) {
    *why =
        "no feet found: no joints named like a left and a right foot or ankle (LeftFoot, Foot_L, "
        "lfoot, LeftAnkle, …) with a knee and a hip above them, and no two leaf chains of at "
        "least 3 joints (hip → knee → ankle) in the hierarchy of " +
        std::to_string(skeleton.num_joints()) + " joints";
  }
  return std::nullopt;
}

Feet find_feet(const Skeleton& skeleton, Axis up) {
  std::string why;
  if (auto feet = try_find_feet(skeleton, up, &why)) return *feet;
  throw ParameterError(why);
}

std::string_view length_unit_name(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Metre:
      return "m";
    case LengthUnit::CmuUnit:
      return "CMU units (1/0.45 in)";
    case LengthUnit::Inch:
      return "in";
    case LengthUnit::Centimetre:
      return "cm";
    case LengthUnit::Millimetre:
      return "mm";
  }
  return "?";
}

double metres_per_unit(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Metre:
      return 1.0;
    case LengthUnit::CmuUnit:
      return 0.0254 / 0.45;
    case LengthUnit::Inch:
      return 0.0254;
    case LengthUnit::Centimetre:
      return 0.01;
    case LengthUnit::Millimetre:
      return 0.001;
  }
  return 1.0;
}

LengthUnits detect_length_units(const Skeleton& skeleton, const Motion& motion) {
  check_motion(skeleton, motion, "detect_length_units", MotionCheck::Sizes);
  const int J = skeleton.num_joints();
  std::vector<double> sizes;
  WorldPose world;
  // The body: the motion root and what hangs below it (not a static joint_Root left at the
  // origin while the body walks away), with End Sites.
  const int root = motion_root(skeleton, motion);
  std::vector<char> body(static_cast<std::size_t>(J), 0);
  for (int j = 0; j < J; ++j) {
    body[j] = j == root || (skeleton.joints[j].parent >= 0 && body[skeleton.joints[j].parent]);
  }
  auto add = [&](const PoseView& pose) {
    forward_kinematics(skeleton, pose, world);
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    std::size_t e = 0;
    for (int j = 0; j < J; ++j) {
      const std::size_t sites = skeleton.joints[j].end_sites.size();
      if (body[j]) {
        lo = lo.cwiseMin(world.positions[j]);
        hi = hi.cwiseMax(world.positions[j]);
        for (std::size_t k = 0; k < sites; ++k) {
          lo = lo.cwiseMin(world.end_sites[e + k]);
          hi = hi.cwiseMax(world.end_sites[e + k]);
        }
      }
      e += sites;
    }
    const double size = (hi - lo).maxCoeff();
    if (std::isfinite(size)) sizes.push_back(size);
  };
  if (motion.num_frames == 0) {
    std::vector<Eigen::Quaterniond> rotations(J, Eigen::Quaterniond::Identity());
    std::vector<Eigen::Vector3d> offsets;
    for (const Joint& j : skeleton.joints) offsets.push_back(j.offset);
    add({rotations, offsets});
  } else {
    const int count = std::min(motion.num_frames, 256);
    for (int i = 0; i < count; ++i) {
      const int f =
          count == 1
              ? 0
              : static_cast<int>(std::llround(static_cast<double>(i) * (motion.num_frames - 1) /
                                              static_cast<double>(count - 1)));
      add(motion.pose(f));
    }
  }
  LengthUnits out;
  out.size = sizes.empty() ? 0.0 : quantile(sizes, 0.9);
  constexpr double kReference = 1.6;  // metres
  constexpr LengthUnit kUnits[] = {LengthUnit::Metre, LengthUnit::CmuUnit, LengthUnit::Inch,
                                   LengthUnit::Centimetre, LengthUnit::Millimetre};
  out.unit = kUnits[0];
  for (std::size_t i = 0; i + 1 < std::size(kUnits); ++i) {
    // The boundary between unit i and i+1: the geometric mean of 1.6 m in each.
    const double bound =
        kReference / std::sqrt(metres_per_unit(kUnits[i]) * metres_per_unit(kUnits[i + 1]));
    if (out.size >= bound) out.unit = kUnits[i + 1];
  }
  out.metres_per_unit = metres_per_unit(out.unit);
  const double metres = out.size * out.metres_per_unit;
  out.plausible = metres >= 0.8 && metres <= 2.6;
  return out;
}

void ContactOptions::validate() const {
  check_range("height", height, 0.0, 1.0, true, "fraction of the leg length");
  check_range("speed", speed, 0.0, 100.0, true, "leg lengths per second");
  check_range("vertical_speed", vertical_speed, 0.0, 100.0, true, "leg lengths per second");
  check_range("gap_seconds", gap_seconds, 0.0, 10.0, false, "seconds");
  check_range("min_seconds", min_seconds, 0.0, 10.0, false, "seconds");
}

bool FootContacts::in_contact(int frame) const {
  for (const ContactInterval& c : intervals) {
    if (frame >= c.first && frame <= c.last) return true;
    if (frame < c.first) return false;
  }
  return false;
}

std::vector<Eigen::Vector3d> joint_trajectory(const Skeleton& skeleton, const Motion& motion,
                                              int joint) {
  check_motion(skeleton, motion, "joint_trajectory", MotionCheck::Sizes);
  if (joint < 0 || joint >= skeleton.num_joints()) {
    throw ParameterError("joint_trajectory: joint " + std::to_string(joint) +
                         " is out of range (the skeleton has " +
                         std::to_string(skeleton.num_joints()) + " joints)");
  }
  std::vector<int> chain;
  for (int j = joint; j >= 0; j = skeleton.joints[j].parent) chain.push_back(j);
  std::reverse(chain.begin(), chain.end());
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(motion.num_frames));
  for (int f = 0; f < motion.num_frames; ++f) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    for (int j : chain) {
      p += q * motion.translation(f, j);
      q = q * motion.rotation(f, j);
    }
    out[static_cast<std::size_t>(f)] = p;
  }
  return out;
}

AnklePaths ankle_paths(const Skeleton& skeleton, const Motion& motion, const Feet& feet) {
  return {joint_trajectory(skeleton, motion, feet.legs[0].ankle),
          joint_trajectory(skeleton, motion, feet.legs[1].ankle)};
}

std::array<FootContacts, 2> detect_contacts(const Skeleton& skeleton, const Motion& motion,
                                            const Feet& feet, const ContactOptions& options) {
  options.validate();
  check_motion(skeleton, motion, "detect_contacts", MotionCheck::Sizes);
  return detect_contacts(skeleton, motion, feet, ankle_paths(skeleton, motion, feet), options);
}

std::array<FootContacts, 2> detect_contacts(const Skeleton& skeleton, const Motion& motion,
                                            const Feet& feet, const AnklePaths& ankles,
                                            const ContactOptions& options) {
  options.validate();
  check_motion(skeleton, motion, "detect_contacts", MotionCheck::Sizes);
  const int F = motion.num_frames;
  for (const auto& path : ankles) {
    if (path.size() != static_cast<std::size_t>(F)) {
      throw ParameterError("detect_contacts: an ankle path of " + std::to_string(path.size()) +
                           " points for " + std::to_string(F) + " frames");
    }
  }
  const int axis = static_cast<int>(options.up);
  const double fps = motion.fps();
  const int half = window_half(fps);
  const int gap = frames_at_most(options.gap_seconds, fps);
  const int min_frames = std::max(1, frames_at_least(options.min_seconds, fps));
  std::array<FootContacts, 2> out;
  for (int s = 0; s < 2; ++s) {
    const Leg& leg = feet.legs[static_cast<std::size_t>(s)];
    FootContacts& fc = out[static_cast<std::size_t>(s)];
    fc.leg = leg;
    if (F == 0) continue;
    const WorldPose w0 = forward_kinematics(skeleton, motion, 0);
    fc.leg_length = (w0.positions[leg.knee] - w0.positions[leg.hip]).norm() +
                    (w0.positions[leg.ankle] - w0.positions[leg.knee]).norm();
    const std::vector<Eigen::Vector3d>& ankle = ankles[static_cast<std::size_t>(s)];
    std::vector<double> heights(static_cast<std::size_t>(F));
    for (int f = 0; f < F; ++f) heights[static_cast<std::size_t>(f)] = ankle[f][axis];
    fc.floor = quantile(heights, 0.02);
    const double max_height = options.height * fc.leg_length;
    const double max_speed = options.speed * fc.leg_length;
    const double max_climb = options.vertical_speed * fc.leg_length;
    std::vector<char> on(static_cast<std::size_t>(F), 0);
    for (int f = 0; f < F; ++f) {
      const int lo = std::max(0, f - half), hi = std::min(F - 1, f + half);
      double speed = 0.0, climb = 0.0;
      if (hi > lo) {
        Eigen::Vector3d d = (ankle[hi] - ankle[lo]) / ((hi - lo) * motion.frame_time);
        climb = std::abs(d[axis]);
        d[axis] = 0.0;
        speed = d.norm();
      }
      on[static_cast<std::size_t>(f)] =
          heights[static_cast<std::size_t>(f)] - fc.floor <= max_height && speed <= max_speed &&
          climb <= max_climb;
    }
    // Runs, gaps filled, short runs dropped.
    std::vector<ContactInterval> runs;
    for (int f = 0; f < F; ++f) {
      if (!on[static_cast<std::size_t>(f)]) continue;
      if (!runs.empty() && f - runs.back().last - 1 <= gap) {
        runs.back().last = f;
      } else {
        runs.push_back({f, f});
      }
    }
    for (const ContactInterval& r : runs) {
      if (r.frames() >= min_frames) fc.intervals.push_back(r);
    }
  }
  return out;
}

Skating measure_skating(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                        const LengthUnits& units, Axis up) {
  check_motion(skeleton, motion, "measure_skating", MotionCheck::Sizes);
  if (!(units.metres_per_unit > 0.0) || !std::isfinite(units.metres_per_unit)) {
    throw ParameterError("measure_skating: metres_per_unit " +
                         format_number(units.metres_per_unit) + " is not a finite number > 0");
  }
  Skating out;
  out.units = units;
  const int F = motion.num_frames;
  out.transitions = std::max(0, F - 1);
  if (F < 2) {
    out.contact_speed_cm_s = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const int axis = static_cast<int>(up);
  const double m = units.metres_per_unit;
  std::vector<char> skating(static_cast<std::size_t>(F - 1), 0);
  double speed_sum = 0.0;
  for (const Leg& leg : feet.legs) {
    const std::vector<Eigen::Vector3d> ankle = joint_trajectory(skeleton, motion, leg.ankle);
    double lowest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : ankle) lowest = std::min(lowest, p[axis]);
    int raised = 0;
    for (const Eigen::Vector3d& p : ankle) {
      raised = (p[axis] - lowest) * m < kSkatingContactHeightM ? 0 : raised + 1;
      out.longest_raised_s = std::max(out.longest_raised_s, raised * motion.frame_time);
    }
    for (int f = 0; f + 1 < F; ++f) {
      const double h0 = (ankle[f][axis] - lowest) * m, h1 = (ankle[f + 1][axis] - lowest) * m;
      if (!(h0 < kSkatingContactHeightM && h1 < kSkatingContactHeightM)) continue;
      Eigen::Vector3d d = ankle[f + 1] - ankle[f];
      d[axis] = 0.0;
      const double speed = d.norm() * m / motion.frame_time;  // m/s
      ++out.contact_transitions;
      speed_sum += speed;
      if (speed > kSkatingSpeedMPerS) skating[static_cast<std::size_t>(f)] = 1;
    }
  }
  for (char s : skating) out.skating_transitions += s;
  out.ratio = static_cast<double>(out.skating_transitions) / out.transitions;
  out.contact_speed_cm_s = out.contact_transitions > 0 ? 100.0 * speed_sum / out.contact_transitions
                                                       : std::numeric_limits<double>::quiet_NaN();
  return out;
}

Skating measure_skating(const Skeleton& skeleton, const Motion& motion, const Feet& feet, Axis up) {
  return measure_skating(skeleton, motion, feet, detect_length_units(skeleton, motion), up);
}

}  // namespace motionmap
