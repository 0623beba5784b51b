#pragma once
// Gait phase, and the registration of a path's blends to one phase (MapBlender::locate_path;
// docs/synthesis.md, "Gait phase").
//
// A clip's gait phase counts its left foot's strikes (the starts of its contacts, detect_contacts;
// a contact already under way at the clip's first frame is no strike) over its longest run of gait
// cycles: consecutive left strikes at most kMaxCycleSeconds apart with a right strike between them.
// 0 at the run's first strike, 1 at the second, …; ½ (1½, …) at the right foot's first strike
// between them, linear in time within each half cycle; continued at the first (last) cycle's rate
// before (after) them. A clip with fewer than kMinCycles such cycles in a row has no phase (a golf
// swing, a bow, a few shuffled steps). (Linear over whole cycles, two takes blended at one phase
// landed their right feet apart where one's right strike falls earlier in its cycle than the
// other's: the angry run drawn halfway to the old one slid 143 cm/s in contact, cleaned, against
// 132 with the halves registered.)
//
// A path frame's blend (locate_path) is a sum of sources: clip times with weights (the samples the
// local kriging weighs, and the clip times the path follows). The map puts near each other frames
// that look alike, and the kriging's neighbours are often at different phases of the gait (other
// cycles of the take, another take): blended as they are, a left stance is mixed with a right one
// and the feet slide; and where the heavier sources change from one phase to another along the
// path, the legs jump. Registered (after Kovar & Gleicher's registration curves), per frame k:
//  - Each frame j has a lead phase ψ_j (its sources' mean phase on the circle, by |weight|), how
//    clearly they agree c_j (that mean's length, 0–1) and a cadence ω_j (its sources' phase
//    rates, by |weight|: cycles per second).
//  - φ_k: the frames j within kPhaseWindowSeconds of k give r_j = ψ_j − ∫_k^j ω, weighted by c_j
//    and a triangle falling to 0 at the window's ends; their mean on the circle, then a line
//    fitted to them about it (weighted least squares in time), read at k. Within the window the
//    phase advances at the clips' own cadence, over longer spans it follows where the path leads.
//    A path along one clip at any steady pace gives its own phase back, at the path's ends too,
//    where the window is cut short.
//  - Each source with a phase is moved, in its own cycle, to within kPhaseBand of φ_k (the time of
//    that phase, kept inside its run). One nearly half a cycle off shares its weight with the
//    other cycle's time, half and half at half a cycle, where the nearest flips.
//  - The frame's blend is the moved sources' by h and the sources as they were by 1 − h, h
//    rising from 0 to 1 as the mean that gave φ_k (its length, by those weights) grows from
//    kPhaseVague to twice that: where the window's leads cancel out, nothing is moved. (Measured
//    about the fitted line instead, h registered frames whose leads stall, and legs held
//    mid-swing for up to a second between two walks or two runs: the leads are no sure guide
//    to the phase where they do not move at the cadence.)
//  - The blend's root moves on at the pace its legs play the gait at (pace(): how fast φ advances
//    against the cadence), so a step carries it as far as the clips' steps carry theirs. (The
//    root's velocity is the samples' own: where the path dwelt, legs held at one phase glided on
//    with it. Halfway between the proud and the angry walk the feet slid 141 cm/s in contact,
//    98 cleaned, against the capture's 44; at the legs' pace 75 and 54.)
//  - Each run's share of the frame (the sum of its sources' weights) becomes the mean of its
//    shares over the frames within kShareSeconds (a triangle), scaled to the frame's own total
//    on runs with a phase; what a run gains or loses is added at its time of φ_k by h (in the
//    cycle nearest its heaviest source at the nearest frame on it) and by 1 − h at that source's
//    phase carried on at the cadence. Between two takes the kriging moves its weight from one
//    take's samples to the other's within a frame, at the same phase but in another style: a
//    joint stepped up to 69 cm in a frame between two runs (their captures' largest step 21–25).
//  - lead_pace(): where h < ½ the legs play the sources' own leads, and how fast those move on
//    (their steps over kLeadPaceSeconds either side, against the cadence) tells where they
//    stall: a path between two runs' curves held one phase for 10–20 frames while the path
//    moved on, then flipped to another (detail/outside_route.h routes such stretches). Leads
//    that jump about instead (their median step over kLeadJumpy times the cadence's) are a mix
//    of phases, not legs held, and get none: on the synthetic random-walk bench map nearly half
//    the frames' leads summed to less than half the cadence that way, and routing them made a
//    10 s synthesis 8 times slower and an edit re-make the whole take.
// Sources without a phase keep their times and weights. A frame's registration reads the frames
// within kPhaseWindowSeconds of it (phase_window()); its pace those of its neighbours too
// (pace_window()).
#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "motionmap/skeleton/contacts.h"

namespace motionmap::synth::detail {

/// A gait cycle is at most this long; a clip has a phase with at least this many in a row.
inline constexpr double kMaxCycleSeconds = 2.5;
inline constexpr int kMinCycles = 2;
/// The registration's constants (see the top): seconds, cycles, a mean's length.
inline constexpr double kPhaseWindowSeconds = 0.5;
inline constexpr double kPhaseBand = 0.02;
inline constexpr double kPhaseSplit = 0.3;
inline constexpr double kPhaseVague = 0.2;
/// A frame's share of each run is the mean of its shares over this many seconds either side
/// (see the top); changes smaller than kShareTolerance are left out.
inline constexpr double kShareSeconds = 0.15;
inline constexpr double kShareTolerance = 1e-9;
/// PhaseFrame::lead_pace reads the leads this many seconds either side (at most
/// kPhaseWindowSeconds).
inline constexpr double kLeadPaceSeconds = 0.2;
/// … and has none where the leads' median step is over this many times the cadence's.
inline constexpr double kLeadJumpy = 2.0;

/// One clip's gait phase, in seconds from the start of one run of its samples (see the top).
struct GaitPhase {
  /// The left foot's strikes, seconds into the run (increasing; may lie outside [0, duration]).
  std::vector<double> strikes;
  /// The right foot's first strike after each left one but the last (empty: phase linear over
  /// whole cycles); phase ½ of its cycle.
  std::vector<double> right;
  /// The run's length in seconds (its first sample to its last).
  double duration = 0.0;

  /// Whether the clip has a phase (two strikes or more).
  bool known() const { return strikes.size() >= 2; }
  /// The phase at `seconds` (cycles, not wrapped); `rate`, if given: its derivative (cycles/s).
  double at(double seconds, double* rate = nullptr) const;
  /// The time whose phase is `phase` (the inverse of at()).
  double time_at(double phase) const;
  /// The time of `phase` (time_at()), moved by whole cycles towards [0, duration] while outside
  /// it, then clamped to it.
  double time_inside(double phase) const;
};

/// The gait phase of a clip whose feet's contacts (left, right) are `contacts`, in seconds from
/// its frame `start` (frame_time apart), for a run of its samples `duration` seconds long.
GaitPhase gait_phase(const std::array<FootContacts, 2>& contacts, double frame_time, int start,
                     double duration);

/// A part of a path frame's blend: clip time `seconds` of the run starting at sample `run`, with
/// `weight` (kriging weights may be negative); `sample`: the sample at that time, if it is one's
/// (−1: between samples, or moved).
struct PhaseSource {
  int run = 0;
  double seconds = 0.0, weight = 0.0;
  int sample = -1;
};
/// A path frame's sources; `moved` once register_phases() changed them. register_phases() also
/// records the phase φ it registered the frame to (NaN where it read none), the frame's cadence
/// (cycles per second) and how far it moved the sources to φ (h, 0–1).
struct PhaseFrame {
  std::vector<PhaseSource> sources;
  bool moved = false;
  double phase = std::numeric_limits<double>::quiet_NaN();
  double cadence = 0.0, registered = 0.0;
  /// How fast the frame's sources' lead phase ψ, as located, moves on against the cadence: the
  /// sum of its steps over the frames within kLeadPaceSeconds either side, in [0, kMaxPace]; NaN
  /// where the sources have no phase, or where ψ jumps about (its median step over kLeadJumpy
  /// times the cadence's: the sources a mix of phases, not legs held).
  double lead_pace = std::numeric_limits<double>::quiet_NaN();
};

using PhaseOf = std::function<const GaitPhase&(int run)>;

/// The frames either side of a frame its registration reads, for frames dt seconds apart.
int phase_window(double dt);

/// How fast frame k of `frames` (registered: register_phases()) moves on against its sources' own
/// pace: (φ_{k+d} − φ_{k−d}) / (2d·cadence·dt), d = kPaceFrames (one-sided where a neighbour has
/// no φ), in [0, kMaxPace], mixed towards 1 as the registration's h falls to 0; 1 where the
/// frame has no φ. The blend's root moves that much slower or faster (MapWeights::pace), so that
/// its legs, playing the gait at φ, carry it a step as long as the clips' (a path that dwells
/// where a gait's samples sit barely moves on, rather than gliding with its legs held).
double pace(std::span<const PhaseFrame> frames, std::size_t k, double dt);
/// How fast the legs of frame k of `frames` (registered: register_phases()) move on where its
/// phase could not be registered (h < ½): its lead_pace, the sources' own phase playing on; 1
/// where it was, or where its sources have no phase. Where the leads stall while the path moves
/// on the blend holds its legs as they do (detail/outside_route.h).
double lead_pace(std::span<const PhaseFrame> frames, std::size_t k);
/// pace()'s d: the frames either side whose phases it differences.
inline constexpr std::size_t kPaceFrames = 1;
/// The fastest pace (the fitted clip times play at most kFollowMaxRate = 2).
inline constexpr double kMaxPace = 2.0;
/// The frames either side of a frame pace() reads, the registrations of its neighbours included.
int pace_window(double dt);

/// Registers frames [first, end) of `frames` (consecutive path frames dt apart; those around them,
/// up to phase_window(dt) either side where the path has them, are read only) as the top of the
/// file says, in place.
void register_phases(std::span<PhaseFrame> frames, std::size_t first, std::size_t end, double dt,
                     const PhaseOf& phase_of);

}  // namespace motionmap::synth::detail
