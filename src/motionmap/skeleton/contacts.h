#pragma once
// Feet: which joints they are, the skeleton's length unit, when each foot is on the floor, and how
// much the feet skate. The clean-up of synthesized motion (synth/clean_feet.h), `motionmap info
// --contacts/--skating` and the tests use these.
//
//   const motionmap::Feet feet = motionmap::find_feet(clip.skeleton);   // throws if none
//   const motionmap::LengthUnits units = motionmap::detect_length_units(clip.skeleton,
//   clip.motion); auto contacts = motionmap::detect_contacts(clip.skeleton, clip.motion, feet);
//   const motionmap::Skating s = motionmap::measure_skating(clip.skeleton, clip.motion, feet,
//   units);
//   // s.ratio: fraction of frame transitions where a foot skates; s.contact_speed_cm_s
//
// FINDING THE FEET (find_feet). Per side, the ankle, the toe, and the leg above the ankle:
//  1. By name. A joint name is cut into words: what follows the last ':' or '|' (Mixamo's
//     "mixamorig:"), split at '_', '-', '.', spaces, lower→upper case changes and letter↔digit
//     changes, compared ignoring case. The side is a word "left"/"l" or "right"/"r", or such a
//     prefix glued to the part ("lfoot", "LeftFoot" in lower case). The part is what remains,
//     joined: "foot" or "ankle" is an ankle; "toe", "toes", "toebase" or "ball" a toe. So
//     CMU's LeftFoot/LeftToeBase, Bandai Namco's Foot_L/Toes_L, Acclaim's lfoot/ltoes,
//     Mixamo's mixamorig:LeftFoot, MocapBank's LeftAnkle are found; "LeftToe_End" and
//     "LeftFootIndex1" are not. The first such ankle of each side (joint order) is its ankle.
//  2. By hierarchy, when names do not give an ankle on both sides: the leaf chains, each joint
//     without children followed up to (not including) the first joint with several children or
//     no parent, joints at their parent's position (zero offsets, CMU's LHipJoint) not
//     counted. Chains of at least 3 joints are legs; the two whose leaf is lowest in the rest
//     pose (every rotation identity) along `up` are taken. A chain of 4 or more ends in a toe
//     (the ankle is its parent), one of 3 in the ankle. The leg whose ankle has the larger rest
//     X coordinate is the left one (BVH convention: Y up, facing +Z, the subject's left on +X).
//  The knee is the nearest ancestor of the ankle at a distance from it, the hip the nearest
//  ancestor of the knee at a distance from it (in the rest pose: joints with zero offsets are
//  skipped). The toe is the ankle's child named as a toe, else its first child at a distance,
//  else none (−1). The two legs must not share a hip, knee or ankle.
//
// LENGTH UNITS (detect_length_units). The size of the body: per frame, the largest extent along
// a coordinate axis of the motion root (motion_root()) and every joint and End Site below it
// (standing: the height; in a T-pose: the arm span; lying: the length), and its 90th percentile
// over (up to 256 evenly spread) frames; the rest pose when the motion has no frame. The unit is
// the one that makes that size nearest, by ratio, to 1.6 m: the size in units is compared with the
// geometric means of neighbouring units' 1.6 m: m below 6.7, CMU units (1/0.45 inch = 5.644 cm: the
// CMU ASF/AMC and its BVH conversions) below 42.2, inches below 100.4, cm below 506, else mm.
// `plausible` says whether the size is 0.8–2.6 m in the unit chosen (a human body).
//
// CONTACTS (detect_contacts), for the clean-up: a foot is on the floor in frame f when its ankle
// is within `height` × the leg length of its floor level (the 2 % quantile of the ankle's height
// over the clip, robust to a few bad frames), and its velocity (central difference over
// ±⌈fps/60⌉ frames, frames_at_least(): 2 at BVH's 120.0005 fps) is below `speed` × the leg length
// per second horizontally and below `vertical_speed` × the leg length per second up or down (a heel
// rising slowly is leaving); gaps of at most `gap_seconds` between such frames are filled, then
// runs shorter than `min_seconds` dropped. The leg length is |hip − knee| + |knee − ankle|.
// Thresholds thus scale with the skeleton's size and the frame rate; the defaults (6 % of the leg,
// 1 and 0.1 legs/s, 0.05 s, 0.05 s) were set on Bandai Namco walks, against hand-labelled contacts
// (docs/synthesis.md) and on blended walks, whose stance feet slide.
//
// THE SKATING MEASURE (measure_skating), after Karunratanakul et al., "Guided Motion Diffusion"
// (ICCV 2023): a foot (its ankle joint) is in contact across the transition from frame f to f+1
// when in both frames it is less than 5 cm above the lowest point that ankle reaches in the
// clip; it skates when, in contact, its horizontal speed (distance between the two frames ÷
// frame time) exceeds 0.5 m/s. The skating ratio is the fraction of frame transitions in which
// either foot skates; contact_speed_cm_s is the mean horizontal speed of the feet over their
// contact transitions (each foot's counted separately), in cm/s. A foot held up never skates, so
// the measure also reports longest_raised_s: the longest either ankle stays 5 cm or more above
// its lowest point, in seconds (a leg held mid-swing scores well on the ratio alone). Lengths are
// converted with the units given (detect_length_units() by default).
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap {

enum class FootSide { Left, Right };
/// "left" / "right".
std::string_view foot_side_name(FootSide side);

/// One leg, joint indices from the hip down.
struct Leg {
  FootSide side = FootSide::Left;
  int hip = -1;    ///< rotates the thigh: UpperLeg_L, LeftUpLeg, lfemur
  int knee = -1;   ///< rotates the shin: LowerLeg_L, LeftLeg, ltibia
  int ankle = -1;  ///< Foot_L, LeftFoot, lfoot, LeftAnkle
  int toe = -1;    ///< Toes_L, LeftToeBase, ltoes; −1 when the ankle has no joint below it
};

struct Feet {
  std::array<Leg, 2> legs;  ///< left, then right
  bool by_name = true;      ///< false: found from the hierarchy (leaf chains), see above
};

/// The feet of `skeleton` (see the top of the file), or nothing; `why` (if given) then receives
/// the reason. `up`: the rest pose's up axis, for the hierarchy rule.
std::optional<Feet> try_find_feet(const Skeleton& skeleton, Axis up = Axis::Y,
                                  std::string* why = nullptr);
/// The feet of `skeleton`. @throws ParameterError "no feet found: …" naming what was looked for.
Feet find_feet(const Skeleton& skeleton, Axis up = Axis::Y);

enum class LengthUnit { Metre, CmuUnit, Inch, Centimetre, Millimetre };
/// "m", "CMU units (1/0.45 in)", "in", "cm", "mm".
std::string_view length_unit_name(LengthUnit unit);
/// Metres per unit: 1, 0.0254/0.45, 0.0254, 0.01, 0.001.
double metres_per_unit(LengthUnit unit);

struct LengthUnits {
  LengthUnit unit = LengthUnit::Centimetre;
  double metres_per_unit = 0.01;
  double size = 0.0;       ///< the body's size the unit was chosen from, in file units (see above)
  bool plausible = false;  ///< size × metres_per_unit is 0.8–2.6 m
};
/// The length unit of `motion` of `skeleton` (see the top of the file).
/// @throws ParameterError or NumericalError if check_motion (MotionCheck::Sizes) fails.
LengthUnits detect_length_units(const Skeleton& skeleton, const Motion& motion);

/// Frames first…last (inclusive) of a contact.
struct ContactInterval {
  int first = 0;
  int last = 0;
  int frames() const { return last - first + 1; }
  bool operator==(const ContactInterval&) const = default;
};

struct ContactOptions {
  double height = 0.06;         ///< × leg length above the ankle's floor level, in (0, 1]
  double speed = 1.0;           ///< × leg length per second, horizontal, in (0, 100]
  double vertical_speed = 0.1;  ///< × leg length per second, up or down, in (0, 100]
  double gap_seconds = 0.05;    ///< shorter gaps between contact frames are filled, in [0, 10]
  double min_seconds = 0.05;    ///< shorter contacts are dropped, in [0, 10]
  Axis up = Axis::Y;

  /// @throws ParameterError naming the field, its value and its range.
  void validate() const;
};

struct FootContacts {
  Leg leg;
  double floor = 0.0;                      ///< the ankle's floor level along `up` (file units)
  double leg_length = 0.0;                 ///< |hip − knee| + |knee − ankle| (file units)
  std::vector<ContactInterval> intervals;  ///< increasing, disjoint
  /// Whether frame f lies in a contact.
  bool in_contact(int frame) const;
};

/// The contacts of each foot (left, right) of `motion` (see the top of the file).
/// @throws ParameterError for bad options or a motion that does not fit the skeleton.
std::array<FootContacts, 2> detect_contacts(const Skeleton& skeleton, const Motion& motion,
                                            const Feet& feet, const ContactOptions& options = {});

/// Each leg's ankle path (left, right): joint_trajectory() of feet.legs[s].ankle.
using AnklePaths = std::array<std::vector<Eigen::Vector3d>, 2>;
AnklePaths ankle_paths(const Skeleton& skeleton, const Motion& motion, const Feet& feet);

/// detect_contacts() with the ankles' paths given (ankle_paths() of the same motion), for a caller
/// that needs them too (synth::clean_feet: computed once for both). The same contacts.
/// @throws as above, and ParameterError if a path has not one point per frame.
std::array<FootContacts, 2> detect_contacts(const Skeleton& skeleton, const Motion& motion,
                                            const Feet& feet, const AnklePaths& ankles,
                                            const ContactOptions& options = {});

struct Skating {
  double ratio = 0.0;  ///< skating transitions ÷ transitions (0 with fewer than 2 frames)
  double contact_speed_cm_s = 0.0;  ///< mean horizontal ankle speed in contact; NaN if never
  int transitions = 0;              ///< #frames − 1
  int skating_transitions = 0;      ///< transitions where either foot skates
  int contact_transitions = 0;      ///< (foot, transition) pairs in contact
  /// The longest run of frames in which an ankle is at or above the contact line (5 cm over its
  /// lowest point), × the frame time; 0 when neither ever is.
  double longest_raised_s = 0.0;
  LengthUnits units;  ///< the units the measure used
};

/// Contact height and skating speed of the measure (Karunratanakul et al. 2023).
inline constexpr double kSkatingContactHeightM = 0.05;
inline constexpr double kSkatingSpeedMPerS = 0.5;

/// The skating measure of `motion` (see the top of the file), lengths in `units`.
/// @throws ParameterError if the motion does not fit the skeleton.
Skating measure_skating(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                        const LengthUnits& units, Axis up = Axis::Y);
/// The same with detect_length_units(skeleton, motion).
Skating measure_skating(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                        Axis up = Axis::Y);

/// The world positions of `joint` in every frame (forward kinematics of its chain only).
std::vector<Eigen::Vector3d> joint_trajectory(const Skeleton& skeleton, const Motion& motion,
                                              int joint);

}  // namespace motionmap
