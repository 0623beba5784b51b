#pragma once
// Contact clean-up: feet that stay planted while they are on the floor. A blended motion's feet
// slide (the blend of several stances is no stance); this finds each foot's contacts and holds
// its ankle still through each, bending the leg to reach.
//
//   const motionmap::Feet feet = motionmap::find_feet(skeleton);
//   motionmap::synth::CleanFeetResult r = motionmap::synth::clean_feet(skeleton, motion, feet);
//   // r.motion: the cleaned motion; r.contacts: each foot's contact intervals
//
// Method (docs/synthesis.md, "Clean feet"):
//  1. Contacts per foot: detect_contacts() (skeleton/contacts.h) with `contacts`, each started
//     where its foot arrives: extended back over the frames before it (from kHoldFadeSeconds after
//     the foot's previous contact) whose ankle is as low as a standing one and lies, on the floor,
//     within one frame's contact speed (contacts.speed) of where the contact's first frame has
//     it. detect_contacts() takes each frame's speed over a few frames, which leaves out the
//     frame a landing foot reaches its spot from (a blend of two runs, which lands a foot over
//     one frame more than the runs do, skated there). Contacts given to clean_feet() are held as
//     given.
//  2. Targets: through a contact the ankle is held at the mean of its places over the contact,
//     at the floor height of its heights there (of ankle_heights, when given): their lower
//     envelope, which comes down with them as they make new lows up to their lowest frame (a heel
//     strike) and goes up with them after it (heel-off), level where they rise and fall back; so
//     the foot stands still while the ankle settles, and stands on the floor, not above it.
//     Fixed frames in a contact: see fixed_frames.
//     Around it, the displacement that needs at the contact's first (last) frame, held − original,
//     is added to the ankle's own path with a weight falling from 1 at the contact to 0 over
//     `blend_seconds` before (after) it (smoothstep, 1 − (3x² − 2x³), x = frames away ÷ (blend
//     frames + 1)), so the foot keeps its own motion and drifts onto the held spot; between two
//     contacts closer than that the two add, normalised where their weights sum past 1. Frames
//     farther from every contact are left as they are, bit for bit. Towards a fixed frame outside
//     the contacts the displacement (a hold's too) fades to nothing over ±blend frames, by the
//     same smoothstep, so the frame, left as given, is not a step.
//     With keep_above_floor (in-betweening), an ankle more than kFloorSlack leg lengths below the
//     floor is lifted to that depth (see the option).
//  3. Reach: where a target is farther from the hip than `reach` × the leg length (and farther
//     than the original ankle was) by more than `reach_slack` × the leg length, the root (the
//     motion root, synth's blender root) is lowered along the up axis just enough to bring it
//     within that (the leg then reaches as far as it goes); the lowering is widened (a running
//     maximum over ±blend frames) and then smoothed (a running mean over ±blend frames), so it is
//     never less than needed and has no steps. Where the root is lowered, every foot is held at its
//     own position (contact or not), so only the legs bend to absorb it.
//  4. Two-bone IK per leg (hip–knee–ankle), analytic: the knee angle from the law of cosines,
//     bent about the knee's own hinge axis (the thigh × shin normal of the frame; for a leg
//     straighter than 5°, the axis of the input's most bent frame, carried by the thigh), so the
//     knee stays in its plane and never bends backwards (the angle is 0…180° towards the
//     side the knee bends in the input); then the leg is swung at the hip by the smallest
//     rotation that takes the ankle onto the target (no twist about the leg).
//  5. The ankle's world rotation is restored to the original's, so the foot keeps its roll and
//     everything below the ankle (toes) follows it rigidly.
// Polls `control` between blocks of frames; reports the stage through it.
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::synth {

struct CleanFeetOptions {
  /// Contact detection (contacts.up is the up axis of everything here).
  ContactOptions contacts;
  /// Seconds over which a contact's correction fades in before it and out after it, in [0, 2];
  /// 0: the correction stops at the contact's ends.
  double blend_seconds = 0.15;
  /// Most a leg is straightened to reach a target, × its length (hip–knee + knee–ankle), in
  /// [0.5, 1): beyond it the root is lowered.
  double reach = 0.995;
  /// Most the root is lowered, × the leg length, in [0, 1].
  double max_root_drop = 0.25;
  /// How far out of reach a target may be, × the leg length, in [0, 0.5], before the root is
  /// lowered: within it the leg reaches as far as it goes and the foot stops short by at most
  /// that; beyond it the root is lowered by what lies beyond. Lowering the root bends the other
  /// leg too (a foot just out of its contact, held where it is, bent its knee 21° when the hips
  /// dropped 3.9 cm to save a landing foot 1.6 cm of reach: docs/synthesis.md).
  double reach_slack = 0.01;
  /// Frames whose pose must stay exactly as given (in-betweening's keys): a contact holding
  /// one holds the ankle where that frame has it rather than at the contact's mean — between two
  /// such frames on the straight line from one's place to the other's, before the first at the
  /// first's, after the last at the last's (at the floor height of the ankle's own heights from
  /// the contact's start to that frame, from it to the end) — and the frame itself is left bit
  /// for bit; towards one outside the contacts the displacement fades to nothing over
  /// ±blend_seconds (a contact cut the frame before an in-between's key held an ankle 1 m from
  /// the key's, which snapped there). Any order; out of range ignored.
  std::vector<int> fixed_frames;
  /// Per foot (left, right), empty or one value per frame: the ankle heights (along contacts.up,
  /// file units) a contact without a fixed frame is held at (their floor height, see the top of
  /// the file), instead of the motion's own. In-betweening passes its blend's, from before the
  /// keys' displacement map: spread over a segment, that map tilts a stance, lifting a planted
  /// foot by a few cm at one end.
  std::array<std::vector<double>, 2> ankle_heights;
  /// Keep every ankle (but a fixed frame's) above the floor, contact or not: one more than
  /// kFloorSlack leg lengths below the floor — the lowest median height of its foot's contacts
  /// without a fixed frame — is lifted to that depth, the leg bent to reach (a foot without such a
  /// contact is left as it is: over a short in-between it may never touch the floor). In-betweening
  /// sets it: its keys' displacement map, spread over a segment, can push a foot into the floor (a
  /// walk's in-between to a punch's key pushed an ankle 6.3 cm into it, 2.6 cm with its contacts
  /// held).
  bool keep_above_floor = false;

  /// @throws ParameterError naming the field (contacts.height, …), its value and its range.
  void validate() const;
};

struct CleanFeetResult {
  Motion motion;                         ///< the cleaned motion (same frames, joints, timing)
  std::array<FootContacts, 2> contacts;  ///< left, right: what was held
  int frames_changed = 0;                ///< frames where any joint changed
  /// Per frame: 1 where the clean-up changed the frame (frames_changed counts them); elsewhere the
  /// frame is the input's, bit for bit.
  std::vector<char> changed;
  double max_root_drop = 0.0;  ///< file units, 0 when the root was never lowered
  /// Frames where a target stayed out of reach by more than reach_slack.
  int unreachable_frames = 0;
  /// Per frame: how far the root was lowered (file units, ≥ 0).
  std::vector<double> root_drop;
  /// Per foot (left, right) and frame: 1 where the foot was moved to a target (a contact or its
  /// fade in or out, or lifted by keep_above_floor). A leg is solved where its foot is held or the
  /// root is lowered; elsewhere its joints are the input's, bit for bit.
  std::array<std::vector<char>, 2> held;
};

/// The motion of `skeleton` with its feet held through their contacts (see the top of the file).
/// `feet` from find_feet(skeleton). Deterministic: the same input gives the same output bits.
/// @throws ParameterError for bad options, a motion that does not fit the skeleton, or feet not
///         of it; Cancelled if `control` says so.
CleanFeetResult clean_feet(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                           const CleanFeetOptions& options = {}, const Control& control = {});

/// The same with the contacts given (options.contacts is then not used to find them): e.g.
/// contacts_from_shares() of a synthesized motion, whose blended feet slide too fast to be found
/// by their speed. @throws as above, and ParameterError for intervals out of range.
CleanFeetResult clean_feet(const Skeleton& skeleton, const Motion& motion, const Feet& feet,
                           const std::array<FootContacts, 2>& contacts,
                           const CleanFeetOptions& options = {}, const Control& control = {});

/// clean_feet() with the contacts of contacts_from_shares(skeleton, motion, feet, shares,
/// options.contacts), the inputs checked and each ankle's path computed once for both (what
/// synthesize() and edit_path() do). @throws as both.
CleanFeetResult clean_feet_from_shares(const Skeleton& skeleton, const Motion& motion,
                                       const Feet& feet,
                                       std::span<const std::array<double, 2>> shares,
                                       const CleanFeetOptions& options = {},
                                       const Control& control = {});

/// The note a clean-up that left planted feet out of reach adds to its motion's notes ("feet: in
/// N frames[ of `part`] a planted foot stayed out of the leg's reach …"); empty when it left none.
std::string unreachable_feet_note(const CleanFeetResult& result, std::string_view part = {});

/// How far (× the leg length) an ankle may stand below the floor before keep_above_floor lifts it.
inline constexpr double kFloorSlack = 0.02;

/// How far (× the leg length, on the floor) a blended ankle may drift from where a contact began
/// before contacts_from_shares() ends that contact and starts another.
inline constexpr double kMaxHoldDrift = 0.25;
/// Frames (in seconds) left free between two such pieces, for the foot to ease from one hold to
/// the next.
inline constexpr double kHoldFadeSeconds = 0.15;

/// Cuts each contact into pieces over which the ankle (`ankle`: its position per frame) stays
/// within max_drift leg lengths of where the piece began on the floor, the next piece starting
/// kHoldFadeSeconds later; a contact over which it stays within keep_within leg lengths of its
/// first frame is left whole. Pieces shorter than min_seconds are dropped. A blend can glide (a
/// pose held while the root moves on), and a hold there stretches the leg after a foot left
/// behind. @throws ParameterError if an interval is empty or not within the ankle's frames.
void cut_drifting_contacts(FootContacts& contacts, std::span<const Eigen::Vector3d> ankle, Axis up,
                           double fps, double min_seconds, double max_drift,
                           double keep_within = 0.0);

/// The contacts of a blended motion from its blend weights as well as its own feet: foot s is on
/// the floor in frame f when detect_contacts() finds it there, or when more than half of that
/// frame's blend weight is on samples whose foot s is (shares[f][s] > 0.5,
/// MapBlender::contact_share) and its ankle is as low as a standing one (within options.height
/// leg lengths of the foot's floor level). A run over which the ankle drifts more
/// than kMaxHoldDrift leg lengths on the floor is cut where it does (a blend gliding at the
/// data's edge would otherwise stretch the leg after a foot left behind). Runs shorter than
/// options.min_seconds are dropped and gaps shorter than options.gap_seconds filled, as
/// detect_contacts() does, and each starts where its foot arrives, as clean_feet() starts the
/// contacts it finds (see the top of the file); the legs, lengths and floor levels are
/// detect_contacts()'s of the motion. `shares`: one per frame of `motion`.
/// @throws ParameterError if the sizes differ or the motion does not fit the skeleton.
std::array<FootContacts, 2> contacts_from_shares(const Skeleton& skeleton, const Motion& motion,
                                                 const Feet& feet,
                                                 std::span<const std::array<double, 2>> shares,
                                                 const ContactOptions& options = {});

}  // namespace motionmap::synth
