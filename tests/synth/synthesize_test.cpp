#include "motionmap/synth/synthesize.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/synth/detail/outside_route.h"
#include "support/error_message.h"
#include "synth/synth_fixtures.h"

namespace motionmap::synth {
namespace {

using test::all_frames;
using test::curve_map;
using test::walking_clip;

constexpr BlendMode kModes[] = {BlendMode::Kriging, BlendMode::Local, BlendMode::Idw};

MapBlender make_blender(const Clip& clip, const Eigen::MatrixXd& map,
                        BlendMode mode = BlendMode::Local, int k = 12) {
  BlendOptions opt;
  opt.mode = mode;
  opt.neighbors = k;
  return MapBlender(std::span<const Clip>(&clip, 1), all_frames(clip.motion.num_frames), map, opt);
}

// The map trajectory of frames [first, end) at the clip's own timing.
MapPath own_trajectory(const Eigen::MatrixXd& map, double frame_time, int first = 0, int end = -1) {
  if (end < 0) end = static_cast<int>(map.rows());
  MapPath path;
  for (int f = first; f < end; ++f) {
    path.points.emplace_back(map(f, 0), map(f, 1));
    path.times.push_back((f - first) * frame_time);
  }
  return path;
}

std::string parameter_message(const std::function<void()>& f) {
  return motionmap::test::error_message<ParameterError>(f);
}

TEST(SynthSynthesize, RetracingTheTrajectoryReproducesTheClip) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const Motion& orig = clip.motion;
  // The synthesized clip starts at the origin with heading 0: compare with the original moved
  // there (translation by −p0, rotation by −θ0 about Y).
  const double h0 = features::heading_angle(orig.rotation(0, 0));
  const Eigen::Quaterniond unturn = axis_rotation(Axis::Y, -h0);
  Eigen::Vector3d p0 = orig.translation(0, 0);
  p0.y() = 0;
  for (const auto& [mode, smooth] :
       {std::pair{BlendMode::Kriging, 0.0}, std::pair{BlendMode::Local, 0.0},
        std::pair{BlendMode::Idw, 0.0}, std::pair{BlendMode::Local, 0.2},
        std::pair{BlendMode::Kriging, 0.2}}) {
    // Smoothed too: each neighbour's weights are moved back in the clip by its distance in time
    // before they are averaged, so they all land on the frame itself.
    SCOPED_TRACE(std::string(blend_mode_name(mode)) + ", smooth " + std::to_string(smooth));
    const MapBlender blender = make_blender(clip, map, mode);
    SynthOptions options;
    options.smooth = smooth;
    const SynthResult r = synthesize(blender, own_trajectory(map, orig.frame_time), options);
    ASSERT_EQ(r.motion.num_frames, orig.num_frames);
    EXPECT_EQ(r.motion.frame_time, orig.frame_time);
    EXPECT_EQ(r.clamped_frames, 0);
    for (int f = 0; f < orig.num_frames; ++f) {
      EXPECT_LE(rotation_angle(r.motion.rotation(f, 0), unturn * orig.rotation(f, 0)), 1e-9) << f;
      for (int j = 1; j < 5; ++j)
        EXPECT_LE(rotation_angle(r.motion.rotation(f, j), orig.rotation(f, j)), 1e-9) << f;
      const Eigen::Vector3d expected = unturn * (orig.translation(f, 0) - p0);
      EXPECT_LE((r.motion.translation(f, 0) - expected).norm(), 1e-9) << f;
      EXPECT_EQ(r.validity[f].distance, 0.0);
    }
  }
}

TEST(SynthSynthesize, GivenWeightsMakeTheMotionThePathsLocatedWeightsMake) {
  // synthesize(weights) is synthesize(path) without the locating: the path's own located weights
  // (locate_path) give its motion bit for bit, smoothing and cleaning included.
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map, BlendMode::Local);
  MapPath path = own_trajectory(map, clip.motion.frame_time);
  for (Eigen::Vector2d& p : path.points) p += Eigen::Vector2d(0.01, -0.02);  // between samples
  SynthOptions options;
  options.smooth = 0.05;
  const SynthResult from_path = synthesize(blender, path, options);
  const std::vector<MapWeights> weights =
      blender.locate_path(path.points, clip.motion.frame_time, 0, path.points.size());
  const SynthResult from_weights = synthesize(blender, weights, options);
  ASSERT_EQ(from_weights.motion.num_frames, from_path.motion.num_frames);
  EXPECT_EQ(from_weights.motion.rotations, from_path.motion.rotations);
  EXPECT_EQ(from_weights.motion.translations, from_path.motion.translations);
  EXPECT_EQ(from_weights.clamped_frames, from_path.clamped_frames);

  // Two samples' weights half and half: the frame between them.
  const std::vector<MapWeights> between{MapWeights{{10, 11}, {0.5, 0.5}, {}}};
  const SynthResult half = synthesize(blender, between);
  EXPECT_NEAR(rotation_angle(half.motion.rotation(0, 2), clip.motion.rotation(10, 2)),
              rotation_angle(half.motion.rotation(0, 2), clip.motion.rotation(11, 2)), 1e-9);

  EXPECT_NE(parameter_message([&] {
              synthesize(blender, std::vector<MapWeights>{});
            }).find("no frames' weights"),
            std::string::npos);
  EXPECT_NE(parameter_message([&] {
              synthesize(blender, std::vector<MapWeights>{MapWeights{{11, 10}, {0.5, 0.5}, {}}});
            }).find("frame 0's weights"),
            std::string::npos);
  EXPECT_NE(parameter_message([&] {
              synthesize(blender, std::vector<MapWeights>{MapWeights{{0}, {NAN}, {}}});
            }).find("frame 0's weights"),
            std::string::npos);
  EXPECT_NE(parameter_message([&] {
              synthesize(blender, std::vector<MapWeights>{MapWeights::of_sample(100000)});
            }).find("frame 0's weights"),
            std::string::npos);
}

TEST(SynthSynthesize, ASketchedWalkWalksEvenWhenThePathTurnsBack) {
  // Forward along the map then back: the blended heading-local velocity is always ≈ 30 units/s
  // forward, so the body keeps walking (and turning at 0.4 rad/s), whatever the map direction.
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  MapPath path;
  for (int f = 5; f < 75; f += 5) path.points.emplace_back(map(f, 0), map(f, 1));
  for (int f = 70; f > 5; f -= 5) path.points.emplace_back(map(f, 0), map(f, 1));
  const SynthResult r = synthesize(blender, path);
  const Motion& m = r.motion;
  ASSERT_GT(m.num_frames, 100);
  EXPECT_DOUBLE_EQ(blender.median_speed(), blender.median_step() * 30.0);
  double travelled = 0.0, turned = 0.0;
  for (int f = 1; f < m.num_frames; ++f) {
    Eigen::Vector3d d = m.translation(f, 0) - m.translation(f - 1, 0);
    d.y() = 0;
    travelled += d.norm();
    turned += features::heading_angle(m.rotation(f - 1, 0).conjugate() * m.rotation(f, 0));
  }
  const double seconds = (m.num_frames - 1) * m.frame_time;
  EXPECT_NEAR(travelled / seconds, 30.0, 1.0);
  EXPECT_NEAR(turned / seconds, 0.4, 0.05);
}

TEST(SynthSynthesize, UntimedPathsUseTheMedianMapSpeed) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  MapPath path;
  path.points = {{1.0, 0.0}, {4.0, 0.0}};
  const SynthResult r = synthesize(blender, path);
  const double seconds = 3.0 / blender.median_speed();
  EXPECT_EQ(r.motion.num_frames, static_cast<int>(std::floor(seconds * 30.0 + 1e-9)) + 1);
  SynthOptions opt;
  opt.speed = 1.5;  // 2 s
  opt.fps = 60.0;
  const SynthResult s = synthesize(blender, path, opt);
  EXPECT_EQ(s.motion.num_frames, 121);
  EXPECT_DOUBLE_EQ(s.motion.frame_time, 1.0 / 60.0);
}

TEST(SynthSynthesize, HigherFrameRatesInterpolateBetweenSamples) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  SynthOptions opt;
  opt.fps = 90.0;  // 3 output frames per source frame
  const SynthResult r = synthesize(blender, own_trajectory(map, clip.motion.frame_time), opt);
  ASSERT_EQ(r.motion.num_frames, 3 * (clip.motion.num_frames - 1) + 1);
  for (int f = 0; f < clip.motion.num_frames; f += 7) {
    for (int j = 1; j < 5; ++j) {
      EXPECT_LE(rotation_angle(r.motion.rotation(3 * f, j), clip.motion.rotation(f, j)), 1e-9) << f;
    }
  }
  // The walking speed is kept: 30 units/s.
  const Eigen::Vector3d d =
      r.motion.translation(r.motion.num_frames - 1, 0) - r.motion.translation(0, 0);
  EXPECT_GT(Eigen::Vector2d(d.x(), d.z()).norm() / ((r.motion.num_frames - 1) / 90.0), 20.0);
}

TEST(SynthSynthesize, SmoothingSoftensJumpsAlongThePath) {
  // Hold one sample, jump to one far along the clip in 1/30 s, hold it (inside the data: outside
  // it a path follows the clips' own frames, which never jump).
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  for (BlendMode mode : kModes) {
    SCOPED_TRACE(std::string(blend_mode_name(mode)));
    const MapBlender blender = make_blender(clip, map, mode);
    MapPath path;
    const Eigen::Vector2d a = map.row(10).transpose(), b = map.row(60).transpose();
    path.points = {a, a, b, b};
    path.times = {0.0, 1.0, 1.0 + 1.0 / 30, 2.0};
    auto max_step = [&](double smooth) {
      SynthOptions opt;
      opt.smooth = smooth;
      const SynthResult r = synthesize(blender, path, opt);
      double worst = 0.0;
      for (int f = 1; f < r.motion.num_frames; ++f) {
        worst =
            std::max(worst, rotation_angle(r.motion.rotation(f - 1, 3), r.motion.rotation(f, 3)));
      }
      return worst;
    };
    const double sharp = max_step(0.0), soft = max_step(0.2);
    EXPECT_GT(sharp, 0.3);
    EXPECT_LT(soft, sharp / 4.0);
  }
}

TEST(SynthSynthesize, ReportsFramesOutsideTheData) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  MapPath path;
  path.points = {{2.0, 0.0}, {2.0, 30.0}};
  path.times = {0.0, 1.0};
  const SynthResult r = synthesize(blender, path);
  ASSERT_EQ(r.motion.num_frames, 31);
  EXPECT_FALSE(r.validity.front().clamped);
  EXPECT_TRUE(r.validity.back().clamped);
  EXPECT_GT(r.clamped_frames, 25);
  EXPECT_LT(r.clamped_frames, 31);
  for (int f = 0; f < r.motion.num_frames; ++f) {
    for (int j = 0; j < 5; ++j) EXPECT_NEAR(r.motion.rotation(f, j).norm(), 1.0, 1e-12);
    EXPECT_TRUE(r.motion.translation(f, 0).allFinite());
  }
}

TEST(SynthSynthesize, APathOutsideTheDataPlaysTheClipsOwnFrames) {
  // The clip's curve moved 3 units off it (about 7 reaches: every frame outside), at the clip's
  // timing: a route through the clip's own frames tracks it, so every frame is a pose of the clip
  // (between two consecutive frames) and no joint turns further between two frames than it does
  // in the clip. Blended at the data's edge, frames mixed the curve's phases (poses of no frame).
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  MapPath path;
  for (int f = 0; f < clip.motion.num_frames; ++f) {
    path.points.emplace_back(map(f, 0), map(f, 1) + 3.0);
    path.times.push_back(f * clip.motion.frame_time);
  }
  SynthOptions raw;
  raw.clean_feet = false;
  const SynthResult r = synthesize(blender, path, raw);
  ASSERT_EQ(r.motion.num_frames, clip.motion.num_frames);
  EXPECT_EQ(r.clamped_frames, r.motion.num_frames);
  double clip_step = 0.0, step = 0.0, off = 0.0;
  for (int f = 1; f < clip.motion.num_frames; ++f) {
    for (int j = 1; j < 5; ++j) {
      clip_step = std::max(
          clip_step, rotation_angle(clip.motion.rotation(f - 1, j), clip.motion.rotation(f, j)));
      step = std::max(step, rotation_angle(r.motion.rotation(f - 1, j), r.motion.rotation(f, j)));
    }
  }
  for (int f = 0; f < r.motion.num_frames; ++f) {
    double nearest = 1e9;
    for (int g = 0; g < clip.motion.num_frames; ++g) {
      double worst = 0.0;
      for (int j = 1; j < 5; ++j) {
        worst =
            std::max(worst, rotation_angle(r.motion.rotation(f, j), clip.motion.rotation(g, j)));
      }
      nearest = std::min(nearest, worst);
    }
    off = std::max(off, nearest);
  }
  EXPECT_LE(off, 0.5 * clip_step + 1e-9);
  EXPECT_LE(step, clip_step + 1e-9);
  // The same path in the kriging mode is blended at the edge (routes are the local mode's).
  const MapBlender kriging = make_blender(clip, map, BlendMode::Kriging);
  EXPECT_EQ(synthesize(kriging, path, raw).clamped_frames, r.motion.num_frames);
}

TEST(SynthSynthesize, AGaitStallsWhereItsPaceDropsAsThePathMovesOn) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  const double dt = clip.motion.frame_time;
  // A path moving on at the clips' median map speed, and its frames' located weights: a pace and
  // a distance from the nearest sample each.
  const double step = blender.median_speed() * dt;
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < 8; ++k) points.emplace_back(map(0, 0) + k * step, map(0, 1));
  const double far = 2.0 * kFollowNear * blender.median_step();
  const double near = 0.5 * kFollowNear * blender.median_step();
  std::vector<MapWeights> located(points.size(), MapWeights::of_sample(0));
  const auto frame = [&](std::size_t k, double pace, double distance) {
    located[k].pace = pace;
    located[k].validity.distance = distance;
  };
  frame(0, 1.0, far);   // the legs at their pace
  frame(1, 0.3, far);   // stalled: slow legs, away from the clips, the path moving on
  frame(2, 0.3, near);  // slow legs on a clip's trajectory: the path plays it slowly
  frame(3, 0.49, far);  // stalled
  frame(4, 0.5, far);   // at the line: not
  frame(5, 0.0, far);   // stalled
  frame(6, 0.3, far);   // stalled (the path still moves on into frame 7)
  frame(7, 0.3, far);
  EXPECT_EQ(detail::stalled_frames(blender, points, dt, located),
            (std::vector<char>{0, 1, 0, 1, 0, 1, 1, 1}));
  // Frames 4… of the path alone give the same.
  EXPECT_EQ(detail::stalled_frames(blender, points, dt, std::span(located).subspan(4), 4),
            (std::vector<char>{0, 1, 1, 1}));
  // Where the phase was not registered, the sources' own leads: near the clips too.
  located[2].lead_pace = 0.2;  // stalled
  located[4].lead_pace = 0.6;  // not
  EXPECT_EQ(detail::stalled_frames(blender, points, dt, located),
            (std::vector<char>{0, 1, 1, 1, 0, 1, 1, 1}));
  // A path that dwells holds the pose: no stall.
  const std::vector<Eigen::Vector2d> still(points.size(), points[0]);
  EXPECT_EQ(detail::stalled_frames(blender, still, dt, located), std::vector<char>(8, 0));
  // Nor but in the local mode.
  EXPECT_EQ(detail::stalled_frames(make_blender(clip, map, BlendMode::Idw), points, dt, located),
            std::vector<char>(8, 0));
  EXPECT_EQ(detail::stall_spread(1.0 / 30.0), 15);
  std::vector<PointValidity> inside(3);
  EXPECT_EQ(detail::stalled_note(std::vector<char>(3, 0), inside), "");
  EXPECT_EQ(detail::stalled_note(std::vector<char>{0, 1, 1}, inside),
            "gait: at 2 frames the blend held its legs mid-stride while the path moved on; the "
            "clips' own frames play there and within 500 ms of them");
  // A stalled frame outside the data is told as outside (its own note), not twice.
  std::vector<PointValidity> last_outside = inside;
  last_outside[2].clamped = true;
  EXPECT_EQ(detail::stalled_note(std::vector<char>{0, 1, 1}, last_outside),
            "gait: at 1 frame the blend held its legs mid-stride while the path moved on; the "
            "clips' own frames play there and within 500 ms of them");
  last_outside[1].clamped = true;
  EXPECT_EQ(detail::stalled_note(std::vector<char>{0, 1, 1}, last_outside), "");

  // On the clip's own curve nothing is outside; the frames within `spread` of a stall are routed.
  std::vector<Eigen::Vector2d> on_curve;
  for (int f = 0; f < 20; ++f) on_curve.emplace_back(map(f, 0), map(f, 1));
  using Runs = std::vector<std::pair<std::size_t, std::size_t>>;
  std::vector<char> stalled(on_curve.size(), 0);
  EXPECT_EQ(detail::outside_runs(blender, on_curve, stalled, 3), Runs{});
  stalled[8] = 1;
  EXPECT_EQ(detail::outside_runs(blender, on_curve, stalled, 3), (Runs{{5, 12}}));
  stalled[13] = 1;  // within reach of the first: one run
  EXPECT_EQ(detail::outside_runs(blender, on_curve, stalled, 3), (Runs{{5, 17}}));
  stalled[1] = 1;  // its run starts at the path's start
  EXPECT_EQ(detail::outside_runs(blender, on_curve, stalled, 3), (Runs{{0, 17}}));
  // Not but in the local mode.
  EXPECT_EQ(detail::outside_runs(make_blender(clip, map, BlendMode::Idw), on_curve, stalled, 3),
            Runs{});
}

TEST(SynthSynthesize, RunsToRouteAreOutsideOrBeyondHalfTheReach) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  // The line: half the reach, here more than kFollowNear median steps.
  const double line = detail::kRouteReachFraction * blender.reach_distance();
  ASSERT_GT(line, kFollowNear * blender.median_step());
  // Frames on the curve ('i'), inside the data but nearer than the line ('n': half of it) or
  // farther ('f': halfway from it to the reach), or outside ('o'), the curve moved up by as much.
  const double far = 0.5 * (line + blender.reach_distance());
  const auto path_of = [&](const std::string& pattern) {
    std::vector<Eigen::Vector2d> points;
    for (std::size_t k = 0; k < pattern.size(); ++k) {
      const double up = pattern[k] == 'o'   ? 3.0
                        : pattern[k] == 'n' ? 0.5 * line
                        : pattern[k] == 'f' ? far
                                            : 0.0;
      points.emplace_back(map(static_cast<int>(k), 0), map(static_cast<int>(k), 1) + up);
    }
    return points;
  };
  for (const Eigen::Vector2d& p : path_of(std::string(60, 'f'))) EXPECT_TRUE(blender.inside(p));
  EXPECT_FALSE(blender.inside(path_of("o")[0]));
  using Runs = std::vector<std::pair<std::size_t, std::size_t>>;
  // A lone frame outside is no run; two are.
  EXPECT_EQ(detail::outside_runs(blender, path_of("iioiiiiiii")), Runs{});
  EXPECT_EQ(detail::outside_runs(blender, path_of("iiooiiiiii")), (Runs{{2, 4}}));
  // Frames beyond the line, inside the data, are routed with those outside beside them; those
  // short of it are not, and part runs.
  EXPECT_EQ(detail::outside_runs(blender, path_of("iffooffiiffi")), (Runs{{1, 7}, {9, 11}}));
  EXPECT_EQ(detail::outside_runs(blender, path_of("innnoonnfni")), (Runs{{4, 6}}));
  EXPECT_EQ(detail::outside_runs(blender, path_of("ooonooo")), (Runs{{0, 3}, {4, 7}}));
  // A run with frames outside the data is widened by `pad` frames each side, and runs that then
  // meet are joined; one only beyond the line is not widened.
  EXPECT_EQ(detail::outside_runs(blender, path_of("iiiiooiiiiii"), {}, 0, 2), (Runs{{2, 8}}));
  EXPECT_EQ(detail::outside_runs(blender, path_of("iooiiiooii"), {}, 0, 2), (Runs{{0, 10}}));
  EXPECT_EQ(detail::outside_runs(blender, path_of("iffiiiiiiii"), {}, 0, 2), (Runs{{1, 3}}));
  // Other modes have none.
  EXPECT_EQ(detail::outside_runs(make_blender(clip, map, BlendMode::Idw), path_of("ioooffi")),
            Runs{});
}

// A stroke between two points on a clip's curve, drawn at about the clip's timing, follows the
// curve, not the chord across its loop (detail/strokes.h): the frames between its ends are the
// curve's points at the clip's times, the ends' offsets from the curve shared linearly.
TEST(SynthSynthesize, AStrokeBetweenTwoPointsOfACurveAtItsTimingFollowsTheCurve) {
  const Clip clip = walking_clip(80);
  const double dt = clip.motion.frame_time;
  // Most of a circle of radius 1: its chords pass far inside it (step 0.07, kFollowFar 0.21).
  Eigen::MatrixXd map(80, 2);
  for (int f = 0; f < 80; ++f) map.row(f) << std::cos(0.07 * f), std::sin(0.07 * f);
  const MapBlender blender = make_blender(clip, map);
  const double step = blender.median_step();
  const auto curve = [&](double frame) {
    const int f = static_cast<int>(std::floor(frame));
    const double u = frame - f;
    return Eigen::Vector2d((1.0 - u) * map.row(f).transpose() + u * map.row(f + 1).transpose());
  };
  const auto stroke = [&](int from, int to, double seconds, Eigen::Vector2d off_from = {0, 0},
                          Eigen::Vector2d off_to = {0, 0}) {
    MapPath path;
    path.points = {curve(from) + off_from, curve(to) + off_to};
    path.times = {1.0, 1.0 + seconds};
    return path;
  };
  const auto expect_points = [&](const MapPath& path, const auto& expected) {
    const std::vector<Eigen::Vector2d> points = blender.path_points(path, dt, 0.0, 1000);
    ASSERT_EQ(points.size(), resample_path(path, dt).size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      EXPECT_LT((points[k] - expected(k)).norm(), 1e-9 * step) << "frame " << k;
    }
  };
  // At the clip's timing: its own points (20 frames from frame 10 to 30).
  expect_points(stroke(10, 30, 20 * dt), [&](std::size_t k) { return curve(10.0 + k); });
  // Drawn slower (0.6 of the pace) and off the curve by a step at one end (outwards, where frame
  // 10 stays its nearest point): the curve at that rate, the offset fading out along the stroke.
  const Eigen::Vector2d off = step * curve(10);
  const MapPath slower = stroke(10, 30, 20 * dt / 0.6, off);
  const std::size_t frames = resample_path(slower, dt).size();
  expect_points(slower, [&](std::size_t k) {
    const double u = static_cast<double>(k) * dt / (slower.times[1] - slower.times[0]);
    return Eigen::Vector2d(curve(10.0 + 0.6 * static_cast<double>(k)) + (1.0 - u) * off);
  });
  EXPECT_EQ(frames, 34u);
  // The chord, as drawn: at a quarter or four times the pace (the follow plays a clip at
  // 0.5–2), an end farther than kFollowFar steps off the curve (at the circle's centre), in the
  // other modes.
  for (const MapPath& path : {stroke(10, 30, 80 * dt), stroke(10, 30, 5 * dt),
                              stroke(10, 30, 20 * dt, {0, 0}, -curve(30))}) {
    const std::vector<Eigen::Vector2d> chord = resample_path(path, dt);
    expect_points(path, [&](std::size_t k) { return chord[k]; });
  }
  const MapBlender idw = make_blender(clip, map, BlendMode::Idw);
  EXPECT_EQ(idw.path_points(stroke(10, 30, 20 * dt), dt, 0.0, 1000),
            resample_path(stroke(10, 30, 20 * dt), dt));
  // An end 3 steps inside the curve (the two ends' RMS 2.1 steps, between kFollowNear and
  // kFollowFar): partly, between the chord and the curve.
  const MapPath between = stroke(10, 30, 20 * dt, {0, 0}, -3.0 * step * curve(30));
  const std::vector<Eigen::Vector2d> chord = resample_path(between, dt);
  const std::vector<Eigen::Vector2d> points = blender.path_points(between, dt, 0.0, 1000);
  const Eigen::Vector2d full = curve(20.0) + 0.5 * (-3.0 * step * curve(30));
  const double share =
      (points[10] - chord[10]).dot(full - chord[10]) / (full - chord[10]).squaredNorm();
  EXPECT_GT(share, 0.05) << share;
  EXPECT_LT(share, 0.95) << share;
}

TEST(SynthSynthesize, ReportsProgressAndCancels) {
  const Clip clip = walking_clip();
  const Eigen::MatrixXd map = curve_map(clip.motion.num_frames);
  const MapBlender blender = make_blender(clip, map);
  MapPath path;
  path.points = {{0.5, 0.0}, {7.5, 0.0}};
  path.times = {0.0, 40.0};  // 1201 frames: five blocks
  std::vector<double> seen;
  synthesize(blender, path, {}, Control([&](double x, std::string_view) { seen.push_back(x); }));
  ASSERT_FALSE(seen.empty());
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(seen.back(), 1.0);
  int polls = 0;
  EXPECT_THROW(synthesize(blender, path, {}, Control({}, [&] { return ++polls > 2; })), Cancelled);
}

TEST(SynthSynthesize, RejectsBadOptions) {
  const Clip clip = walking_clip(20);
  const MapBlender blender = make_blender(clip, curve_map(20));
  MapPath path;
  path.points = {{0, 0}, {1, 0}};
  auto run = [&](double speed, double fps, double smooth) {
    SynthOptions opt;
    opt.speed = speed;
    opt.fps = fps;
    opt.smooth = smooth;
    return parameter_message([&] { synthesize(blender, path, opt); });
  };
  EXPECT_EQ(run(-1, 0, 0), "speed: -1 is out of range (map units per second, ≥ 0; 0 = the clip's)");
  EXPECT_EQ(run(NAN, 0, 0),
            "speed: nan is out of range (map units per second, ≥ 0; 0 = the clip's)");
  EXPECT_EQ(run(0, -30, 0), "fps: -30 is out of range (must be in (0, 1000]; 0 = the clip's)");
  EXPECT_EQ(run(0, 1e4, 0), "fps: 10000 is out of range (must be in (0, 1000]; 0 = the clip's)");
  EXPECT_EQ(run(0, 0, -0.1), "smooth: -0.1 s is out of range (must be in [0, 10])");
  EXPECT_EQ(run(0, 0, 11), "smooth: 11 s is out of range (must be in [0, 10])");
  EXPECT_EQ(run(0, 0, INFINITY), "smooth: inf s is out of range (must be in [0, 10])");
  EXPECT_EQ(parameter_message([&] { synthesize(blender, MapPath{}); }),
            "path: 0 point(s); at least 2 are needed");
}

TEST(SynthSynthesize, RejectsADefaultSpeedOnAStillMap) {
  const Clip clip = walking_clip(10);
  const MapBlender blender = make_blender(clip, Eigen::MatrixXd::Zero(10, 2), BlendMode::Local, 4);
  MapPath path;
  path.points = {{0, 0}, {1, 0}};
  EXPECT_EQ(
      parameter_message([&] { synthesize(blender, path); }),
      "speed: the map has no motion to take a default speed from; give one (map units per second)");
  SynthOptions opt;
  opt.speed = 2.0;
  EXPECT_EQ(synthesize(blender, path, opt).motion.num_frames, 16);  // 0.5 s at 30 fps
}

TEST(SynthSynthesize, RejectsOverlongPathsAndSmoothingWindows) {
  const Clip clip = walking_clip(20);
  const MapBlender blender = make_blender(clip, curve_map(20));
  MapPath path;
  path.points = {{0, 0}, {1, 0}};
  path.times = {0, 1e5};
  EXPECT_EQ(parameter_message([&] { synthesize(blender, path); }),
            "path: 100000 s at 30 fps gives 3000001 frames, more than the limit of 360000");
  // Kriging keeps dense weights (one per sample) for every frame of the smoothing window.
  Clip still = walking_clip(1);
  features::FeatureSet set;
  set.clip_of.assign(1000, 0);
  set.frame_of.assign(1000, 0);
  Eigen::MatrixXd map(1000, 2);
  for (int i = 0; i < 1000; ++i) map.row(i) << 0.01 * i, std::sin(0.01 * i);
  BlendOptions bo;
  bo.mode = BlendMode::Kriging;
  const MapBlender kriging(std::span<const Clip>(&still, 1), set, map, bo);
  SynthOptions so;
  so.smooth = 10.0;
  so.fps = 1000.0;
  path.times = {0, 40};
  EXPECT_EQ(parameter_message([&] { synthesize(kriging, path, so); }),
            "smooth: 10 s spans 60001 frames of dense kriging weights over 1000 samples, more than "
            "the limit of "
            "50000000 weights; use less smoothing or the local mode");
}

TEST(SynthSynthesize, OutsideFramesNoteSaysHowTheyWerePlayed) {
  SynthResult r;
  EXPECT_EQ(outside_frames_note(r), "");
  r.clamped_frames = 12;
  EXPECT_EQ(outside_frames_note(r), "12 were blended at the nearest edge of the data");
  r.routed_frames = 12;
  EXPECT_EQ(outside_frames_note(r), "12 play the clips' own frames along the path there");
  r.routed_frames = 9;
  EXPECT_EQ(outside_frames_note(r),
            "9 play the clips' own frames along the path there, 3 were blended at the nearest edge "
            "of the data");
}

}  // namespace
}  // namespace motionmap::synth
