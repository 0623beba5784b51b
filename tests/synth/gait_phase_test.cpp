// Gait phase and its registration (synth/detail/gait_phase.h): the phase's arithmetic, which
// clips have one (the shared Bandai walks and runs; not a golf swing), and what the registration
// does to a path's sources: takes at different phases lined up, continuously, one clip played at
// its own pace left as it is, each take's share crossing over smoothly; the pace at which the
// root moves on with the registered legs, and how fast the leads move where none are.
#include "motionmap/synth/detail/gait_phase.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "motionmap/io/load.h"
#include "motionmap/skeleton/contacts.h"
#include "support/test_data.h"

namespace motionmap::synth::detail {
namespace {

double wrapped(double x) {
  return x - std::round(x);
}

// Frame k's clip time, 3 s into a take, frames dt apart.
double t_of(std::size_t k, double dt) {
  return 3.0 + static_cast<double>(k) * dt;
}

// A clip's contacts: the left foot's starting at `left`, the right foot's at `right`, each
// 10 frames long.
std::array<FootContacts, 2> contacts(const std::vector<int>& left, const std::vector<int>& right) {
  std::array<FootContacts, 2> out;
  for (const int f : left) out[0].intervals.push_back({f, f + 10});
  for (const int f : right) out[1].intervals.push_back({f, f + 10});
  return out;
}

TEST(SynthGaitPhase, CountsTheLeftFootsStrikesAndContinuesPastThem) {
  GaitPhase p;
  p.strikes = {0.5, 1.5, 2.3};
  p.duration = 3.0;
  double rate = 0.0;
  EXPECT_DOUBLE_EQ(p.at(1.0, &rate), 0.5);
  EXPECT_DOUBLE_EQ(rate, 1.0);
  EXPECT_DOUBLE_EQ(p.at(1.9, &rate), 1.5);
  EXPECT_DOUBLE_EQ(rate, 1.25);
  // Before the first strike and after the last, at the nearest cycle's rate.
  EXPECT_DOUBLE_EQ(p.at(0.0), -0.5);
  EXPECT_DOUBLE_EQ(p.at(2.7), 2.5);
  for (const double t : {0.0, 0.7, 1.5, 2.0, 2.9}) EXPECT_NEAR(p.time_at(p.at(t)), t, 1e-12);
  // Times outside the run are moved by whole cycles into it, then clamped.
  EXPECT_DOUBLE_EQ(p.time_inside(-1.0), 0.5);              // −0.5 s, a cycle on
  EXPECT_DOUBLE_EQ(p.time_inside(-0.9), 0.6);              // −0.4 s, a cycle on
  EXPECT_DOUBLE_EQ(p.time_inside(3.25), p.time_at(2.25));  // 3.1 s, a cycle back
  GaitPhase short_run = p;
  short_run.duration = 0.3;  // no cycle fits: clamped
  EXPECT_DOUBLE_EQ(short_run.time_inside(-0.9), 0.0);
  EXPECT_DOUBLE_EQ(short_run.time_inside(0.2), 0.3);
}

// With the right foot's strikes, each half cycle is linear on its own: a right strike is phase ½
// however far into its cycle it lands, so two takes blended at one phase land both feet together.
TEST(SynthGaitPhase, TheRightFootsStrikeIsHalfACycle) {
  GaitPhase p;
  p.strikes = {0.5, 1.5, 2.3};
  p.right = {0.9, 2.1};  // 0.4 of the first cycle, 0.75 of the second
  p.duration = 3.0;
  double rate = 0.0;
  EXPECT_DOUBLE_EQ(p.at(0.9, &rate), 0.5);
  EXPECT_DOUBLE_EQ(p.at(0.7, &rate), 0.25);
  EXPECT_DOUBLE_EQ(rate, 0.5 / 0.4);
  EXPECT_DOUBLE_EQ(p.at(1.2, &rate), 0.75);
  EXPECT_DOUBLE_EQ(rate, 0.5 / 0.6);
  EXPECT_DOUBLE_EQ(p.at(2.1), 1.5);
  EXPECT_NEAR(p.at(2.2, &rate), 1.75, 1e-12);
  EXPECT_NEAR(rate, 0.5 / 0.2, 1e-12);
  // Before the first strike and after the last, at the nearest whole cycle's rate.
  EXPECT_DOUBLE_EQ(p.at(0.0, &rate), -0.5);
  EXPECT_DOUBLE_EQ(rate, 1.0);
  EXPECT_DOUBLE_EQ(p.at(2.7), 2.5);
  for (const double t : {0.0, 0.5, 0.7, 0.9, 1.2, 1.5, 2.0, 2.1, 2.3, 2.9})
    EXPECT_NEAR(p.time_at(p.at(t)), t, 1e-12);
  // gait_phase() records the right strike after each left one but the last.
  const GaitPhase walk = gait_phase(contacts({5, 15, 25, 35}, {12, 19, 32}), 0.1, 3, 4.0);
  ASSERT_TRUE(walk.known());
  ASSERT_EQ(walk.right.size(), 3u);
  EXPECT_NEAR(walk.right[0], 0.9, 1e-12);  // frame 12
  EXPECT_NEAR(walk.right[1], 1.6, 1e-12);  // frame 19
  EXPECT_NEAR(walk.right[2], 2.9, 1e-12);  // frame 32
  EXPECT_DOUBLE_EQ(walk.at(0.9), 0.5);
}

TEST(SynthGaitPhase, OnlyGaitCyclesInARowMakeAPhase) {
  const double dt = 0.1;
  // Left strikes 10 frames apart, a right one between each: three cycles.
  const GaitPhase walk = gait_phase(contacts({5, 15, 25, 35}, {10, 20, 30}), dt, 3, 4.0);
  ASSERT_TRUE(walk.known());
  EXPECT_EQ(walk.strikes.size(), 4u);
  EXPECT_NEAR(walk.strikes.front(), 0.2, 1e-12);  // frame 5, 2 frames after the run's start
  EXPECT_DOUBLE_EQ(walk.duration, 4.0);
  // A contact under way at frame 0 is no strike; one cycle alone is not a gait.
  EXPECT_FALSE(gait_phase(contacts({0, 15, 25}, {20}), dt, 0, 3.0).known());
  // No right strike between two left ones (a foot lifted and put down, a golf swing's).
  EXPECT_FALSE(gait_phase(contacts({5, 15, 25}, {}), dt, 0, 3.0).known());
  // Cycles longer than kMaxCycleSeconds (a step, a pause, a step).
  EXPECT_FALSE(gait_phase(contacts({5, 40, 75}, {20, 60}), dt, 0, 9.0).known());
  // The longest run of cycles in a row counts: two here, after a pause.
  const GaitPhase later = gait_phase(contacts({5, 50, 60, 70}, {55, 65}), dt, 0, 8.0);
  ASSERT_TRUE(later.known());
  EXPECT_NEAR(later.strikes.front(), 5.0, 1e-12);
}

TEST(SynthGaitPhase, SharedWalksAndRunsHaveAPhaseAGolfSwingNone) {
  const std::map<std::string, bool> files{
      {"bandai/dataset-1_walk_proud_001.bvh", true},
      {"bandai/dataset-1_walk_tired_001.bvh", true},
      {"bandai/dataset-1_run_angry_001.bvh", true},
      {"cmu/64_08.bvh", false},
  };
  for (const auto& [file, walks] : files) {
    MOTIONMAP_REQUIRE_SHARED(file);
    SCOPED_TRACE(file);
    const Clip clip = io::load_clip(motionmap::test::shared_file(file));
    const Feet feet = find_feet(clip.skeleton);
    const GaitPhase p =
        gait_phase(detect_contacts(clip.skeleton, clip.motion, feet), clip.motion.frame_time, 0,
                   (clip.motion.num_frames - 1) * clip.motion.frame_time);
    EXPECT_EQ(p.known(), walks);
    if (!p.known()) continue;
    const double cycle =
        (p.strikes.back() - p.strikes.front()) / static_cast<double>(p.strikes.size() - 1);
    std::printf("[ figures  ] %s: %zu gait cycles, %.2f s each on average\n", file.c_str(),
                p.strikes.size() - 1, cycle);
    EXPECT_GT(cycle, 0.5);
    EXPECT_LT(cycle, 1.6);
  }
}

// Two takes, each a run of samples starting at "sample" 0 and 100, whose phases advance at one
// cycle per second (the second shifted by `offset` cycles).
struct TwoTakes {
  GaitPhase a, b;
  explicit TwoTakes(double offset) {
    for (int i = -1; i <= 12; ++i) {
      a.strikes.push_back(i);
      b.strikes.push_back(i - offset);
    }
    a.duration = b.duration = 10.0;
  }
  PhaseOf phase_of() const {
    return [this](int run) -> const GaitPhase& { return run == 0 ? a : b; };
  }
};

TEST(SynthGaitPhase, LinesUpTwoTakesBlendedOutOfStep) {
  // 3 s at 30 fps: take a at its own pace, take b a third of a cycle ahead, 60:40.
  const double dt = 1.0 / 30.0;
  const TwoTakes takes(1.0 / 3.0);
  std::vector<PhaseFrame> frames(90);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double t = t_of(k, dt);
    frames[k].sources = {{0, t, 0.6}, {100, t, 0.4}};
  }
  register_phases(frames, 0, frames.size(), dt, takes.phase_of());
  std::vector<double> before(2, 0.0);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE(k);
    ASSERT_TRUE(frames[k].moved);
    // Every source within the band of one phase; the weights as they were, by take.
    double weight[2] = {0.0, 0.0}, lead = 0.0, lead_weight = 0.0;
    for (const PhaseSource& s : frames[k].sources) {
      weight[s.run == 0 ? 0 : 1] += s.weight;
      if (s.weight > lead_weight) {
        lead_weight = s.weight;
        lead = takes.phase_of()(s.run).at(s.seconds);
      }
    }
    EXPECT_NEAR(weight[0], 0.6, 1e-12);
    EXPECT_NEAR(weight[1], 0.4, 1e-12);
    for (const PhaseSource& s : frames[k].sources) {
      EXPECT_LE(std::abs(wrapped(takes.phase_of()(s.run).at(s.seconds) - lead)),
                2.0 * kPhaseBand + 1e-9);
    }
    // Each take's time advances by a frame, as it did: the registered blend walks at the takes'
    // cadence, with no jump.
    double t[2] = {0.0, 0.0};
    for (const PhaseSource& s : frames[k].sources) t[s.run == 0 ? 0 : 1] = s.seconds;
    if (k > 0) {
      EXPECT_NEAR(t[0] - before[0], dt, 1e-9);
      EXPECT_NEAR(t[1] - before[1], dt, 1e-9);
    }
    before = {t[0], t[1]};
  }
}

TEST(SynthGaitPhase, LeavesAClipAtItsOwnPaceAndSourcesWithoutAPhase) {
  const double dt = 1.0 / 30.0;
  const TwoTakes takes(0.0);
  GaitPhase none;
  const PhaseOf phase_of = [&](int run) -> const GaitPhase& {
    return run == 7 ? none : takes.phase_of()(run);
  };
  // One take at 1.4 times its pace, beside a golf swing's frame; then one at half its pace.
  for (const double rate : {1.4, 0.5}) {
    std::vector<PhaseFrame> frames(60);
    for (std::size_t k = 0; k < frames.size(); ++k) {
      frames[k].sources = {{0, 2.0 + rate * static_cast<double>(k) * dt, 0.7}, {7, 0.3, 0.3}};
    }
    const std::vector<PhaseFrame> kept = frames;
    register_phases(frames, 0, frames.size(), dt, phase_of);
    for (std::size_t k = 0; k < frames.size(); ++k) {
      EXPECT_FALSE(frames[k].moved) << "pace " << rate << ", frame " << k;
      ASSERT_EQ(frames[k].sources.size(), 2u);
      EXPECT_EQ(frames[k].sources[0].seconds, kept[k].sources[0].seconds);
      EXPECT_EQ(frames[k].sources[1].seconds, kept[k].sources[1].seconds);
      // Its root moves on at the pace its legs play at, at the path's ends too.
      EXPECT_NEAR(pace(frames, k, dt), rate, 1e-9) << "frame " << k;
    }
  }
}

TEST(SynthGaitPhase, APathThatDwellsBarelyMovesOn) {
  // A path that stays by one sample of a take, then moves on along it at its pace: the legs hold
  // their phase, and the root moves on at the share the registration is unsure of (the leads,
  // carried at the cadence, spread over ±half a cycle: h ≈ 0.86), then walks (pace 1).
  const double dt = 1.0 / 30.0;
  const TwoTakes takes(0.0);
  std::vector<PhaseFrame> frames(120);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double moving = std::max(0.0, static_cast<double>(k) - 60.0) * dt;
    frames[k].sources = {{0, 3.0 + moving, 1.0}};
  }
  register_phases(frames, 0, frames.size(), dt, takes.phase_of());
  for (std::size_t k = 0; k < 40; ++k) EXPECT_LT(pace(frames, k, dt), 0.2) << k;
  for (std::size_t k = 80; k < frames.size(); ++k) EXPECT_NEAR(pace(frames, k, dt), 1.0, 1e-9) << k;
  // No frame registered (an empty one, or one whose sources have no phase): pace 1.
  std::vector<PhaseFrame> none(3);
  EXPECT_EQ(pace(none, 1, dt), 1.0);
}

TEST(SynthGaitPhase, AHalfCycleApartSharesBothCyclesSoNothingJumps) {
  // Take b drifts from a quarter of a cycle behind take a to three quarters (through half a
  // cycle, where its nearest way to a's phase flips from one cycle to the other), weighted 0.2:
  // the blend's clip times, weighted, move continuously.
  const double dt = 1.0 / 30.0;
  const TwoTakes takes(0.0);
  std::vector<PhaseFrame> frames(90);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double t = t_of(k, dt);
    const double drift = 0.25 + 0.5 * static_cast<double>(k) / 89.0;
    frames[k].sources = {{0, t, 0.8}, {100, t - drift, 0.2}};
  }
  register_phases(frames, 0, frames.size(), dt, takes.phase_of());
  // Take b's weighted mean clip time, from frame to frame.
  double before = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    double sum = 0.0, weight = 0.0;
    for (const PhaseSource& s : frames[k].sources) {
      if (s.run != 100) continue;
      sum += s.weight * s.seconds;
      weight += s.weight;
    }
    EXPECT_NEAR(weight, 0.2, 1e-12);
    const double mean = sum / weight;
    if (k > 0) worst = std::max(worst, std::abs(mean - before));
    before = mean;
  }
  // A whole cycle is 1 s; the frames are 1/30 s apart.
  EXPECT_LT(worst, 0.1);
}

TEST(SynthGaitPhase, EachTakesShareMovesSmoothly) {
  // Two takes in step; the blend's weight flips from the first to the second at frame 45, as
  // the kriging's does between two takes' curves. Each take's share now crosses over ±0.15 s,
  // its added weight at the frame's phase, and the blend's weights still sum to 1.
  const double dt = 1.0 / 30.0;
  const TwoTakes takes(0.0);
  std::vector<PhaseFrame> frames(90);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    frames[k].sources = {{k < 45 ? 0 : 100, t_of(k, dt), 1.0}};
  }
  register_phases(frames, 0, frames.size(), dt, takes.phase_of());
  const auto reach = static_cast<std::size_t>(std::lround(kShareSeconds / dt));
  double before = 1.0, largest = 0.0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    SCOPED_TRACE(k);
    double first = 0.0, total = 0.0;
    for (const PhaseSource& s : frames[k].sources) {
      total += s.weight;
      if (s.run == 0) first += s.weight;
      // At the frame's phase, the one both takes play here.
      EXPECT_LE(std::abs(wrapped(takes.phase_of()(s.run).at(s.seconds) - (t_of(k, dt) - 3.0))),
                kPhaseBand + 1e-9);
    }
    EXPECT_NEAR(total, 1.0, 1e-12);
    // Away from the flip, as they were.
    if (k + reach < 45) {
      EXPECT_NEAR(first, 1.0, 1e-12);
    } else if (k >= 45 + reach) {
      EXPECT_NEAR(first, 0.0, 1e-12);
    }
    if (k > 0) largest = std::max(largest, std::abs(first - before));
    before = first;
  }
  // A triangle over ±5 frames: at most 6/36 of the weight moves in a frame (it all did).
  EXPECT_LE(largest, 6.0 / 36.0 + 1e-12);
}

TEST(SynthGaitPhase, LeadPaceSaysWhereTheUnregisteredLegsStandStill) {
  // A take of two cycles a second, held at one clip time for 2 s, then played at its pace. Held,
  // its lead carried at the cadence over ±0.5 s covers two whole cycles: nothing is registered,
  // and the lead stands still (lead_pace 0). Played, the lead moves on at the cadence.
  const double dt = 1.0 / 30.0;
  GaitPhase quick;
  for (int i = -1; i <= 30; ++i) quick.strikes.push_back(0.5 * i);
  quick.duration = 10.0;
  const PhaseOf phase_of = [&](int) -> const GaitPhase& { return quick; };
  std::vector<PhaseFrame> frames(120);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double moving = std::max(0.0, static_cast<double>(k) - 60.0) * dt;
    frames[k].sources = {{0, 3.0 + moving, 1.0}};
  }
  register_phases(frames, 0, frames.size(), dt, phase_of);
  for (std::size_t k = 15; k < 45; ++k) {
    EXPECT_LT(frames[k].registered, 0.5) << k;
    EXPECT_NEAR(lead_pace(frames, k), 0.0, 1e-9) << k;
  }
  for (std::size_t k = 75; k < frames.size(); ++k)
    EXPECT_NEAR(lead_pace(frames, k), 1.0, 1e-9) << k;
  // Leads that jump about (the sources alternating between two times 0.3 cycles apart, as a
  // kriging of samples at scattered phases does) are a mix, not legs held: no lead pace.
  std::vector<PhaseFrame> jumpy(60);
  for (std::size_t k = 0; k < jumpy.size(); ++k) {
    jumpy[k].sources = {{0, 3.0 + (k % 2 == 0 ? 0.0 : 0.15), 1.0}};
  }
  register_phases(jumpy, 0, jumpy.size(), dt, phase_of);
  for (std::size_t k = 0; k < jumpy.size(); ++k) {
    EXPECT_TRUE(std::isnan(jumpy[k].lead_pace)) << k;
    EXPECT_EQ(lead_pace(jumpy, k), 1.0) << k;
  }
  // Registered frames, or frames without a phase: 1.
  std::vector<PhaseFrame> none(3);
  EXPECT_EQ(lead_pace(none, 1), 1.0);
}

}  // namespace
}  // namespace motionmap::synth::detail
