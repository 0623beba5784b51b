#include "motionmap/synth/inbetween.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/clean_feet.h"
#include "motionmap/synth/route.h"
#include "support/error_message.h"
#include "support/test_data.h"
#include "synth/synth_fixtures.h"

namespace motionmap::synth {
namespace {

using test::all_frames;
using test::curve_map;
using test::walking_clip;

// Options with `n` frames between keys (−1: not given).
InbetweenOptions between(int n) {
  InbetweenOptions options;
  options.frames_between = n;
  return options;
}

std::string parameter_message(const std::function<void()>& f) {
  return motionmap::test::error_message<ParameterError>(f);
}

// The output frame `k` is the key's pose, root included: joint rotations to `tol` radians, the
// root's floor position and height to `tol` relative to its distance from the origin, its heading
// to `tol` radians.
void expect_key_hit(const MapBlender& blender, const Motion& out, int k, const Key& key,
                    double tol = 1e-9) {
  SCOPED_TRACE(testing::Message() << "frame " << k << " key " << key.label);
  const int root = blender.motion_root();
  const Axis up = blender.options().up;
  for (int j = 0; j < out.num_joints; ++j) {
    EXPECT_LE(rotation_angle(out.rotation(k, j), key.pose.rotation(0, j)), tol) << "joint " << j;
  }
  const Eigen::Vector3d want = key.pose.translation(0, root), got = out.translation(k, root);
  EXPECT_LE((got - want).norm(), tol * std::max(1.0, want.norm()))
      << got.transpose() << " vs " << want.transpose();
  const RootPlacement a = root_placement(out, k, root, up);
  const RootPlacement b = root_placement(key.pose, 0, root, up);
  EXPECT_LE(std::abs(wrap_angle(a.heading - b.heading)), tol);
}

// How many of an in-between's notes say `what`.
long notes_saying(const InbetweenResult& r, const std::string& what) {
  return std::count_if(r.notes.begin(), r.notes.end(),
                       [&](const std::string& n) { return n.find(what) != std::string::npos; });
}

struct Synthetic {
  Clip clip = walking_clip(120);
  Eigen::MatrixXd map = curve_map(120);
  features::FeatureSet set = all_frames(120);
  MapBlender blender{std::span<const Clip>(&clip, 1), set, map};

  Key key(int frame, std::optional<double> time = std::nullopt) const {
    Key k = sample_key(blender, frame, clip.motion, frame);
    k.label = "walking.bvh:" + std::to_string(frame);
    k.time = time;
    return k;
  }
};

TEST(SynthInbetween, FramesBetweenPutsTheKeysWhereAskedAndHitsThemExactly) {
  const Synthetic s;
  const std::vector<Key> keys{s.key(10), s.key(60), s.key(100)};
  for (const RouteMode mode : {RouteMode::Clips, RouteMode::Grid}) {
    SCOPED_TRACE(route_mode_name(mode));
    InbetweenOptions options = between(24);
    options.route.mode = mode;
    const InbetweenResult r = inbetween(s.blender, s.set, keys, options);
    ASSERT_EQ(r.motion.num_frames, 51);
    EXPECT_EQ(r.key_frames, (std::vector<int>{0, 25, 50}));
    EXPECT_EQ(r.motion.frame_time, s.clip.motion.frame_time);
    ASSERT_EQ(r.routes.size(), 2u);
    ASSERT_EQ(r.points.size(), 51u);
    ASSERT_EQ(r.validity.size(), 51u);
    EXPECT_EQ(r.outside_frames, 0);
    for (int i = 0; i < 3; ++i) {
      // The key's own world placement, as in the clip: root position and heading included.
      expect_key_hit(s.blender, r.motion, r.key_frames[i], keys[i]);
      // The grid route blends a key's frame at its point; a clip route at the sample it passes
      // there (the displacement map makes the pose the key's all the same).
      if (mode == RouteMode::Grid) {
        EXPECT_EQ(r.points[r.key_frames[i]], keys[i].point);
      }
    }
    EXPECT_EQ(r.routes[0].front(), keys[0].point);
    EXPECT_EQ(r.routes[0].back(), keys[1].point);
    const MapField field(s.blender);
    for (const auto& p : r.points) EXPECT_TRUE(field.valid(p)) << p.transpose();
  }
}

TEST(SynthInbetween, APlayedJumpCrossfadesTheTwoClips) {
  // A route through samples 5–10, then a jump to 50–55 (route.h, clip_route_weights). Within
  // the fade (0.6 s at 30 steps per second: 9 steps, cut to 5.5 by the route's ends) a frame
  // mixes the clip jumped from played on past 10 and the clip jumped to played up to 50, the
  // latter's share rising by a smoothstep through 0.5 at the jump's middle; with no fade, the
  // nearer sample alone, as a cut.
  const Synthetic s;
  const std::vector<int> next = next_samples(s.blender);
  const ClipRoutePlay play =
      play_clip_route(s.blender, next, {5, 6, 7, 8, 9, 10, 50, 51, 52, 53, 54, 55}, 1.0);
  const auto share_of = [](const MapWeights& w, int lo, int hi) {
    double sum = 0.0;
    for (std::size_t i = 0; i < w.samples.size(); ++i)
      if (w.samples[i] >= lo && w.samples[i] <= hi) sum += w.weights[i];
    return sum;
  };
  double last = -1.0;
  for (double t = 0.0; t <= 11.0; t += 0.25) {
    const MapWeights w = clip_route_weights(s.blender, next, play, t, 30.0);
    double total = 0.0;
    for (const double x : w.weights) total += x;
    EXPECT_NEAR(total, 1.0, 1e-12) << t;
    const double to = share_of(w, 40, 55);
    EXPECT_NEAR(to + share_of(w, 5, 16), 1.0, 1e-12) << t;  // only the two clips' frames
    EXPECT_GE(to, last - 1e-12) << t;
    last = to;
  }
  const MapWeights middle = clip_route_weights(s.blender, next, play, 5.5, 30.0);
  EXPECT_NEAR(share_of(middle, 40, 55), 0.5, 1e-12);
  // Half a frame on from 10 and half a frame before 50.
  EXPECT_NEAR(share_of(middle, 10, 10), 0.25, 1e-12);
  EXPECT_NEAR(share_of(middle, 11, 11), 0.25, 1e-12);
  EXPECT_NEAR(share_of(middle, 49, 49), 0.25, 1e-12);
  EXPECT_NEAR(share_of(middle, 50, 50), 0.25, 1e-12);
  EXPECT_EQ(clip_route_weights(s.blender, next, play, 5.4, 30.0, 0.0).samples,
            std::vector<int>{10});
  EXPECT_EQ(clip_route_weights(s.blender, next, play, 5.6, 30.0, 0.0).samples,
            std::vector<int>{50});
}

TEST(SynthInbetween, KeysOnTheClipsOwnTrajectoryReproduceItsFrames) {
  // Consecutive frames as keys with no frame between: every output frame is a clip frame, in its
  // own world placement.
  const Synthetic s;
  std::vector<Key> keys;
  for (int f = 30; f <= 40; ++f) keys.push_back(s.key(f));
  const InbetweenResult r = inbetween(s.blender, s.set, keys, between(0));
  ASSERT_EQ(r.motion.num_frames, 11);
  for (int k = 0; k < 11; ++k) expect_key_hit(s.blender, r.motion, k, keys[k]);
}

TEST(SynthInbetween, TimesAndTheSamplesOwnSpeedSetTheFrames) {
  const Synthetic s;
  const double dt = s.clip.motion.frame_time;
  // Times: the nearest frames.
  {
    const std::vector<Key> keys{s.key(10, 1.0), s.key(60, 1.0 + 31.2 * dt), s.key(90, 3.0)};
    const InbetweenResult r = inbetween(s.blender, s.set, keys);
    EXPECT_EQ(r.key_frames, (std::vector<int>{0, 31, 60}));
    ASSERT_EQ(r.motion.num_frames, 61);
    for (int i = 0; i < 3; ++i) expect_key_hit(s.blender, r.motion, r.key_frames[i], keys[i]);
  }
  // Neither: the samples' own speed along the route. Two keys of one clip, the later later in
  // it: the clip's own time, 10 → 60 in 50 frames, the clip played through frame by frame.
  {
    const std::vector<Key> keys{s.key(10), s.key(60)};
    const InbetweenResult r = inbetween(s.blender, s.set, keys);
    ASSERT_EQ(r.key_frames.size(), 2u);
    EXPECT_EQ(r.key_frames[1], 50);
    ASSERT_EQ(r.motion.num_frames, r.key_frames[1] + 1);
    for (int k = 0; k <= 50; ++k) expect_key_hit(s.blender, r.motion, k, s.key(10 + k));
  }
}

// A real walk at 120 fps (an exporter's figure-8 walk): untimed keys 500 frames apart play it
// between them as captured. The map's route walked them in 3.9 s, and the clip played 7 % fast
// skated 0.31 of its transitions, 78 cm/s in contact, against the captured frames' 0.25 and 60.
// Backwards, the body must turn where the clips do not: noted.
TEST(SynthInbetween, UntimedKeysOfOneClipPlayItAsCaptured) {
  const std::string file = "other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh";
  MOTIONMAP_REQUIRE_SHARED(file);
  const std::vector<Clip> clips{io::load_clip(motionmap::test::shared_file(file))};
  const pipeline::ClipMap map = pipeline::map_clips(clips, {});
  const MapBlender blender(clips, *map.features, map.embedding.coordinates);
  const Clip& walk = clips[0];
  const int first = 100, last = 600;
  const std::vector<Key> keys{
      sample_key(blender, find_sample(*map.features, 0, first), walk.motion, first),
      sample_key(blender, find_sample(*map.features, 0, last), walk.motion, last)};
  const InbetweenResult r = inbetween(blender, *map.features, keys);
  ASSERT_EQ(r.key_frames, (std::vector<int>{0, last - first}));
  const Motion captured = walk.motion.frames(first, last + 1);
  const Feet feet = find_feet(walk.skeleton);
  const Skating made = measure_skating(walk.skeleton, r.motion, feet);
  const Skating own = measure_skating(walk.skeleton, captured, feet);
  std::printf(
      "[ figures  ] untimed keys %d and %d of %s: %d frames; skating %.3f, %.1f cm/s in contact "
      "(the captured frames %.3f, %.1f)\n",
      first, last, file.c_str(), r.motion.num_frames - 1, made.ratio, made.contact_speed_cm_s,
      own.ratio, own.contact_speed_cm_s);
  EXPECT_LE(made.ratio, own.ratio);
  EXPECT_LE(made.contact_speed_cm_s, own.contact_speed_cm_s);
  EXPECT_TRUE(r.notes.empty()) << r.notes.front();

  // The other way round, frame 600 to frame 100: no clip plays backwards, and the clips played
  // leave the body facing 139° away from frame 100's heading. Turned as it walks, the body walks
  // askew and the feet slide (142 cm/s in contact); a note says so, and with free roots, which
  // leave the later key's heading where the clips carry it, neither (63 cm/s).
  const std::vector<Key> back{keys[1], keys[0]};
  const InbetweenResult askew = inbetween(blender, *map.features, back);
  ASSERT_EQ(askew.notes.size(), 1u);
  EXPECT_NE(askew.notes[0].find("the clips played leave the body facing "), std::string::npos)
      << askew.notes[0];
  EXPECT_NE(askew.notes[0].find("° away from key 2's heading in its clip: it turns that in"),
            std::string::npos)
      << askew.notes[0];
  InbetweenOptions free;
  free.free_roots = true;
  const InbetweenResult freed = inbetween(blender, *map.features, back, free);
  EXPECT_TRUE(freed.notes.empty()) << freed.notes.front();
  const Skating turned = measure_skating(walk.skeleton, askew.motion, feet);
  const Skating faced = measure_skating(walk.skeleton, freed.motion, feet);
  std::printf(
      "[ figures  ] keys %d and %d of %s: %.3f, %.1f cm/s in contact; free roots %.3f, "
      "%.1f cm/s (%s)\n",
      last, first, file.c_str(), turned.ratio, turned.contact_speed_cm_s, faced.ratio,
      faced.contact_speed_cm_s, askew.notes[0].c_str());
  EXPECT_GT(turned.contact_speed_cm_s, 1.5 * faced.contact_speed_cm_s);
}

TEST(SynthInbetween, AKeyPoseOffTheMapIsHitThroughTheDisplacementMap) {
  // A key whose pose is not the blend at its point (an arm raised, the body lifted, turned and
  // moved): hit exactly, and the change fades out towards the neighbouring keys.
  const Synthetic s;
  std::vector<Key> keys{s.key(10), s.key(50), s.key(90)};
  Key& middle = keys[1];
  middle.pose.rotation(0, 3) = axis_rotation(Axis::X, 0.7) * middle.pose.rotation(0, 3);
  middle.pose.rotation(0, 0) = axis_rotation(Axis::Y, 0.5) * middle.pose.rotation(0, 0);
  middle.pose.translation(0, 0) += Eigen::Vector3d(40, 5, -20);
  const InbetweenResult r = inbetween(s.blender, s.set, keys, between(19));
  ASSERT_EQ(r.motion.num_frames, 41);
  for (int i = 0; i < 3; ++i) expect_key_hit(s.blender, r.motion, r.key_frames[i], keys[i]);
  // Half-way to the next key, about half the arm's change is left.
  const InbetweenResult plain =
      inbetween(s.blender, s.set, std::vector<Key>{s.key(10), s.key(50), s.key(90)}, between(19));
  const double half = rotation_angle(r.motion.rotation(30, 3), plain.motion.rotation(30, 3));
  EXPECT_NEAR(half, 0.35, 0.05);
  // The root moves smoothly: no step between frames larger than a few times the clip's own.
  const int root = s.blender.motion_root();
  double worst = 0.0;
  for (int k = 1; k < r.motion.num_frames; ++k)
    worst =
        std::max(worst, (r.motion.translation(k, root) - r.motion.translation(k - 1, root)).norm());
  EXPECT_LT(worst, 4.0 * 30.0 * s.clip.motion.frame_time + 40.0 / 20);
}

TEST(SynthInbetween, MapPointKeysTakeTheBlendAndLeaveTheRootFree) {
  const Synthetic s;
  Key a, b;
  a.point = s.blender.sample_point(20);
  a.label = "a";
  b.point = s.blender.sample_point(70);
  b.label = "b";
  const InbetweenResult r = inbetween(s.blender, s.set, std::vector<Key>{a, b}, between(9));
  ASSERT_EQ(r.motion.num_frames, 11);
  // The blend at the keys' points: the samples' poses (non-root joints).
  for (int j = 1; j < 5; ++j) {
    EXPECT_LE(rotation_angle(r.motion.rotation(0, j), s.clip.motion.rotation(20, j)), 1e-9);
    EXPECT_LE(rotation_angle(r.motion.rotation(10, j), s.clip.motion.rotation(70, j)), 1e-9);
  }
  // Free root: starts at the origin, heading 0, as synthesize() does.
  EXPECT_LE(std::abs(r.motion.translation(0, 0).x()), 1e-12);
  EXPECT_LE(std::abs(features::heading_angle(r.motion.rotation(0, 0))), 1e-12);
  // Mixed with a key with a pose: its placement rules the whole root.
  const Key c = s.key(90);
  const InbetweenResult m = inbetween(s.blender, s.set, std::vector<Key>{a, c}, between(9));
  expect_key_hit(s.blender, m.motion, 10, c);
}

TEST(SynthInbetween, BadKeysAndOptions) {
  const Synthetic s;
  EXPECT_EQ(parameter_message([&] { inbetween(s.blender, s.set, std::vector<Key>{s.key(1)}); }),
            "keys: 1 given; in-betweening needs at least 2");
  EXPECT_EQ(parameter_message([&] {
              inbetween(s.blender, s.set, std::vector<Key>{s.key(1, 0.0), s.key(5)});
            }),
            "keys: 1 of 2 keys have a time; give a time to every key or to none");
  EXPECT_EQ(
      parameter_message([&] {
        inbetween(s.blender, s.set, std::vector<Key>{s.key(1, 0.0), s.key(5, 1.0)}, between(3));
      }),
      "frames_between: the keys have times; give either times or frames between keys");
  EXPECT_EQ(parameter_message([&] {
              inbetween(s.blender, s.set, std::vector<Key>{s.key(1, 0.0), s.key(5, 0.01)});
            }),
            "key 2 (walking.bvh:5): its time 0.01 s is not at least a frame (0.0333333 s) after "
            "the previous key's 0 s");
  EXPECT_EQ(parameter_message([&] {
              inbetween(s.blender, s.set, std::vector<Key>{s.key(1), s.key(5)}, between(-2));
            }),
            "frames_between: -2 is out of range (must be in [0, 100000], or −1 = not given)");
  InbetweenOptions unpriced;
  unpriced.priced_jump_samples = -1;
  EXPECT_EQ(parameter_message([&] {
              inbetween(s.blender, s.set, std::vector<Key>{s.key(1), s.key(5)}, unpriced);
            }),
            "priced_jump_samples: -1 is negative (must be ≥ 0: 0 prices every jump by its map "
            "distance)");
  Key wrong = s.key(5);
  wrong.pose.resize(1, 3);
  EXPECT_EQ(parameter_message([&] {
              inbetween(s.blender, s.set, std::vector<Key>{s.key(1), wrong});
            }),
            "key 2 (walking.bvh:5): its pose has 1 frames of 3 joints; a key pose is one frame of "
            "the map's 5 joints");
  Key nan = s.key(5);
  nan.point.x() = NAN;
  EXPECT_EQ(parameter_message([&] {
              inbetween(s.blender, s.set, std::vector<Key>{s.key(1), nan});
            }),
            "key 2 (walking.bvh:5): its map point is not finite");
  EXPECT_THROW(sample_key(s.blender, 120, s.clip.motion, 5), ParameterError);
  EXPECT_THROW(sample_key(s.blender, 5, s.clip.motion, 120), ParameterError);
}

// ---- real motion capture --------------------------------------------------------------------

// Bandai walks and runs mapped together (isomap, every other frame); walk_feminine is kept out
// of the map.
struct Library {
  std::vector<Clip> clips;
  pipeline::ClipMapOptions options;
  std::shared_ptr<const features::FeatureSet> set;
  Eigen::MatrixXd coords;
  std::unique_ptr<MapBlender> blender;
  mapfile::MapFile file;

  static std::string path(const std::string& name) {
    return motionmap::test::shared_file("bandai/dataset-1_" + name + "_001.bvh");
  }
  Library() {
    for (const char* name : {"walk_angry", "walk_old", "walk_proud", "run_angry", "run_old"})
      clips.push_back(io::load_clip(path(name)));
    options.features.stride = 2;
    options.embed.method = embed::Method::Isomap;
    pipeline::ClipMap map = pipeline::map_clips(clips, options);
    set = map.features;
    coords = map.embedding.coordinates;
    blender = std::make_unique<MapBlender>(clips, *set, coords);
    file = mapfile::make_map_file(clips, std::move(map), options);
  }
  // Frame `frame` of `clip` as a key: its sample's point when it is one, else placed on the map
  // as `map --onto` places frames.
  Key key(const Clip& clip, int clip_index, int frame) const {
    Key k;
    const int sample = clip_index < 0 ? -1 : find_sample(*set, clip_index, frame);
    if (sample >= 0) {
      k = sample_key(*blender, sample, clip.motion, frame);
    } else {
      const mapfile::Placement placed = mapfile::place_clips(
          std::span<const Clip>(&clip, 1), file,
          {.first_frame = frame, .end_frame = frame + 1, .stride = 1, .keep_first = true});
      k.point = Eigen::Vector2d(placed.coordinates(0, 0), placed.coordinates(0, 1));
      k.pose.frame_time = clip.motion.frame_time;
      k.pose.resize(1, clip.motion.num_joints);
      for (int j = 0; j < clip.motion.num_joints; ++j) {
        k.pose.rotation(0, j) = clip.motion.rotation(frame, j);
        k.pose.translation(0, j) = clip.motion.translation(frame, j);
      }
    }
    k.label = clip.path + ":" + std::to_string(frame);
    return k;
  }
};

class SynthInbetweenBandai : public testing::Test {
 protected:
  void SetUp() override {
    for (const char* name :
         {"walk_angry", "walk_old", "walk_proud", "run_angry", "run_old", "walk_feminine"}) {
      if (!std::filesystem::exists(Library::path(name)))
        GTEST_SKIP() << "shared data file absent: " << Library::path(name);
    }
    static const Library library;
    lib = &library;
  }
  const Library* lib = nullptr;
};

TEST_F(SynthInbetweenBandai, RoutesStayInTheDataAndKeysAreHitExactly) {
  const Library& L = *lib;
  // A walk frame that is a sample, one that is not (odd: placed), a run frame, another walk.
  const std::vector<Key> keys{L.key(L.clips[0], 0, 20), L.key(L.clips[1], 1, 101),
                              L.key(L.clips[3], 3, 40), L.key(L.clips[2], 2, 200)};
  EXPECT_GE(find_sample(*L.set, 0, 20), 0);
  EXPECT_LT(find_sample(*L.set, 1, 101), 0);
  for (const int n : {-1, 0, 30}) {
    SCOPED_TRACE(testing::Message() << "frames between " << n);
    const InbetweenResult r = inbetween(*L.blender, *L.set, keys, between(n));
    const MapField field(*L.blender);
    for (std::size_t k = 0; k < r.points.size(); ++k) {
      EXPECT_TRUE(field.valid(r.points[k])) << k;
      EXPECT_FALSE(r.validity[k].clamped) << k;
    }
    EXPECT_EQ(r.outside_frames, 0);
    for (const auto& route : r.routes) {
      for (std::size_t i = 1; i < route.size(); ++i)
        EXPECT_TRUE(field.segment_valid(route[i - 1], route[i]));
    }
    for (int i = 0; i < 4; ++i) expect_key_hit(*L.blender, r.motion, r.key_frames[i], keys[i]);
    if (n >= 0) {
      EXPECT_EQ(r.motion.num_frames, 3 * (n + 1) + 1);
    }
    for (const auto& q : r.motion.rotations) ASSERT_TRUE(q.coeffs().allFinite());
    // The feet were cleaned (the keys above are exact all the same), and slide no more than the
    // blend's did.
    EXPECT_TRUE(r.feet_cleaned);
    InbetweenOptions raw_options = between(n);
    raw_options.clean_feet = false;
    const InbetweenResult raw = inbetween(*L.blender, *L.set, keys, raw_options);
    const Feet feet = find_feet(L.blender->skeleton());
    const Skating before = measure_skating(L.blender->skeleton(), raw.motion, feet);
    const Skating after = measure_skating(L.blender->skeleton(), r.motion, feet);
    std::printf("frames between %d: skating %.3f → %.3f, %.1f → %.1f cm/s in contact\n", n,
                before.ratio, after.ratio, before.contact_speed_cm_s, after.contact_speed_cm_s);
    EXPECT_LE(after.contact_speed_cm_s, before.contact_speed_cm_s + 1.0);
    // The keys stay as given, root included, and the clean-up's root lowering fades to nothing
    // towards them: next to a key the root is lowered by at most half the most it is lowered
    // anywhere (a fade over ±blend_seconds), so it never steps down at a key.
    const int root = L.blender->motion_root();
    const int u = static_cast<int>(L.blender->options().up);
    const auto lowered = [&](int f) {
      return raw.motion.translation(f, root)[u] - r.motion.translation(f, root)[u];
    };
    double most = 0.0;
    for (int f = 0; f < r.motion.num_frames; ++f) most = std::max(most, lowered(f));
    for (const int k : r.key_frames) {
      EXPECT_EQ(lowered(k), 0.0) << "key frame " << k;
      for (const int next : {k - 1, k + 1}) {
        if (next >= 0 && next < r.motion.num_frames) {
          EXPECT_LE(lowered(next), 0.5 * most + 1e-9) << "key frame " << k << ", frame " << next;
        }
      }
    }
  }
}

TEST_F(SynthInbetweenBandai, UntimedKeysOfAWalkTakeTheWalksTimeToCoverTheirDistance) {
  // Two keys of one walk, 180 frames (6 s) apart: near the same phase, so the route between their
  // map points is short, but the root must cover the walk's distance between them. Untimed, the
  // segment lasts at least that distance at the root speed of the samples near the keys, and the
  // clip route plays the walk through: its feet skate as the captured frames between the keys do.
  // (Timed by the map route alone it lasted 30 frames, its feet sliding 125 cm/s in contact.)
  const Library& L = *lib;
  const Clip& walk = L.clips[1];  // walk_old
  const int first = 20, last = 200;
  const std::vector<Key> keys{L.key(walk, 1, first), L.key(walk, 1, last)};
  const InbetweenResult r = inbetween(*L.blender, *L.set, keys);
  for (int i = 0; i < 2; ++i) expect_key_hit(*L.blender, r.motion, r.key_frames[i], keys[i]);
  const Motion captured = walk.motion.frames(first, last + 1);
  const Feet feet = find_feet(L.blender->skeleton());
  const Skating made = measure_skating(L.blender->skeleton(), r.motion, feet);
  const Skating own = measure_skating(walk.skeleton, captured, feet);
  std::printf(
      "[ figures  ] untimed keys %d and %d of the old walk: %d frames (the walk's %d); skating "
      "%.3f, %.1f cm/s in contact (the walk's frames between them %.3f, %.1f)\n",
      first, last, r.motion.num_frames - 1, last - first, made.ratio, made.contact_speed_cm_s,
      own.ratio, own.contact_speed_cm_s);
  EXPECT_NEAR(r.key_frames[1], last - first, 0.15 * (last - first));
  EXPECT_LE(made.ratio, own.ratio + 0.03);
  EXPECT_LE(made.contact_speed_cm_s, 1.1 * own.contact_speed_cm_s);
}

// The map of all 12 Bandai takes (walks, runs, bows, a dash, a punch), the default isomap.
class SynthInbetweenBandaiLibrary : public ::testing::Test {
 protected:
  struct Library {
    std::vector<Clip> clips;
    pipeline::ClipMap map;
    std::unique_ptr<MapBlender> blender;
    Key key(int clip, int frame) const {
      return sample_key(*blender, find_sample(*map.features, clip, frame), clips[clip].motion,
                        frame);
    }
    // The largest distance a joint moves between two frames of the motion.
    double largest_step(const Motion& m) const { return test::max_jump(blender->skeleton(), m); }
    // The in-between of `keys` with free roots (InbetweenOptions::free_roots), untimed.
    InbetweenResult with_free_roots(const std::vector<Key>& keys) const {
      InbetweenOptions free;
      free.free_roots = true;
      return inbetween(*blender, *map.features, keys, free);
    }
  };
  static inline const std::vector<std::string> kNames{
      "bow_normal", "bow_old",    "dash_normal",   "punch_normal", "run_angry",  "run_normal",
      "run_old",    "walk_angry", "walk_feminine", "walk_old",     "walk_proud", "walk_tired"};
  static int index(const std::string& name) {
    return static_cast<int>(std::find(kNames.begin(), kNames.end(), name) - kNames.begin());
  }
  static void SetUpTestSuite() {
    auto made = std::make_unique<Library>();
    for (const std::string& n : kNames) {
      const std::string path = motionmap::test::shared_file("bandai/dataset-1_" + n + "_001.bvh");
      if (!std::filesystem::exists(path)) return;
      made->clips.push_back(io::load_clip(path));
    }
    made->map = pipeline::map_clips(made->clips, {});
    made->blender = std::make_unique<MapBlender>(made->clips, *made->map.features,
                                                 made->map.embedding.coordinates);
    lib = std::move(made);
  }
  static void TearDownTestSuite() { lib.reset(); }
  void SetUp() override {
    if (!lib) GTEST_SKIP() << "shared data files absent: bandai/";
  }
  static inline std::unique_ptr<Library> lib;
};

TEST_F(SynthInbetweenBandaiLibrary, TheKeysDisplacementMapDoesNotPushAFootIntoTheFloor) {
  // The punch's key to the tired walk's, 130 frames between: the keys' displacement map, spread
  // over the segment, bends the legs towards the other key's stance, pushing the right ankle
  // 4.0 cm into the floor raw. (A walk's key to a punch's pushed it 6.3 cm, 2.6 cm with the
  // contacts held, before keep_above_floor; its route now bridges to the punch's own frames, its
  // jump crossfaded.) The clean-up lifts an ankle more than kFloorSlack leg lengths (1.7 cm) under
  // the floor back to that depth.
  const Library& L = *lib;
  const int from = index("punch_normal"), to = index("walk_tired");
  const std::vector<Key> keys{L.key(from, 50), L.key(to, 60)};
  const MapBlender& blender = *L.blender;
  const std::vector<Clip>& clips = L.clips;
  InbetweenOptions options;
  options.frames_between = 130;
  InbetweenOptions raw_options = options;
  raw_options.clean_feet = false;
  const InbetweenResult raw = inbetween(blender, *L.map.features, keys, raw_options);
  const InbetweenResult r = inbetween(blender, *L.map.features, keys, options);
  const Feet feet = find_feet(blender.skeleton());
  for (int side = 0; side < 2; ++side) {
    // The floor: the lower of the two captured clips' (their ankles' 2 % quantiles).
    const auto from_contacts = detect_contacts(clips[from].skeleton, clips[from].motion, feet);
    const auto to_contacts = detect_contacts(clips[to].skeleton, clips[to].motion, feet);
    const double floor = std::min(from_contacts[side].floor, to_contacts[side].floor);
    const double slack = kFloorSlack * from_contacts[side].leg_length;
    const auto lowest = [&](const Motion& m) {
      double low = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& a :
           joint_trajectory(blender.skeleton(), m, feet.legs[side].ankle))
        low = std::min(low, a.y());
      return low;
    };
    std::printf("[ figures  ] %s ankle at most %.1f cm under the floor raw, %.1f cleaned\n",
                side == 0 ? "left" : "right", floor - lowest(raw.motion), floor - lowest(r.motion));
    EXPECT_GE(lowest(r.motion), floor - slack - 0.5) << "side " << side;
    if (side == 1) {
      EXPECT_LT(lowest(raw.motion), floor - 3.5);  // the cause is there
    }
  }
}

TEST_F(SynthInbetweenBandaiLibrary, KeysFurtherApartThanTheClipsWalkInTheTimeAreNoted) {
  // Each key's root stands where it stood in its clip: the proud walk's frame 9 and the bow's
  // frame 40 stand 3.6 m apart, which 30 frames between them cover at 3.5 m/s while the clips
  // there move at 0.37: the root glides and the feet slide, and the result says so, with the time
  // the clips would take. Untimed, the segment takes that time; keys of one walk at its own
  // timing glide nowhere: no note.
  const Library& L = *lib;
  const int walk = index("walk_proud"), bow = index("bow_normal");
  const auto glide_notes = [](const InbetweenResult& r) {
    return notes_saying(r, "apart (each where it stood in its clip)");
  };
  InbetweenOptions quick;
  quick.frames_between = 30;
  const std::vector<Key> far{L.key(walk, 9), L.key(bow, 40)};
  const InbetweenResult r = inbetween(*L.blender, *L.map.features, far, quick);
  ASSERT_EQ(glide_notes(r), 1) << ::testing::PrintToString(r.notes);
  const std::string& note = r.notes.front();
  std::printf("[ figures  ] note: %s\n", note.c_str());
  EXPECT_NE(note.find("key 1 to key 2: their roots stand 3.63 m apart"), std::string::npos);
  EXPECT_NE(note.find("the feet slide"), std::string::npos);
  // The time it names is the untimed segment's (the clips' pace over the keys' distance).
  const InbetweenResult untimed = inbetween(*L.blender, *L.map.features, far);
  EXPECT_EQ(glide_notes(untimed), 0) << ::testing::PrintToString(untimed.notes);
  const std::string frames = std::to_string(untimed.key_frames[1] - 1) + " frames between";
  EXPECT_NE(note.find(frames), std::string::npos) << frames;
  // The walk's frames 9 and 60 at its own timing; 30 frames between them is 1.8 times its pace.
  InbetweenOptions own;
  own.frames_between = 50;
  const std::vector<Key> walked{L.key(walk, 9), L.key(walk, 60)};
  EXPECT_EQ(glide_notes(inbetween(*L.blender, *L.map.features, walked, own)), 0);
  EXPECT_EQ(glide_notes(inbetween(*L.blender, *L.map.features, walked, quick)), 1);
}

TEST_F(SynthInbetweenBandaiLibrary, KeysTheClipsDoNotWalkBetweenAreNoted) {
  // Timed as the clips walk their distance, keys can still ask what the clips played do not do:
  // the old walk's frame 130 to its frame 100, 30 frames later, is a walk's 30 frames of distance
  // behind it; the bow's frame 70 to the feminine walk's frame 21 (its first steps) stand 3.9 m
  // apart while the route plays the bow and those steps. The root glides the rest and the feet
  // slide (0.52 and 55 cm/s where the feminine walk skates 0.41 and 48): said. Keys of the walk
  // forward at its own timing glide nowhere: no note.
  const Library& L = *lib;
  const int old = index("walk_old"), bow = index("bow_old"), feminine = index("walk_feminine");
  const auto glide_notes = [](const InbetweenResult& r) {
    return notes_saying(r, "the root glides that in");
  };
  InbetweenOptions thirty;
  thirty.frames_between = 29;
  const std::vector<Key> behind{L.key(old, 130), L.key(old, 100)};
  const InbetweenResult back = inbetween(*L.blender, *L.map.features, behind, thirty);
  ASSERT_EQ(glide_notes(back), 1) << ::testing::PrintToString(back.notes);
  EXPECT_EQ(back.notes.size(), 1u) << ::testing::PrintToString(back.notes);  // in time for it
  std::printf("[ figures  ] note: %s\n", back.notes.front().c_str());
  EXPECT_NE(back.notes.front().find("key 1 to key 2: the clips played carry the root"),
            std::string::npos);
  const std::vector<Key> ahead{L.key(old, 100), L.key(old, 130)};
  EXPECT_EQ(glide_notes(inbetween(*L.blender, *L.map.features, ahead, thirty)), 0);
  const std::vector<Key> apart{L.key(bow, 70), L.key(feminine, 21)};
  const InbetweenResult untimed = inbetween(*L.blender, *L.map.features, apart);
  ASSERT_EQ(glide_notes(untimed), 1) << ::testing::PrintToString(untimed.notes);
  std::printf("[ figures  ] note: %s\n", untimed.notes.back().c_str());
  const Feet feet = find_feet(L.blender->skeleton());
  const Skating slid = measure_skating(L.blender->skeleton(), untimed.motion, feet);
  const Skating own = measure_skating(L.blender->skeleton(), L.clips[feminine].motion, feet);
  std::printf("[ figures  ] skating %.3f, %.1f cm/s in contact (the feminine walk %.3f, %.1f)\n",
              slid.ratio, slid.contact_speed_cm_s, own.ratio, own.contact_speed_cm_s);
}

TEST_F(SynthInbetweenBandaiLibrary, FreeRootsHitEveryPoseAndPlaceOnlyTheFirstRoot) {
  // The bow's frame 70 to the feminine walk's frame 21, untimed: with each key's root where it
  // stood, the root glides 4.6 m (above). With free roots the first key's root stands where it
  // stood, the second key's pose is hit but for its root's place and heading, which are where
  // the clips carry them: nothing glides, and the feet stand (below the walk's own skating).
  const Library& L = *lib;
  const int bow = index("bow_old"), feminine = index("walk_feminine");
  const std::vector<Key> keys{L.key(bow, 70), L.key(feminine, 21)};
  const InbetweenResult r = L.with_free_roots(keys);
  EXPECT_TRUE(r.notes.empty()) << ::testing::PrintToString(r.notes);
  expect_key_hit(*L.blender, r.motion, r.key_frames[0], keys[0]);
  const int k = r.key_frames[1], root = L.blender->motion_root();
  const Axis up = L.blender->options().up;
  for (int j = 0; j < r.motion.num_joints; ++j) {
    if (j == root) continue;
    EXPECT_LE(rotation_angle(r.motion.rotation(k, j), keys[1].pose.rotation(0, j)), 1e-9) << j;
  }
  const RootPlacement got = root_placement(r.motion, k, root, up);
  const RootPlacement want = root_placement(keys[1].pose, 0, root, up);
  EXPECT_LE(rotation_angle(axis_rotation(up, -got.heading) * r.motion.rotation(k, root),
                           axis_rotation(up, -want.heading) * keys[1].pose.rotation(0, root)),
            1e-9);  // the tilt
  const Eigen::Vector3d u = Eigen::Vector3d::Unit(static_cast<int>(up));
  EXPECT_NEAR(r.motion.translation(k, root).dot(u), keys[1].pose.translation(0, root).dot(u),
              1e-9);  // the height
  const Feet feet = find_feet(L.blender->skeleton());
  const Skating made = measure_skating(L.blender->skeleton(), r.motion, feet);
  const Skating own = measure_skating(L.blender->skeleton(), L.clips[feminine].motion, feet);
  std::printf(
      "[ figures  ] free roots: %d frames, key 2's root %.0f cm from where it stood; skating "
      "%.3f, %.1f cm/s in contact (the feminine walk %.3f, %.1f)\n",
      r.motion.num_frames, (got.floor - want.floor).norm(), made.ratio, made.contact_speed_cm_s,
      own.ratio, own.contact_speed_cm_s);
  EXPECT_LE(made.ratio, own.ratio);
  EXPECT_LE(made.contact_speed_cm_s, own.contact_speed_cm_s);
}

TEST_F(SynthInbetweenBandaiLibrary, UntimedKeysOfTwoClipsTakeAtLeastTheJumpsCrossfade) {
  // The old walk's frame 224 to the tired walk's frame 78, untimed, free roots: the keys'
  // distance asks for no time, and the map lays the two poses close, so the route's own time was
  // 3 frames: the walk turned into the other in 0.1 s, a joint moving 21 cm in a frame (the
  // walks' fastest: 12.5), the feet sliding 4.1 m/s in contact, every transition skating. A route
  // between two clips jumps, and its crossfade takes kJumpFadeSeconds: the segment takes at least
  // that. (With the rule, over 43 random untimed pairs of two takes that had taken less than
  // 0.7 s, the mean skating went from 0.66 to 0.55 of the transitions, the mean speed in contact
  // from 135 to 107 cm/s.)
  const Library& L = *lib;
  const int from = index("walk_old"), to = index("walk_tired");
  const std::vector<Key> keys{L.key(from, 224), L.key(to, 78)};
  const InbetweenResult r = L.with_free_roots(keys);
  const double dt = L.blender->frame_time();
  EXPECT_GE(r.key_frames[1] * dt, kJumpFadeSeconds - 0.5 * dt);
  const Feet feet = find_feet(L.blender->skeleton());
  const Skating made = measure_skating(L.blender->skeleton(), r.motion, feet);
  double slide = 0.0, step = 0.0;
  for (const int c : {from, to}) {
    slide = std::max(
        slide, measure_skating(L.blender->skeleton(), L.clips[c].motion, feet).contact_speed_cm_s);
    step = std::max(step, L.largest_step(L.clips[c].motion));
  }
  std::printf(
      "[ figures  ] the old walk's key to the tired walk's, free roots, untimed: %d frames; "
      "skating %.3f, %.1f cm/s in contact (the walks at most %.1f); a joint's largest step "
      "%.1f cm (the walks' %.1f)\n",
      r.motion.num_frames, made.ratio, made.contact_speed_cm_s, slide, L.largest_step(r.motion),
      step);
  EXPECT_LE(made.contact_speed_cm_s, 2.0 * slide);
  EXPECT_LE(L.largest_step(r.motion), 1.5 * step);
}

TEST_F(SynthInbetweenBandaiLibrary, UntimedKeysOfTwoGaitsTakeTheTimeTheirPhasesAreApart) {
  // The tired walk's frame 178 to the feminine walk's frame 223, untimed, free roots: both keys
  // stand at one phase of their gait (the left foot down, the right about to strike), so a step
  // cycle lies between them. Timed by their route and the jump's crossfade alone (0.7 s, half a
  // cycle) the standing foot slid. Untimed keys of two gaits take the time their phases are
  // apart, in whole cycles more, nearest that.
  const Library& L = *lib;
  const int from = index("walk_tired"), to = index("walk_feminine");
  const std::vector<Key> keys{L.key(from, 178), L.key(to, 223)};
  const InbetweenResult r = L.with_free_roots(keys);
  InbetweenOptions rushed;
  rushed.free_roots = true;
  rushed.frames_between = 20;
  const InbetweenResult half = inbetween(*L.blender, *L.map.features, keys, rushed);
  const Feet feet = find_feet(L.blender->skeleton());
  const Skeleton& skeleton = L.blender->skeleton();
  const Skating made = measure_skating(skeleton, r.motion, feet);
  const Skating short_made = measure_skating(skeleton, half.motion, feet);
  Skating walks;
  for (const int c : {from, to}) {
    const Skating own = measure_skating(skeleton, L.clips[c].motion, feet);
    walks.ratio = std::max(walks.ratio, own.ratio);
    walks.contact_speed_cm_s = std::max(walks.contact_speed_cm_s, own.contact_speed_cm_s);
  }
  std::printf(
      "[ figures  ] the tired walk's key to the feminine walk's, free roots, untimed: %d frames; "
      "skating %.3f, %.1f cm/s in contact (the walks at most %.3f, %.1f); 20 frames between: "
      "%.3f, %.1f cm/s\n",
      r.motion.num_frames, made.ratio, made.contact_speed_cm_s, walks.ratio,
      walks.contact_speed_cm_s, short_made.ratio, short_made.contact_speed_cm_s);
  // Measured: 41 frames, 0.400 of the transitions and 66 cm/s in contact (the walks at most 0.413,
  // 58; on the CLI's default map of the 12 takes, 41 frames, 0.350 and 58); 20 frames between,
  // 0.619 and 74. (Over 16–48 frames between, the feet slide 74–124 cm/s in contact up to 28
  // frames, 57–75 from 34 on.)
  EXPECT_GE(r.key_frames[1], 30);  // a walk's cycle: 1.2 s (the tired), 1.4 s (the feminine)
  EXPECT_LE(made.ratio, walks.ratio);
  EXPECT_LE(made.contact_speed_cm_s, 1.2 * walks.contact_speed_cm_s);
  EXPECT_GT(short_made.ratio, walks.ratio + 0.1);  // the cause is there
  // Timed so, the in-between says it is out of step and how long it takes in step: the untimed
  // one's time. Timed in step, or untimed, it says nothing of the step.
  const auto step_notes = [](const InbetweenResult& result) {
    std::vector<std::string> notes;
    for (const std::string& note : result.notes)
      if (note.find("out of step") != std::string::npos) notes.push_back(note);
    return notes;
  };
  const std::vector<std::string> rushed_notes = step_notes(half);
  ASSERT_EQ(rushed_notes.size(), 1u);
  EXPECT_NE(rushed_notes[0].find("in step it takes 1.33 s (" + std::to_string(r.key_frames[1] - 1) +
                                 " frames between the keys)"),
            std::string::npos)
      << rushed_notes[0];
  EXPECT_NE(rushed_notes[0].find(" or 1.9 times as fast as the clips, and the feet slide"),
            std::string::npos)
      << rushed_notes[0];
  EXPECT_TRUE(step_notes(r).empty());
  InbetweenOptions in_step = rushed;
  in_step.frames_between = static_cast<int>(r.key_frames[1] - 1);
  EXPECT_TRUE(step_notes(inbetween(*L.blender, *L.map.features, keys, in_step)).empty());
}

// The library's clips, read on demand as a saved map's are.
class LibraryClips : public ClipSource {
 public:
  explicit LibraryClips(const std::vector<Clip>& clips) : m_clips(clips) {}
  std::shared_ptr<const Clip> clip(int c) const override {
    return std::make_shared<const Clip>(m_clips[static_cast<std::size_t>(c)]);
  }

 private:
  const std::vector<Clip>& m_clips;
};

TEST_F(SynthInbetweenBandaiLibrary, JumpsOnABlenderReadingItsClipsOnDemandArePricedByPoses) {
  // A blender reading its clips on demand (a saved map's) of at most priced_jump_samples samples
  // prices its routes' jumps by their poses, every sample's read first: the in-between is the one
  // of the blender given the clips, bit for bit. Above (a larger map, where reading every pose
  // would take longer than the search) by their map distance alone, and against the bridge by
  // their poses: a walk's key, a dash's and a bow's then move a joint 18.1 cm in a frame, as
  // priced by poses (the clips' fastest 31.7; on the CLI's saved map of the 12 takes, before the
  // chain of jumps was priced against the bridge, 71).
  const Library& L = *lib;
  const auto source = std::make_shared<const LibraryClips>(L.clips);
  const MapBlender on_demand(source, summarize_clips(L.clips, *L.map.features), *L.map.features,
                             L.map.embedding.coordinates);
  ASSERT_TRUE(on_demand.reads_on_demand());
  const std::vector<Key> keys{L.key(index("walk_old"), 50), L.key(index("dash_normal"), 10),
                              L.key(index("bow_old"), 80)};
  const InbetweenResult in_memory = inbetween(*L.blender, *L.map.features, keys);
  const InbetweenResult priced = inbetween(on_demand, *L.map.features, keys);
  EXPECT_EQ(priced.motion.rotations, in_memory.motion.rotations);
  EXPECT_EQ(priced.motion.translations, in_memory.motion.translations);
  InbetweenOptions by_distance;
  by_distance.priced_jump_samples = 0;
  const InbetweenResult unpriced = inbetween(on_demand, *L.map.features, keys, by_distance);
  double clips = 0.0;
  for (const char* name : {"walk_old", "dash_normal", "bow_old"})
    clips = std::max(clips, L.largest_step(L.clips[static_cast<std::size_t>(index(name))].motion));
  std::printf(
      "[ figures  ] a walk's, a dash's and a bow's keys read on demand: a joint's largest step "
      "%.1f cm priced by poses, %.1f by map distance (the clips' %.1f)\n",
      L.largest_step(priced.motion), L.largest_step(unpriced.motion), clips);
  EXPECT_LE(L.largest_step(unpriced.motion), clips);
}

TEST_F(SynthInbetweenBandaiLibrary, AnInbetweenBetweenActionsMovesNoFasterThanItsClips) {
  // Keys of different actions; no joint may move further in a frame than in the keys' clips.
  // - A bow's key to a walk's: the route plays the bow on, then the walk up to its key. Cut at
  //   the jump, and with a foot held while the keys' root, spread over the bow, glided it 72 cm
  //   away, a joint moved 32 cm in a frame raw and 62 cm cleaned (the bow's fastest 4.8 cm, the
  //   walk's 10.3).
  // - A walk's key, a dash's, a bow's: from the dash the cheapest chain of jumps to the bow
  //   played a walk backwards, hopping between clips: 49 cm in a frame (the dash's fastest 33).
  //   Backward jumps within a clip are not taken now, and a bridge cheaper than any chain is.
  // - The same keys by the grid route, which passes through other actions' poses between them:
  //   within 1.5 times the clips' fastest step (the bow's key to the walk's: 14.4 cm against the
  //   walk's 10.3). Its kriging's neighbours change from one action's samples to another's
  //   between two points of the route: with the weights unsmoothed a joint moved 61 cm in a
  //   frame from the walk towards the dash, and 18 cm from the bow to the walk.
  const Library& L = *lib;
  const std::vector<std::vector<std::pair<std::string, int>>> cases{
      {{"bow_normal", 60}, {"walk_old", 50}},
      {{"walk_old", 50}, {"dash_normal", 10}, {"bow_old", 80}}};
  for (const RouteMode mode : {RouteMode::Clips, RouteMode::Grid})
    for (const auto& keyed : cases) {
      InbetweenOptions options;
      options.route.mode = mode;
      InbetweenOptions raw_options = options;
      raw_options.clean_feet = false;
      std::vector<Key> keys;
      double clips = 0.0;
      std::string name;
      for (const auto& [clip, frame] : keyed) {
        keys.push_back(L.key(index(clip), frame));
        clips = std::max(clips, L.largest_step(L.clips[index(clip)].motion));
        name += (name.empty() ? "" : " to ") + clip;
      }
      name += std::string(", route ") + route_mode_name(mode);
      const InbetweenResult raw = inbetween(*L.blender, *L.map.features, keys, raw_options);
      const InbetweenResult r = inbetween(*L.blender, *L.map.features, keys, options);
      std::printf(
          "[ figures  ] %s: a joint's largest step %.1f cm raw, %.1f cleaned; the clips' %.1f\n",
          name.c_str(), L.largest_step(raw.motion), L.largest_step(r.motion), clips);
      const double most = mode == RouteMode::Grid ? 1.5 * clips : clips;
      EXPECT_LE(L.largest_step(raw.motion), most) << name;
      EXPECT_LE(L.largest_step(r.motion), most) << name;
      // Every key's pose in world space, from the motion root down: the dash moves on its
      // joint_Root (static in the other takes), which the blend folds into the motion root.
      const Skeleton& skeleton = L.blender->skeleton();
      std::vector<char> above(skeleton.joints.size(), 0);
      for (int j = skeleton.joints[L.blender->motion_root()].parent; j >= 0;
           j = skeleton.joints[j].parent)
        above[j] = 1;
      for (std::size_t i = 0; i < keys.size(); ++i) {
        WorldPose got, want;
        forward_kinematics(skeleton, r.motion.pose(r.key_frames[i]), got);
        forward_kinematics(skeleton, keys[i].pose.pose(0), want);
        for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
          if (above[j]) continue;
          EXPECT_NEAR((got.positions[j] - want.positions[j]).norm(), 0.0, 1e-6)
              << name << ": key " << i << ", joint " << j;
        }
      }
    }
}

TEST_F(SynthInbetweenBandaiLibrary, KeysOfClipsNoJumpJoinsAreBridged) {
  // A run's key to a walk's: no jump from the run reaches the walk's samples. Ended wherever lay
  // nearest the walk's key, the route held the run's key pose for every frame while the root
  // glided 1.5 m to the walk's (and the clean-up, holding the run's planted foot, let it snap
  // 1 m at the last frame). Bridged, the run plays on, then the walk up to its key.
  const Library& L = *lib;
  const int run = index("run_angry"), walk = index("walk_tired");
  const std::vector<Key> keys{L.key(run, 20), L.key(walk, 60)};
  const InbetweenResult r = inbetween(*L.blender, *L.map.features, keys);
  ASSERT_EQ(r.key_frames.size(), 2u);
  const int frames = r.key_frames[1];
  int moved = 0;  // frames whose map point is not the previous one's
  for (int k = 1; k <= frames; ++k) moved += r.points[k] != r.points[k - 1] ? 1 : 0;
  std::printf(
      "[ figures  ] run to walk: %d frames, %d of them at a new map point; a joint's "
      "largest step %.1f cm, the run's %.1f\n",
      frames + 1, moved, L.largest_step(r.motion), L.largest_step(L.clips[run].motion));
  EXPECT_GE(moved, frames - 2);
  EXPECT_LE(L.largest_step(r.motion), 1.25 * L.largest_step(L.clips[run].motion));
  for (int i = 0; i < 2; ++i) expect_key_hit(*L.blender, r.motion, r.key_frames[i], keys[i]);
}

TEST_F(SynthInbetweenBandai, AKeyFromAClipNotInTheMapIsPlacedAndReproduced) {
  const Library& L = *lib;
  const Clip held_out = io::load_clip(Library::path("walk_feminine"));
  const std::vector<Key> keys{L.key(L.clips[0], 0, 30), L.key(held_out, -1, 120),
                              L.key(L.clips[2], 2, 150)};
  const InbetweenResult r = inbetween(*L.blender, *L.set, keys, between(20));
  for (int i = 0; i < 3; ++i) expect_key_hit(*L.blender, r.motion, r.key_frames[i], keys[i]);
  // The held-out frame's blend at its placed point is not its own pose: the displacement map
  // does the rest, so the frames next to it are near it.
  const Motion blend = L.blender->pose_at(keys[1].point);
  double moved = 0.0;
  for (int j = 0; j < blend.num_joints; ++j) {
    if (j == L.blender->motion_root()) continue;
    moved = std::max(moved, rotation_angle(blend.rotation(0, j), keys[1].pose.rotation(0, j)));
  }
  EXPECT_GT(moved, 1e-3);
  const int k = r.key_frames[1];
  double step = 0.0;
  for (int j = 0; j < r.motion.num_joints; ++j)
    step = std::max(step, rotation_angle(r.motion.rotation(k + 1, j), r.motion.rotation(k, j)));
  EXPECT_LT(step, 0.3);
}

TEST_F(SynthInbetweenBandai, AHeldOutWalksKeysJoinWithoutTurningTheBodyRound) {
  // Keys 45 frames apart on a walk not in the map: between keys the root's path is turned and
  // scaled onto the next key, its heading error spread with time, so no frame turns the body
  // round (turning it by the path's turn at once swung it on the frame after a key). Each run of
  // the clip route plays at an even pace, so no ankle moves much farther between two frames than
  // the walk's own do (played step by step, a skip at the end of a run moved one 18.3 cm where
  // the walk's move at most 9.8).
  const Library& L = *lib;
  const Clip held_out = io::load_clip(Library::path("walk_feminine"));
  std::vector<Key> keys;
  for (int f = 20; f <= 158; f += 46) keys.push_back(L.key(held_out, -1, f));
  const InbetweenResult r = inbetween(*L.blender, *L.set, keys, between(45));
  const int root = L.blender->motion_root();
  const Axis up = L.blender->options().up;
  const Feet feet = find_feet(L.blender->skeleton());
  const auto ankles = [&](const Motion& m, int side) {
    return joint_trajectory(L.blender->skeleton(), m, feet.legs[side].ankle);
  };
  double turn = 0.0, own_turn = 0.0, step = 0.0, own_step = 0.0;
  // Transitions in which an ankle stands (moves less than 0.5 cm on the floor: 15 cm/s).
  const Eigen::Vector3d up_unit = Eigen::Vector3d::Unit(static_cast<int>(L.blender->options().up));
  const auto standing = [&](const std::vector<Eigen::Vector3d>& p) {
    int n = 0;
    for (std::size_t f = 1; f < p.size(); ++f) {
      const Eigen::Vector3d d = p[f] - p[f - 1];
      n += (d - d.dot(up_unit) * up_unit).norm() < 0.5;
    }
    return static_cast<double>(n) / static_cast<double>(p.size() - 1);
  };
  double stands = 0.0, own_stands = 0.0;
  for (int side = 0; side < 2; ++side) {
    const auto a = ankles(r.motion, side), b = ankles(held_out.motion, side);
    for (std::size_t f = 1; f < a.size(); ++f) step = std::max(step, (a[f] - a[f - 1]).norm());
    for (std::size_t f = 1; f < b.size(); ++f)
      own_step = std::max(own_step, (b[f] - b[f - 1]).norm());
    stands += standing(a) / 2.0;
    own_stands += standing(b) / 2.0;
  }
  const auto heading = [&](const Motion& m, int f) {
    return root_placement(m, f, root, up).heading;
  };
  for (int f = 1; f < r.motion.num_frames; ++f)
    turn = std::max(turn, std::abs(wrap_angle(heading(r.motion, f) - heading(r.motion, f - 1))));
  for (int f = 1; f < held_out.motion.num_frames; ++f) {
    own_turn = std::max(own_turn, std::abs(wrap_angle(heading(held_out.motion, f) -
                                                      heading(held_out.motion, f - 1))));
  }
  // No foot stays up much longer than the walk's: the keys' displacement map tilts a stance,
  // lifting it a few cm at one end, so the clean-up holds the blend's heights from before it.
  const Skating skating = measure_skating(L.blender->skeleton(), r.motion, feet, up);
  const Skating own_skating = measure_skating(held_out.skeleton, held_out.motion, feet, up);
  std::printf(
      "[ figures  ] held-out walk's in-between: largest turn %.3f rad (the walk's %.3f), "
      "ankle step %.1f cm (the walk's %.1f), ankles standing %.2f of transitions (the walk's "
      "%.2f), a foot up %.3f s at most (the walk's %.3f)\n",
      turn, own_turn, step, own_step, stands, own_stands, skating.longest_raised_s,
      own_skating.longest_raised_s);
  EXPECT_LE(turn, 2.0 * own_turn);
  EXPECT_LE(step, 1.25 * own_step);
  EXPECT_LE(skating.longest_raised_s, own_skating.longest_raised_s + 0.1);
}

TEST_F(SynthInbetweenBandai, AHeldOutWalksInbetweensStayCloserToItThanInterpolation) {
  // Keys 31 frames apart on a walk not in the map, every 20 frames: the in-betweens take the
  // walk's steps, so their joints stay nearer the capture's than interpolating the keys does.
  // A 2-D map lays a walk's phases close and places the keys among them: with its ends among the
  // 16 samples nearest a key's point only, the route of the window from 230 takes a step the walk
  // does not (mean joint error 9.3 cm, interpolation's 9.5); ending on a sample further out whose
  // pose matches the key better than every near one's, 4.8 cm.
  const Library& L = *lib;
  const Clip held_out = io::load_clip(Library::path("walk_feminine"));
  const Skeleton& s = L.blender->skeleton();
  const int n = 30;
  const auto mean_error = [&](const Motion& m, int first, int a) {
    double sum = 0.0;
    for (int f = 1; f <= n; ++f) {
      const WorldPose got = forward_kinematics(s, m, first + f);
      const WorldPose want = forward_kinematics(s, held_out.motion, a + f);
      for (int j = 0; j < s.num_joints(); ++j) sum += (got.positions[j] - want.positions[j]).norm();
    }
    return sum / (n * s.num_joints());
  };
  double worst = 0.0;
  for (int a = 10; a + n + 1 < held_out.motion.num_frames; a += 20) {
    const int b = a + n + 1;
    const std::vector<Key> keys{L.key(held_out, -1, a), L.key(held_out, -1, b)};
    const InbetweenResult r = inbetween(*L.blender, *L.set, keys, between(n));
    // Interpolation: the keys' local rotations slerped, their translations lerped.
    Motion lerp = held_out.motion;
    for (int f = a + 1; f < b; ++f) {
      const double t = static_cast<double>(f - a) / (b - a);
      for (int j = 0; j < lerp.num_joints; ++j) {
        lerp.rotation(f, j) =
            held_out.motion.rotation(a, j).slerp(t, held_out.motion.rotation(b, j));
        lerp.translation(f, j) =
            (1 - t) * held_out.motion.translation(a, j) + t * held_out.motion.translation(b, j);
      }
    }
    const double ours = mean_error(r.motion, 0, a), theirs = mean_error(lerp, a, a);
    std::printf(
        "[ figures  ] held-out walk, keys at %d and %d: mean joint error %.1f cm "
        "(interpolation %.1f)\n",
        a, b, ours, theirs);
    worst = std::max(worst, ours / theirs);
  }
  EXPECT_LT(worst, 0.8);
}

TEST_F(SynthInbetweenBandai, AKeyOnItsOwnTrajectoryReproducesTheClip) {
  // Consecutive samples of a clip as keys, no frame between: the clip's frames, where they stood.
  const Library& L = *lib;
  std::vector<Key> keys;
  for (int f = 40; f <= 60; f += 2) keys.push_back(L.key(L.clips[1], 1, f));
  const InbetweenResult r = inbetween(*L.blender, *L.set, keys, between(0));
  ASSERT_EQ(r.motion.num_frames, static_cast<int>(keys.size()));
  for (std::size_t i = 0; i < keys.size(); ++i)
    expect_key_hit(*L.blender, r.motion, static_cast<int>(i), keys[i]);
}

}  // namespace
}  // namespace motionmap::synth
