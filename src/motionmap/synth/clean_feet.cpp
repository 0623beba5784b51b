#include "motionmap/synth/clean_feet.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/detail/smoothing.h"

namespace motionmap::synth {

namespace {

constexpr int kBlockFrames = 256;
// Below this |thigh × shin| (sin 5°) the knee's own hinge axis is not trusted.
constexpr double kStraightSin = 0.0872;

using Eigen::Quaterniond;
using Eigen::Vector3d;

bool is_ancestor(const Skeleton& s, int ancestor, int joint) {
  for (int j = joint; j >= 0; j = s.joints[j].parent) {
    if (j == ancestor) return true;
  }
  return false;
}

Quaterniond parent_world(const Skeleton& s, const WorldPose& w, int joint) {
  const int p = s.joints[joint].parent;
  return p < 0 ? Quaterniond::Identity() : w.rotations[p];
}

struct FootPlan {
  Leg leg;
  std::vector<Vector3d> ankle;               // original world positions per frame
  std::vector<double> height;                // the heights contacts keep (ankle_heights)
  std::vector<Vector3d> offset;              // target − original per frame (zero: untouched)
  std::vector<char> touched;                 // whether offset applies (even when it is zero)
  Vector3d hinge_local = Vector3d::UnitX();  // in the knee's parent's frame
  double length = 0.0;                       // hip–knee + knee–ankle
};

// The height a planted ankle stands at over frames [first, last] whose own heights are `h`, into
// out[first..last]: down to their lowest, which it reaches at their lowest frame, following them
// down before it as they make new lows (a heel strike) and up after it (heel-off), level where
// they rise and fall back. (Held at the mean of its heights, a contact stood up to 1 cm above its
// lowest: a run sketched near its capture skated 1–3 more of each hundred transitions cleaned
// than raw, the skating measure's line, 5 cm over the clip's lowest ankle, raised as much.)
void lower_envelope(const std::vector<double>& h, int first, int last, std::vector<double>& out) {
  int lowest = first;
  for (int f = first; f <= last; ++f)
    if (h[f] < h[lowest]) lowest = f;
  double low = std::numeric_limits<double>::infinity();
  for (int f = first; f <= lowest; ++f) out[f] = low = std::min(low, h[f]);
  low = std::numeric_limits<double>::infinity();
  for (int f = last; f > lowest; --f) out[f] = low = std::min(low, h[f]);
}

// The ankle's target displacement around the contacts (see the top of clean_feet.h).
void plan_offsets(const FootContacts& fc, int frames, int blend, const std::vector<char>& fixed,
                  const Vector3d& up, FootPlan& plan) {
  plan.offset.assign(static_cast<std::size_t>(frames), Vector3d::Zero());
  plan.touched.assign(static_cast<std::size_t>(frames), 0);
  const auto& iv = fc.intervals;
  // Per contact, the ankle's target at its first and its last frame (the fades start from them).
  std::vector<Vector3d> first_target(iv.size()), last_target(iv.size());
  std::vector<double> floor_height(static_cast<std::size_t>(frames)), own(floor_height.size());
  for (std::size_t c = 0; c < iv.size(); ++c) {
    std::vector<int> held;  // the fixed frames in the contact
    for (int f = iv[c].first; f <= iv[c].last; ++f) {
      if (fixed[static_cast<std::size_t>(f)]) held.push_back(f);
    }
    if (held.empty()) {
      // The ankle's mean place over the contact, at the floor height of the heights kept.
      Vector3d sum = Vector3d::Zero();
      for (int f = iv[c].first; f <= iv[c].last; ++f) sum += plan.ankle[f];
      sum /= iv[c].frames();
      lower_envelope(plan.height, iv[c].first, iv[c].last, floor_height);
      for (int f = iv[c].first; f <= iv[c].last; ++f)
        plan.offset[f] = sum + (floor_height[f] - sum.dot(up)) * up;
    } else {
      // Fixed frames in the contact: the ankle stays where the first has it before it and where
      // the last has it after; between two, it goes straight from one's place to the other's, so
      // no leg stretches between two keys whose captured foot slid a little. Before the first
      // (after the last) at the floor height of the ankle's own heights from the contact's start
      // to that frame (from it to the end): the fixed frame's height stands for the part of the
      // contact beyond it, so a path edit's window, whose border frames are the previous
      // motion's, holds a contact that runs past it as the whole motion's clean-up did.
      for (int f = iv[c].first; f <= iv[c].last; ++f) own[f] = plan.ankle[f].dot(up);
      lower_envelope(own, iv[c].first, held.front(), floor_height);
      lower_envelope(own, held.back(), iv[c].last, floor_height);
      std::size_t k = 0;
      for (int f = iv[c].first; f <= iv[c].last; ++f) {
        while (k + 1 < held.size() && held[k + 1] <= f) ++k;
        const int a = held[k];
        if (f <= a || k + 1 == held.size()) {
          plan.offset[f] = plan.ankle[a] + (floor_height[f] - own[a]) * up;
        } else {
          const int b = held[k + 1];
          const double u = static_cast<double>(f - a) / static_cast<double>(b - a);
          plan.offset[f] = (1.0 - u) * plan.ankle[a] + u * plan.ankle[b];
        }
      }
    }
    first_target[c] = plan.offset[iv[c].first];
    last_target[c] = plan.offset[iv[c].last];
    for (int f = iv[c].first; f <= iv[c].last; ++f) {
      plan.offset[f] -= plan.ankle[f];  // the target, as a displacement
      plan.touched[f] = 1;
    }
  }
  if (blend <= 0) return;
  // Frames between contacts: fades from the previous contact's end and the next one's start.
  std::size_t next = 0;  // first contact starting after f
  for (int f = 0; f < frames; ++f) {
    while (next < iv.size() && iv[next].first <= f) ++next;
    if (plan.touched[f]) continue;
    double w1 = 0.0, w2 = 0.0;
    Vector3d d1 = Vector3d::Zero(), d2 = Vector3d::Zero();
    if (next > 0) {
      const ContactInterval& c = iv[next - 1];
      w1 = detail::falloff(static_cast<double>(f - c.last) / (blend + 1));
      d1 = last_target[next - 1] - plan.ankle[c.last];
    }
    if (next < iv.size()) {
      const ContactInterval& c = iv[next];
      w2 = detail::falloff(static_cast<double>(c.first - f) / (blend + 1));
      d2 = first_target[next] - plan.ankle[c.first];
    }
    if (w1 + w2 <= 0.0) continue;
    plan.offset[f] = (w1 * d1 + w2 * d2) / std::max(1.0, w1 + w2);
    plan.touched[f] = 1;
  }
  // A fixed frame outside the contacts is left as given, so the displacement fades to nothing
  // over ±blend towards it, a hold's last frames included: a contact cut one frame before an
  // in-between's key that leaves the foot in the air held a glided ankle 1 m from where the key
  // has it, and the foot snapped there.
  std::size_t c = 0;
  for (int k = 0; k < frames; ++k) {
    while (c < iv.size() && iv[c].last < k) ++c;
    if (!fixed[static_cast<std::size_t>(k)] || (c < iv.size() && iv[c].first <= k)) continue;
    for (int f = std::max(0, k - blend); f <= std::min(frames - 1, k + blend); ++f)
      plan.offset[f] *= 1.0 - detail::falloff(std::abs(f - k) / (blend + 1.0));
  }
}

// CleanFeetOptions::keep_above_floor on a planned foot: its ankles below the floor lifted. The
// floor is the lowest of the median heights (ankle_heights') of this foot's contacts without a
// fixed frame; none: no lift. Not the motion's own lowest heights: over a short in-between a foot
// may never touch the floor, and a contact holding a fixed frame stands where that frame has it.
// Not the lowest height nor the mean height of a contact: a punch's key to the tired walk's dips
// one contact's blend 3.4 cm for a few frames, and with the floor there the ankle stood 3.9 cm
// under the captures' floor (2.2 with the floor at that contact's mean; 1.8 at its median).
void lift_above_floor(const FootContacts& fc, const std::vector<char>& fixed, const Vector3d& up,
                      FootPlan& plan) {
  double floor = std::numeric_limits<double>::infinity();
  for (const ContactInterval& c : fc.intervals) {
    bool free = true;
    for (int f = c.first; f <= c.last; ++f) free = free && !fixed[static_cast<std::size_t>(f)];
    if (!free) continue;
    std::vector<double> h(plan.height.begin() + c.first, plan.height.begin() + c.last + 1);
    std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(h.size() / 2), h.end());
    floor = std::min(floor, h[h.size() / 2]);
  }
  if (!std::isfinite(floor)) return;
  // Within kFloorSlack leg lengths under it the ankle stays as it is (a stance's own heights vary
  // by as much), and one further down stops there.
  floor -= kFloorSlack * plan.length;
  for (std::size_t f = 0; f < plan.offset.size(); ++f) {
    if (fixed[f]) continue;
    const double below = floor - (plan.ankle[f] + plan.offset[f]).dot(up);
    if (below <= 0.0) continue;
    plan.offset[f] += below * up;
    plan.touched[f] = 1;
  }
}

// Two-bone IK of one leg of the pose `q` (local rotations of one frame), whose world pose is `w`:
// the ankle onto `target`. Changes the hip's and the knee's local rotations.
void solve_leg(const Skeleton& s, const WorldPose& w, const FootPlan& plan, const Vector3d& target,
               double reach, Quaterniond* q) {
  const Leg& leg = plan.leg;
  const Vector3d H = w.positions[leg.hip], K = w.positions[leg.knee], A = w.positions[leg.ankle];
  const double l1 = (K - H).norm(), l2 = (A - K).norm();
  if (l1 <= 0.0 || l2 <= 0.0) return;
  const Vector3d t1 = (K - H) / l1, t2 = (A - K) / l2;
  // The knee's hinge: the leg's own plane where it bends forward (the side of the input's most
  // bent frame), else — straight, or bent backwards — that frame's hinge carried by the thigh,
  // so that the new bend (0…π about it) is forward whatever the input's.
  Vector3d hinge = parent_world(s, w, leg.knee) * plan.hinge_local;
  hinge -= hinge.dot(t1) * t1;  // perpendicular to the thigh
  hinge = hinge.norm() > 1e-12 ? Vector3d(hinge.normalized()) : Vector3d(t1.unitOrthogonal());
  Vector3d axis = t1.cross(t2);
  if (axis.norm() > kStraightSin && axis.dot(hinge) > 0.0) {
    axis.normalize();
  } else {
    axis = hinge;
  }
  const double bend = std::atan2(t1.cross(t2).dot(axis), t1.dot(t2));
  const double length = l1 + l2;
  const double original = (A - H).norm();
  const double longest = std::min(std::max(reach * length, original), length * (1.0 - 1e-9));
  const double d = std::clamp((target - H).norm(), std::abs(l1 - l2) + 1e-9 * length, longest);
  const double cos_bend = std::clamp((d * d - l1 * l1 - l2 * l2) / (2.0 * l1 * l2), -1.0, 1.0);
  const double new_bend = std::acos(cos_bend);  // 0…π: towards the knee's side, never backwards
  const Quaterniond knee_turn(Eigen::AngleAxisd(new_bend - bend, axis));
  const Quaterniond knee_world = (knee_turn * w.rotations[leg.knee]).normalized();
  q[leg.knee] = (parent_world(s, w, leg.knee).conjugate() * knee_world).normalized();
  const Vector3d A1 = K + knee_turn * (A - K);
  const Vector3d from = A1 - H, to = target - H;
  if (from.norm() < 1e-12 || to.norm() < 1e-12) return;
  const Quaterniond swing = Quaterniond::FromTwoVectors(from, to);
  const Quaterniond hip_world = (swing * w.rotations[leg.hip]).normalized();
  q[leg.hip] = (parent_world(s, w, leg.hip).conjugate() * hip_world).normalized();
}

void check_leg(const Skeleton& s, const Leg& leg) {
  const int n = s.num_joints();
  for (int j : {leg.hip, leg.knee, leg.ankle}) {
    if (j < 0 || j >= n) {
      throw ParameterError("clean_feet: the " + std::string(foot_side_name(leg.side)) +
                           " leg's joint index " + std::to_string(j) +
                           " is not a joint of the skeleton (" + std::to_string(n) +
                           " joints); take the feet from find_feet() of this skeleton");
    }
  }
  if (!is_ancestor(s, leg.hip, leg.knee) || !is_ancestor(s, leg.knee, leg.ankle) ||
      leg.hip == leg.knee || leg.knee == leg.ankle) {
    throw ParameterError("clean_feet: the " + std::string(foot_side_name(leg.side)) +
                         " leg is not a chain hip → knee → ankle of the skeleton");
  }
}

}  // namespace

void CleanFeetOptions::validate() const {
  try {
    contacts.validate();
  } catch (const ParameterError& e) {
    throw ParameterError("contacts." + std::string(e.what()));
  }
  if (!(blend_seconds >= 0.0 && blend_seconds <= 2.0)) {
    throw ParameterError("blend_seconds: " + format_number(blend_seconds) +
                         " is out of range (seconds, must be in [0, 2])");
  }
  if (!(reach >= 0.5 && reach < 1.0)) {
    throw ParameterError("reach: " + format_number(reach) +
                         " is out of range (fraction of the leg length, must be in [0.5, 1))");
  }
  if (!(max_root_drop >= 0.0 && max_root_drop <= 1.0)) {
    throw ParameterError("max_root_drop: " + format_number(max_root_drop) +
                         " is out of range (fraction of the leg length, must be in [0, 1])");
  }
  if (!(reach_slack >= 0.0 && reach_slack <= 0.5)) {
    throw ParameterError("reach_slack: " + format_number(reach_slack) +
                         " is out of range (fraction of the leg length, must be in [0, 0.5])");
  }
}

namespace {

// Each leg's ankle path (left, right), computed once for the contacts and the clean-up.
using Ankles = AnklePaths;

// How far apart frames a and b have the ankle on the floor (across `up`).
double floor_distance(std::span<const Vector3d> ankle, int a, int b, const Vector3d& up) {
  const Vector3d d = ankle[static_cast<std::size_t>(b)] - ankle[static_cast<std::size_t>(a)];
  return (d - d.dot(up) * up).norm();
}

// Frames left free between two holds of a foot (kHoldFadeSeconds), at least one.
int hold_fade_frames(double fps) {
  return std::max(1, static_cast<int>(std::lround(kHoldFadeSeconds * fps)));
}

// Each contact started where its foot arrives (see clean_feet.h, step 1): extended back over the
// frames, from kHoldFadeSeconds after the foot's previous contact on, whose ankle is as low as a
// standing one and lies, on the floor, within one frame's contact speed of where the contact's
// first frame has it. detect_contacts() takes a frame's speed over ±⌈fps/60⌉ frames, so the frame
// a landing foot reaches its spot from is left out; a blend of two runs lands its feet over one
// frame more than the runs do (their phases read between frames), and that frame, 1.7 cm from
// the spot at 30 fps, skated.
void start_at_arrival(FootContacts& fc, std::span<const Vector3d> ankle,
                      const ContactOptions& options, double fps) {
  const Vector3d up = Vector3d::Unit(static_cast<int>(options.up));
  const int fade = hold_fade_frames(fps);
  const double step = options.speed * fc.leg_length / fps;
  const double low = fc.floor + options.height * fc.leg_length;
  for (std::size_t c = 0; c < fc.intervals.size(); ++c) {
    ContactInterval& in = fc.intervals[c];
    const int earliest = c == 0 ? 0 : fc.intervals[c - 1].last + 1 + fade;
    const int spot = in.first;
    const auto arriving = [&](int f) {
      return floor_distance(ankle, f, spot, up) <= step &&
             ankle[static_cast<std::size_t>(f)].dot(up) <= low;
    };
    while (in.first - 1 >= earliest && arriving(in.first - 1)) --in.first;
  }
}

// contacts_from_shares() with the ankles' paths given.
std::array<FootContacts, 2> shares_contacts(const Skeleton& skeleton, const Motion& motion,
                                            const Feet& feet,
                                            std::span<const std::array<double, 2>> shares,
                                            const ContactOptions& options, const Ankles& ankles) {
  std::array<FootContacts, 2> contacts = detect_contacts(skeleton, motion, feet, ankles, options);
  const int F = motion.num_frames;
  if (shares.size() != static_cast<std::size_t>(F)) {
    throw ParameterError("contacts_from_shares: " + std::to_string(shares.size()) +
                         " contact shares for " + std::to_string(F) + " frames");
  }
  const int gap = frames_at_most(options.gap_seconds, motion.fps());
  const Eigen::Vector3d up = Eigen::Vector3d::Unit(static_cast<int>(options.up));
  for (int s = 0; s < 2; ++s) {
    const FootContacts& fc = contacts[static_cast<std::size_t>(s)];
    const std::vector<Vector3d>& ankle = ankles[static_cast<std::size_t>(s)];
    // In contact: mostly standing samples, and the blended ankle low, as a standing one is.
    const double low = fc.floor + options.height * fc.leg_length;
    std::vector<ContactInterval> runs;
    for (int f = 0; f < F; ++f) {
      // Found by the blended foot's own height and speed, or standing in the samples.
      const bool standing =
          shares[static_cast<std::size_t>(f)][static_cast<std::size_t>(s)] > 0.5 &&
          ankle[static_cast<std::size_t>(f)].dot(up) <= low;
      if (!fc.in_contact(f) && !standing) continue;
      if (!runs.empty() && f - runs.back().last - 1 <= gap) {
        runs.back().last = f;
      } else {
        runs.push_back({f, f});
      }
    }
    FootContacts& out = contacts[static_cast<std::size_t>(s)];
    out.intervals = std::move(runs);
    start_at_arrival(out, ankle, options, motion.fps());
    cut_drifting_contacts(out, ankle, options.up, motion.fps(), options.min_seconds, kMaxHoldDrift);
  }
  return contacts;
}

// Options, motion and feet checked once by each public entry point.
void check_inputs(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                  const CleanFeetOptions& options) {
  options.validate();
  check_motion(skeleton, motion, "clean_feet", MotionCheck::Values);
  for (const Leg& leg : feet.legs) check_leg(skeleton, leg);
  for (int s = 0; s < 2; ++s) {
    const std::vector<double>& h = options.ankle_heights[static_cast<std::size_t>(s)];
    const std::string which = "clean_feet: ankle_heights[" + std::to_string(s) + "]";
    if (!h.empty() && h.size() != static_cast<std::size_t>(motion.num_frames)) {
      throw ParameterError(which + " has " + std::to_string(h.size()) + " values for " +
                           std::to_string(motion.num_frames) +
                           " frames (must be empty or one per frame)");
    }
    for (std::size_t f = 0; f < h.size(); ++f) {
      if (!std::isfinite(h[f]))
        throw ParameterError(which + " at frame " + std::to_string(f) + " is not finite");
    }
  }
}

// clean_feet() of checked inputs and contacts within the motion, the ankles' paths given.
CleanFeetResult clean_checked(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                              const std::array<FootContacts, 2>& contacts,
                              const CleanFeetOptions& options, const Control& control,
                              Ankles ankles) {
  const Control stage = control.stage("cleaning feet", 0.0, 1.0);
  CleanFeetResult result;
  result.motion = motion;
  const int F = motion.num_frames;
  const int J = skeleton.num_joints();
  result.contacts = contacts;
  result.root_drop.assign(static_cast<std::size_t>(F), 0.0);
  result.held.fill(std::vector<char>(static_cast<std::size_t>(F), 0));
  if (F == 0) return result;
  const int blend = static_cast<int>(std::lround(options.blend_seconds * motion.fps()));
  const Vector3d up = Vector3d::Unit(static_cast<int>(options.contacts.up));
  std::vector<char> fixed(static_cast<std::size_t>(F), 0);
  for (const int f : options.fixed_frames) {
    if (f >= 0 && f < F) fixed[static_cast<std::size_t>(f)] = 1;
  }

  // Per foot: original ankle path, target offsets, the knee's hinge axis.
  std::array<FootPlan, 2> plans;
  for (int s = 0; s < 2; ++s) {
    FootPlan& plan = plans[static_cast<std::size_t>(s)];
    plan.leg = feet.legs[static_cast<std::size_t>(s)];
    plan.ankle = std::move(ankles[static_cast<std::size_t>(s)]);
    plan.height = options.ankle_heights[static_cast<std::size_t>(s)];
    if (plan.height.empty()) {
      plan.height.resize(static_cast<std::size_t>(F));
      for (int f = 0; f < F; ++f) plan.height[f] = plan.ankle[f].dot(up);
    }
    plan.length = result.contacts[static_cast<std::size_t>(s)].leg_length;
    plan_offsets(result.contacts[static_cast<std::size_t>(s)], F, blend, fixed, up, plan);
    if (options.keep_above_floor)
      lift_above_floor(result.contacts[static_cast<std::size_t>(s)], fixed, up, plan);
    result.held[static_cast<std::size_t>(s)] = plan.touched;
  }
  // Hinge axes from the input's most bent frame (sampled: ≤ 512 frames).
  {
    std::array<double, 2> best{-1.0, -1.0};
    WorldPose w;
    const int step = std::max(1, F / 512);
    for (int f = 0; f < F; f += step) {
      forward_kinematics(skeleton, motion.pose(f), w);
      for (FootPlan& plan : plans) {
        const Leg& leg = plan.leg;
        const Vector3d t1 = (w.positions[leg.knee] - w.positions[leg.hip]).normalized();
        const Vector3d t2 = (w.positions[leg.ankle] - w.positions[leg.knee]).normalized();
        const Vector3d n = t1.cross(t2);
        double& b = best[plan.leg.side == FootSide::Left ? 0 : 1];
        if (n.norm() > b && n.norm() > 1e-9) {
          b = n.norm();
          plan.hinge_local = parent_world(skeleton, w, leg.knee).conjugate() * n.normalized();
        }
      }
    }
  }
  stage.update(0.1);

  // The motion root, lowered where a target is out of reach: the joint above both hips.
  int root = motion_root(skeleton, motion);
  for (const FootPlan& plan : plans) {
    while (root >= 0 && !is_ancestor(skeleton, root, plan.leg.hip)) {
      root = skeleton.joints[root].parent;
    }
  }
  std::vector<double> need(static_cast<std::size_t>(F), 0.0);
  std::vector<char> capped(static_cast<std::size_t>(F), 0);
  if (root >= 0) {
    parallel_for(F, [&](int f) {
      if (!plans[0].touched[f] && !plans[1].touched[f]) return;
      WorldPose w;
      forward_kinematics(skeleton, motion.pose(f), w);
      double drop = 0.0;
      for (const FootPlan& plan : plans) {
        if (!plan.touched[f]) continue;
        const Vector3d H = w.positions[plan.leg.hip];
        const Vector3d target = plan.ankle[f] + plan.offset[f];
        const double r = std::max(options.reach * plan.length, (plan.ankle[f] - H).norm()) +
                         options.reach_slack * plan.length;
        const Vector3d D = target - H;
        if (D.norm() <= r) continue;
        const double du = D.dot(up);
        const double h2 = std::max(0.0, D.squaredNorm() - du * du);
        double need_f = h2 < r * r ? -std::sqrt(r * r - h2) - du : -du;
        const double cap = options.max_root_drop * plan.length;
        if (h2 >= r * r || need_f > cap) capped[f] = 1;
        drop = std::max(drop, std::clamp(need_f, 0.0, cap));
      }
      need[f] = drop;
    });
  }
  // Widen (running max over ±blend), then smooth (running mean over ±blend): never below need.
  std::vector<double> drop(static_cast<std::size_t>(F), 0.0);
  {
    const int r = std::max(blend, 1);
    std::vector<double> widened(static_cast<std::size_t>(F), 0.0);
    for (int f = 0; f < F; ++f) {
      if (need[f] <= 0.0) continue;
      for (int g = std::max(0, f - r); g <= std::min(F - 1, f + r); ++g) {
        widened[g] = std::max(widened[g], need[f]);
      }
    }
    // A fixed frame stays as given, its root too: the drop fades to 0 over ±blend towards it
    // (where that leaves a target out of reach, the leg reaches as far as it can), so the root
    // never steps at a key.
    std::vector<double> taper(static_cast<std::size_t>(F), 1.0);
    for (const int k : options.fixed_frames) {
      if (k < 0 || k >= F) continue;
      for (int g = std::max(0, k - r); g <= std::min(F - 1, k + r); ++g) {
        taper[g] = std::min(taper[g], static_cast<double>(std::abs(g - k)) / (r + 1));
      }
    }
    for (int f = 0; f < F; ++f) {
      double sum = 0.0;
      for (int g = f - r; g <= f + r; ++g) sum += widened[std::clamp(g, 0, F - 1)];
      drop[f] = taper[f] * sum / (2 * r + 1);
      if (drop[f] < 1e-12 * plans[0].length) drop[f] = 0.0;
      result.root_drop[f] = drop[f];
      result.max_root_drop = std::max(result.max_root_drop, drop[f]);
      result.unreachable_frames += capped[f];
    }
  }
  stage.update(0.2);

  // Per frame: lower the root, solve both legs, restore the ankles' world rotations.
  std::vector<char> changed(static_cast<std::size_t>(F), 0);
  for (int f0 = 0; f0 < F; f0 += kBlockFrames) {
    stage.check();
    const int f1 = std::min(F, f0 + kBlockFrames);
    parallel_for(f1 - f0, [&](int i) {
      const int f = f0 + i;
      const bool lowered = drop[f] > 0.0;
      if (fixed[static_cast<std::size_t>(f)]) return;  // left as given
      if (!lowered && !plans[0].touched[f] && !plans[1].touched[f]) return;
      Quaterniond* q = &result.motion.rotations[static_cast<std::size_t>(f) * J];
      Vector3d* t = &result.motion.translations[static_cast<std::size_t>(f) * J];
      WorldPose w;
      forward_kinematics(skeleton, result.motion.pose(f), w);
      std::array<Quaterniond, 2> ankle_world{w.rotations[plans[0].leg.ankle],
                                             w.rotations[plans[1].leg.ankle]};
      if (lowered) {
        t[root] += parent_world(skeleton, w, root).conjugate() * (-drop[f] * up);
        forward_kinematics(skeleton, result.motion.pose(f), w);
      }
      std::array<bool, 2> solved{false, false};
      for (int s = 0; s < 2; ++s) {
        const FootPlan& plan = plans[static_cast<std::size_t>(s)];
        if (!lowered && !plan.touched[f]) continue;
        const Vector3d target = plan.ankle[f] + plan.offset[f];
        solve_leg(skeleton, w, plan, target, options.reach, q);
        solved[static_cast<std::size_t>(s)] = true;
      }
      forward_kinematics(skeleton, result.motion.pose(f), w);
      for (int s = 0; s < 2; ++s) {
        if (!solved[static_cast<std::size_t>(s)]) continue;
        const int ankle = plans[static_cast<std::size_t>(s)].leg.ankle;
        q[ankle] = (parent_world(skeleton, w, ankle).conjugate() *
                    ankle_world[static_cast<std::size_t>(s)])
                       .normalized();
      }
      changed[f] = 1;
    });
    stage.update(0.2 + 0.8 * static_cast<double>(f1) / F);
  }
  for (char c : changed) result.frames_changed += c;
  result.changed = std::move(changed);
  return result;
}

}  // namespace

void cut_drifting_contacts(FootContacts& contacts, std::span<const Vector3d> ankle, Axis up_axis,
                           double fps, double min_seconds, double max_drift, double keep_within) {
  const Vector3d up = Vector3d::Unit(static_cast<int>(up_axis));
  const int shortest = frames_at_least(min_seconds, fps);
  // A blend can glide (its pose held at the data's edge while the root moves on): a run is
  // cut into pieces over which the ankle stays within max_drift leg lengths of where the
  // piece began on the floor, so no leg is stretched after a foot the body has left behind.
  const double drift = max_drift * contacts.leg_length;
  std::vector<ContactInterval> pieces;
  // After a cut the next piece starts `fade` frames on, so the foot eases from the hold it
  // leaves to the next instead of jumping.
  const int fade = hold_fade_frames(fps);
  for (const ContactInterval& r : contacts.intervals) {
    if (r.first < 0 || r.first > r.last || r.last >= static_cast<int>(ankle.size())) {
      throw ParameterError("contacts: the interval of frames " + std::to_string(r.first) + "-" +
                           std::to_string(r.last) + " is not within the ankle's " +
                           std::to_string(ankle.size()) + " frames");
    }
    if (keep_within > 0.0) {
      double farthest = 0.0;
      for (int f = r.first + 1; f <= r.last; ++f)
        farthest = std::max(farthest, floor_distance(ankle, r.first, f, up));
      if (farthest <= keep_within * contacts.leg_length) {
        pieces.push_back(r);
        continue;
      }
    }
    ContactInterval piece{r.first, r.first};
    for (int f = r.first + 1; f <= r.last; ++f) {
      if (floor_distance(ankle, piece.first, f, up) <= drift) {
        piece.last = f;
        continue;
      }
      pieces.push_back(piece);
      f += fade - 1;
      piece = {f + 1, f + 1};
    }
    if (piece.first <= r.last) pieces.push_back(piece);
  }
  contacts.intervals.clear();
  for (const ContactInterval& p : pieces)
    if (p.frames() >= std::max(1, shortest)) contacts.intervals.push_back(p);
}

CleanFeetResult clean_feet(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                           const CleanFeetOptions& options, const Control& control) {
  check_inputs(skeleton, motion, feet, options);
  Ankles ankles = ankle_paths(skeleton, motion, feet);
  std::array<FootContacts, 2> contacts =
      detect_contacts(skeleton, motion, feet, ankles, options.contacts);
  for (int s = 0; s < 2; ++s) {
    start_at_arrival(contacts[static_cast<std::size_t>(s)], ankles[static_cast<std::size_t>(s)],
                     options.contacts, motion.fps());
  }
  return clean_checked(skeleton, motion, feet, contacts, options, control, std::move(ankles));
}

CleanFeetResult clean_feet(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                           const std::array<FootContacts, 2>& contacts,
                           const CleanFeetOptions& options, const Control& control) {
  check_inputs(skeleton, motion, feet, options);
  const int F = motion.num_frames;
  for (const FootContacts& fc : contacts) {
    for (const ContactInterval& c : fc.intervals) {
      if (c.first < 0 || c.last < c.first || c.last >= F) {
        throw ParameterError("clean_feet: a contact of frames " + std::to_string(c.first) + "–" +
                             std::to_string(c.last) + " is not within the motion's " +
                             std::to_string(F) + " frames");
      }
    }
  }
  return clean_checked(skeleton, motion, feet, contacts, options, control,
                       ankle_paths(skeleton, motion, feet));
}

std::array<FootContacts, 2> contacts_from_shares(const Skeleton& skeleton, const Motion& motion,
                                                 const Feet& feet,
                                                 std::span<const std::array<double, 2>> shares,
                                                 const ContactOptions& options) {
  check_motion(skeleton, motion, "contacts_from_shares", MotionCheck::Sizes);
  return shares_contacts(skeleton, motion, feet, shares, options,
                         ankle_paths(skeleton, motion, feet));
}

CleanFeetResult clean_feet_from_shares(const Skeleton& skeleton, const Motion& motion,
                                       const Feet& feet,
                                       std::span<const std::array<double, 2>> shares,
                                       const CleanFeetOptions& options, const Control& control) {
  check_inputs(skeleton, motion, feet, options);
  Ankles ankles = ankle_paths(skeleton, motion, feet);
  const std::array<FootContacts, 2> contacts =
      shares_contacts(skeleton, motion, feet, shares, options.contacts, ankles);
  return clean_checked(skeleton, motion, feet, contacts, options, control, std::move(ankles));
}

std::string unreachable_feet_note(const CleanFeetResult& result, std::string_view part) {
  if (result.unreachable_frames <= 0) return {};
  return "feet: in " + std::to_string(result.unreachable_frames) + " frames" +
         (part.empty() ? std::string() : " of " + std::string(part)) +
         " a planted foot stayed out of the leg's reach (the root is lowered by at most a quarter "
         "of the leg)";
}

}  // namespace motionmap::synth
