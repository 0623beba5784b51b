// Saved maps opened for use (mapfile::SavedMap; its mapfile::PointIndex, synth::PointIndex): the
// 2-D index against a
// brute-force search on real maps, clips loaded on demand and checked against the SHA-256 the
// map file recorded (a changed, missing or wrong clip is an error naming the file and what was
// expected), poses blended on a saved map equal to the idw blend of the same clips mapped
// directly, and a blender reading a saved map's clips on demand (make_blender) equal to one given
// every clip, bit for bit, while reading only the clips of the samples it blends.
#include "motionmap/mapfile/saved_map.h"

#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::mapfile {
namespace {

namespace fs = std::filesystem;

const std::string kData = MOTIONMAP_SHARED_DATA;

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_path = fs::temp_directory_path() /
             ("motionmap-savedmap-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(m_path);
    fs::create_directories(m_path);
  }
  ~TempDir() { fs::remove_all(m_path); }
  std::string file(const std::string& name) const { return (m_path / name).string(); }

 private:
  fs::path m_path;
};

// Copies the real clips into `dir` (the test's temporary folder), maps them and saves the map
// there: the map file refers to the copies, which a test may then change or remove.
struct SavedLibrary {
  std::vector<Clip> clips;
  pipeline::ClipMap map;
  std::string file;
};

SavedLibrary save_library(const TempDir& dir, const std::vector<std::string>& names,
                          embed::Method method) {
  SavedLibrary lib;
  for (const auto& name : names) {
    const std::string copy = dir.file(fs::path(name).filename().string());
    fs::copy_file(kData + "/" + name, copy, fs::copy_options::overwrite_existing);
    lib.clips.push_back(io::load_clip(copy));
  }
  pipeline::ClipMapOptions options;
  options.embed.method = method;
  lib.map = pipeline::map_clips(lib.clips, options);
  lib.file = dir.file("lib.mmap.h5");
  write_map_file(lib.file, make_map_file(lib.clips, lib.map, options));
  return lib;
}

bool have_data() {
  return fs::exists(kData + "/cmu/64_08.bvh") && fs::exists(kData + "/cmu/64_09.bvh");
}

TEST(PointIndex, MatchesBruteForceOnARealMap) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh"}, embed::Method::Mds);
  const Eigen::MatrixXd& xy = lib.map.embedding.coordinates;
  const PointIndex index(xy);
  ASSERT_EQ(index.size(), xy.rows());
  ASSERT_EQ(index.indexed(), xy.rows());
  const Eigen::Vector2d lo = xy.leftCols(2).colwise().minCoeff(),
                        hi = xy.leftCols(2).colwise().maxCoeff();
  EXPECT_EQ(index.lower(), lo);
  EXPECT_EQ(index.upper(), hi);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(lo.x() - 1.0, hi.x() + 1.0),
      uy(lo.y() - 1.0, hi.y() + 1.0);
  for (int q = 0; q < 300; ++q) {
    // Random points, and points exactly on samples.
    const Eigen::Vector2d p = q % 3 == 0
                                  ? Eigen::Vector2d(xy(q % xy.rows(), 0), xy(q % xy.rows(), 1))
                                  : Eigen::Vector2d(ux(rng), uy(rng));
    std::vector<std::pair<double, int>> brute;
    for (Eigen::Index i = 0; i < xy.rows(); ++i)
      brute.emplace_back((Eigen::Vector2d(xy(i, 0), xy(i, 1)) - p).norm(), int(i));
    std::sort(brute.begin(), brute.end());
    const Neighbor one = index.nearest(p);
    EXPECT_DOUBLE_EQ(one.distance, brute.front().first);
    EXPECT_DOUBLE_EQ(brute[std::size_t(one.sample)].first >= 0
                         ? (Eigen::Vector2d(xy(one.sample, 0), xy(one.sample, 1)) - p).norm()
                         : -1.0,
                     brute.front().first);
    const std::vector<Neighbor> k = index.nearest(p, 13);
    ASSERT_EQ(k.size(), 13u);
    for (std::size_t i = 0; i < k.size(); ++i) {
      EXPECT_DOUBLE_EQ(k[i].distance, brute[i].first) << "query " << q << " rank " << i;
      // The sample is at that distance (ties may name another of the tied samples).
      EXPECT_DOUBLE_EQ((Eigen::Vector2d(xy(k[i].sample, 0), xy(k[i].sample, 1)) - p).norm(),
                       k[i].distance);
      if (i > 0) {
        EXPECT_LE(k[i - 1].distance, k[i].distance);
      }
    }
  }
  // Non-finite rows are never found; a non-finite query finds nothing.
  Eigen::MatrixXd holes = xy;
  holes(5, 0) = std::numeric_limits<double>::quiet_NaN();
  const PointIndex partial(holes);
  EXPECT_EQ(partial.indexed(), xy.rows() - 1);
  EXPECT_NE(partial.nearest(Eigen::Vector2d(xy(5, 0), xy(5, 1))).sample, 5);
  EXPECT_EQ(partial.nearest(Eigen::Vector2d(std::nan(""), 0.0)).sample, -1);
  EXPECT_TRUE(partial.nearest(Eigen::Vector2d(0.0, 0.0), 0).empty());
  EXPECT_THROW(PointIndex(Eigen::MatrixXd(3, 1)), ParameterError);
}

TEST(SavedMap, LoadsClipsOnDemandAndCachesThem) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh"}, embed::Method::Pca);
  const SavedMap map(read_map_file(lib.file), 1);
  EXPECT_EQ(map.num_clips(), 2);
  EXPECT_EQ(map.loads(), 0);  // opening reads no clip
  EXPECT_FALSE(map.is_loaded(1));
  const auto second = map.clip(1);
  EXPECT_TRUE(map.is_loaded(1));
  EXPECT_EQ(second->motion.num_frames, lib.clips[1].motion.num_frames);
  EXPECT_EQ(second->motion.rotations, lib.clips[1].motion.rotations);
  map.clip(1);
  EXPECT_EQ(map.loads(), 1);  // cached
  map.clip(0);                // the cache holds one: clip 1 goes
  EXPECT_FALSE(map.is_loaded(1));
  EXPECT_EQ(map.loads(), 2);
  EXPECT_THROW(map.clip(2), ParameterError);
  EXPECT_THROW(map.clip(-1), ParameterError);
  // The samples as the blender wants them.
  const features::FeatureSet set = map.samples();
  EXPECT_EQ(set.clip_of, lib.map.features->clip_of);
  EXPECT_EQ(set.frame_of, lib.map.features->frame_of);
}

TEST(SavedMap, ReadsTheMapWithoutItsModelForShowingAndBlending) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh"}, embed::Method::Lle);
  const MapFile full = read_map_file(lib.file);
  const MapFile shown = read_map_file(lib.file, {.model = false});
  EXPECT_EQ(full.model.features.rows(), full.num_samples());  // LLE keeps every X row
  EXPECT_EQ(shown.model.features.size(), 0);
  EXPECT_EQ(shown.model.coordinates.size(), 0);
  EXPECT_EQ(shown.coordinates, full.coordinates);
  EXPECT_EQ(shown.clip_of, full.clip_of);
  EXPECT_EQ(shown.frame_of, full.frame_of);
  EXPECT_EQ(shown.parameters, full.parameters);
  EXPECT_EQ(shown.clips.size(), full.clips.size());
  EXPECT_EQ(shown.clips[1].sha256, full.clips[1].sha256);
  EXPECT_EQ(shown.skeleton.names, full.skeleton.names);
}

TEST(SavedMap, FindsClipsBesideTheMapFileWhenPathsAreRelative) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib = save_library(dir, {"cmu/64_08.bvh"}, embed::Method::Pca);
  MapFile file = read_map_file(lib.file);
  file.clips[0].path = "64_08.bvh";  // as `motionmap map 64_08.bvh` run in that folder records it
  const SavedMap map(std::move(file));
  EXPECT_EQ(map.resolve_path(0), dir.file("64_08.bvh"));
  EXPECT_EQ(map.clip(0)->motion.num_frames, lib.clips[0].motion.num_frames);
}

std::string message_of(const SavedMap& map, int c) {
  try {
    map.clip(c);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SavedMap, AChangedOrMissingClipIsAClearError) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh"}, embed::Method::Pca);
  const MapFile file = read_map_file(lib.file);
  const std::string expected_hash = file.clips[0].sha256;
  {
    // One byte more: another SHA-256.
    std::ofstream(dir.file("64_08.bvh"), std::ios::app) << "\n";
    const SavedMap map(file);
    const std::string m = message_of(map, 0);
    EXPECT_NE(m.find(lib.file), std::string::npos) << m;
    EXPECT_NE(m.find(dir.file("64_08.bvh")), std::string::npos) << m;
    EXPECT_NE(m.find("has changed since the map was made"), std::string::npos) << m;
    EXPECT_NE(m.find(expected_hash), std::string::npos) << m;
    EXPECT_FALSE(map.is_loaded(0));
    EXPECT_EQ(map.clip(1)->motion.num_frames, lib.clips[1].motion.num_frames);  // others still load
    // A pose needing that clip fails with the same message, never a pose of other data.
    const int s = file.clips[0].first_sample;
    try {
      map.pose_at(Eigen::Vector2d(file.coordinates(s, 0), file.coordinates(s, 1)), 4);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("has changed since the map was made"),
                std::string::npos);
    }
  }
  {
    // Changed into a file that no longer parses: still reported as changed (the hash and the
    // parse run side by side).
    std::ofstream(dir.file("64_08.bvh"), std::ios::trunc) << "HIERARCHY\nROOT Hips {\n";
    const SavedMap map(file);
    const std::string m = message_of(map, 0);
    EXPECT_NE(m.find("has changed since the map was made"), std::string::npos) << m;
  }
  {
    fs::remove(dir.file("64_08.bvh"));
    const SavedMap map(file);
    const std::string m = message_of(map, 0);
    EXPECT_NE(m.find("is missing"), std::string::npos) << m;
    EXPECT_NE(m.find(expected_hash), std::string::npos) << m;
  }
  {
    // The same bytes recorded with another frame count: the record, not the file, is wrong.
    MapFile wrong = file;
    wrong.clips[1].frames += 1;
    const SavedMap map(std::move(wrong));
    const std::string m = message_of(map, 1);
    EXPECT_NE(m.find("frames, the map expects"), std::string::npos) << m;
  }
}

TEST(SavedMap, PoseEqualsTheIdwBlendOfTheClipsMappedDirectly) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh"}, embed::Method::Mds);
  const SavedMap map(read_map_file(lib.file), 2);
  synth::BlendOptions idw;
  idw.mode = synth::BlendMode::Idw;
  idw.neighbors = 12;
  idw.reach = 1e9;  // never clamped: SavedMap::pose_at blends where the point is
  const synth::MapBlender direct(lib.clips, *lib.map.features, lib.map.embedding.coordinates, idw);
  // The default (local) blender of the same map: what "outside the data" means.
  const synth::MapBlender reference(lib.clips, *lib.map.features, lib.map.embedding.coordinates);
  const Eigen::MatrixXd& xy = lib.map.embedding.coordinates;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, int(xy.rows()) - 2);
  for (int q = 0; q < 25; ++q) {
    const int i = pick(rng);
    // Between two consecutive samples, and exactly on one.
    const Eigen::Vector2d p = q % 5 == 0 ? Eigen::Vector2d(xy(i, 0), xy(i, 1))
                                         : Eigen::Vector2d(0.5 * (xy(i, 0) + xy(i + 1, 0)) + 1e-3,
                                                           0.5 * (xy(i, 1) + xy(i + 1, 1)));
    const SavedPose saved = map.pose_at(p, 12);
    const Motion expected = direct.pose_at(p);
    ASSERT_EQ(saved.pose.num_joints, expected.num_joints);
    ASSERT_EQ(saved.around.size(), 12u);
    double total = 0.0;
    for (double w : saved.weights) total += w;
    EXPECT_NEAR(total, 1.0, 1e-12);
    for (int j = 0; j < expected.num_joints; ++j) {
      EXPECT_LT(saved.pose.rotation(0, j).angularDistance(expected.rotation(0, j)), 1e-9)
          << "query " << q << " joint " << j;
      EXPECT_LT((saved.pose.translation(0, j) - expected.translation(0, j)).norm(), 1e-9);
    }
    EXPECT_EQ(saved.outside, reference.locate(p).validity.clamped) << "query " << q;
  }
  // Far outside the data: said so.
  EXPECT_TRUE(map.pose_at(xy.leftCols(2).colwise().maxCoeff().transpose() * 10.0 +
                          Eigen::Vector2d(100.0, 100.0))
                  .outside);
  EXPECT_THROW(map.pose_at(Eigen::Vector2d(std::nan(""), 0.0)), ParameterError);
  EXPECT_THROW(map.pose_at(Eigen::Vector2d(0.0, 0.0), 0), ParameterError);
  // The blender's reach and the saved map's agree.
  EXPECT_DOUBLE_EQ(map.median_step(), reference.median_step());
}

// Bit for bit: the same doubles (== on every coefficient, so -0 and +0 would differ only in sign).
void expect_same_motion(const Motion& a, const Motion& b, const std::string& what) {
  ASSERT_EQ(a.num_frames, b.num_frames) << what;
  ASSERT_EQ(a.num_joints, b.num_joints) << what;
  ASSERT_EQ(a.rotations.size(), b.rotations.size()) << what;
  EXPECT_EQ(a.frame_time, b.frame_time) << what;
  EXPECT_EQ(std::memcmp(a.rotations.data(), b.rotations.data(),
                        a.rotations.size() * sizeof(Eigen::Quaterniond)),
            0)
      << what;
  EXPECT_EQ(std::memcmp(a.translations.data(), b.translations.data(),
                        a.translations.size() * sizeof(Eigen::Vector3d)),
            0)
      << what;
}

// A saved map's pose (SavedMap::pose_at, which blends its K nearest samples' states straight from
// their clips) is the blend of the whole map's blender (make_blender with idw, K neighbours) at
// the same weights, bit for bit: the map's motion root and moving joints, its first sample's
// translations for the others. On samples, between consecutive samples, between two clips and
// outside the data; on a map of one skeleton (a Bandai walk and run) and on one of two subjects
// whose bone lengths differ (joints whose translations are averaged).
TEST(SavedMap, PoseIsTheSavedMapBlendersPoseBitForBit) {
  struct Case {
    std::vector<std::string> clips;
    bool moving;  // the map averages some joints' translations
    // Every clip has the map's motion root. Not so for Bandai's: joint_Root above the hips moves
    // in the run only, so a blend of walk samples without the map's record takes the hips, as a
    // blender of the walk alone would.
    bool same_roots;
  };
  const Case cases[] = {
      {{"bandai/dataset-1_walk_old_001.bvh", "bandai/dataset-1_run_normal_001.bvh"}, false, false},
      {{"cmu/64_08.bvh", "cmu/02_03.bvh"}, true, true}};
  for (const Case& c : cases) {
    if (!fs::exists(kData + "/" + c.clips[0]) || !fs::exists(kData + "/" + c.clips[1]))
      GTEST_SKIP() << "no shared data in " << kData;
    TempDir dir;
    const SavedLibrary lib = save_library(dir, c.clips, embed::Method::Pca);
    const MapFile file = read_map_file(lib.file, {.model = false});
    ASSERT_TRUE(file.blend.has_value());
    if (c.moving) {
      EXPECT_FALSE(file.blend->moving.empty()) << c.clips[1];
    }
    const Axis up = file.options.features.up;
    const Eigen::MatrixXd& xy = file.coordinates;
    const int second = file.clips[1].first_sample;
    const int n = file.num_samples();
    // Rows by the clips' sample counts (the second clip can be short).
    const int first_count = second, second_count = n - second;
    ASSERT_GE(first_count, 4);
    ASSERT_GE(second_count, 4);
    const auto at = [&](int i) {
      EXPECT_TRUE(i >= 0 && i < n) << i;
      i = std::clamp(i, 0, n - 1);
      return Eigen::Vector2d(xy(i, 0), xy(i, 1));
    };
    const int a = first_count / 3, b = second + second_count / 3;
    const std::vector<Eigen::Vector2d> points = {
        at(first_count / 5),                                          // on a sample
        at(second + second_count / 2),                                // on one of the second clip
        at(n - 1),                                                    // the last sample
        0.5 * (at(a) + at(a + 1)),                                    // between consecutive samples
        0.3 * at(b) + 0.7 * at(b + 1),                                // again, nearer the second
        0.5 * (at(first_count / 2) + at(second + second_count / 2)),  // between the two clips
        at(n / 2) + Eigen::Vector2d(1e-3, -2e-3),                     // just off a sample
        xy.leftCols(2).colwise().maxCoeff().transpose() * 3.0 + Eigen::Vector2d(50.0, 50.0)};
    // The map file without the blend record (an older one): pose_at then blends with the motion
    // root and moving joints of the samples' own clips; where those clips have the map's motion
    // root, the same pose up to rounding (the joints averaged only here hold the same
    // translations in these samples) and the same rotations exactly.
    MapFile old = file;
    old.blend.reset();
    const SavedMap without(std::move(old));
    for (const int K : {1, 4, 12}) {
      auto map = std::make_shared<const SavedMap>(file);
      synth::BlendOptions idw;
      idw.mode = synth::BlendMode::Idw;
      idw.neighbors = K;
      idw.up = up;
      const synth::MapBlender blender = make_blender(map, idw);
      for (std::size_t q = 0; q < points.size(); ++q) {
        const std::string what =
            c.clips[1] + ", K = " + std::to_string(K) + ", point " + std::to_string(q);
        const SavedPose pose = map->pose_at(points[q], K, up);
        ASSERT_EQ(pose.around.size(), std::size_t(K)) << what;
        synth::MapWeights w;
        for (std::size_t i = 0; i < pose.around.size(); ++i) {
          w.samples.push_back(pose.around[i].sample);
          w.weights.push_back(pose.weights[i]);
        }
        expect_same_motion(pose.pose, blender.pose(w), what);
        EXPECT_EQ(pose.root, blender.motion_root()) << what;
        const SavedPose other = without.pose_at(points[q], K, up);
        EXPECT_EQ(other.weights, pose.weights) << what;
        ASSERT_EQ(other.pose.num_joints, pose.pose.num_joints) << what;
        if (!c.same_roots) continue;
        EXPECT_EQ(other.root, pose.root) << what;
        EXPECT_EQ(other.pose.rotations, pose.pose.rotations) << what;
        for (int j = 0; j < pose.pose.num_joints; ++j) {
          EXPECT_LE((other.pose.translation(0, j) - pose.pose.translation(0, j)).norm(),
                    1e-9 * (1.0 + pose.pose.translation(0, j).norm()))
              << what << ", joint " << j;
        }
      }
    }
  }
}

// A path whose frames are routed through the clips' own frames (detail/outside_route.h) takes
// the same route on a saved map as on its clips mapped directly: its jumps are priced by their
// poses on both. Unpriced on the saved map, the feminine walk sketched with a point every third
// of a second through the 11 Bandai takes' isomap took another route into its stalled steps and
// skated 0.141 of its transitions cleaned against 0.275 from the clips (bench/traced_walks.py).
// (Its strokes now follow the walk's curve, detail/strokes.h; drawn at 0.35 of the walk's timing,
// slower than a clip is followed, they keep their chords and stall as that sketch did.)
TEST(SavedMapBlender, RoutesAPathAsTheClipsMappedDirectlyDo) {
  std::vector<std::string> names;
  for (const char* take :
       {"bow_normal", "bow_old", "dash_normal", "punch_normal", "run_angry", "run_normal",
        "run_old", "walk_angry", "walk_feminine", "walk_old", "walk_tired"})
    names.push_back(std::string("bandai/dataset-1_") + take + "_001.bvh");
  for (const std::string& name : names) {
    if (!fs::exists(kData + "/" + name)) GTEST_SKIP() << "no " << name << " in " << kData;
  }
  TempDir dir;
  const SavedLibrary lib = save_library(dir, names, embed::Method::Isomap);
  const Eigen::MatrixXd& xy = lib.map.embedding.coordinates;
  const features::FeatureSet& set = *lib.map.features;
  // The feminine walk's own map points, one every 10 frames (a third of a second), at 0.35 of
  // its timing.
  constexpr int kFeminine = 8;
  const double dt = lib.clips[kFeminine].motion.frame_time;
  synth::MapPath path;
  for (int i = 0; i < set.num_samples(); ++i) {
    if (set.clip_of[i] != kFeminine || set.frame_of[i] % 10 != 0) continue;
    path.points.push_back(xy.row(i).head<2>().transpose());
    path.times.push_back(set.frame_of[i] * dt / 0.35);
  }
  const synth::MapBlender full(lib.clips, set, xy);
  auto saved = std::make_shared<const SavedMap>(read_map_file(lib.file, {.model = false}));
  const synth::MapBlender lazy = make_blender(saved, {});
  ASSERT_TRUE(lazy.reads_on_demand());
  const synth::SynthResult a = synth::synthesize(full, path, {});
  const synth::SynthResult b = synth::synthesize(lazy, path, {});
  // Some of its frames are routed (stalled steps, and the frames about them).
  EXPECT_GT(std::count(a.stalled.begin(), a.stalled.end(), 1), 0);
  EXPECT_EQ(a.stalled, b.stalled);
  expect_same_motion(a.motion, b.motion, "the feminine walk sketched");
}

// A blend record that does not fit the map's clips (a root or a moving joint the first clip does
// not have, moving joints out of order) is refused by the saved map's pose and by the map's
// blender alike, naming the map, the joint and the clip; never a pose of other joints.
TEST(SavedMap, ABlendRecordThatDoesNotFitTheClipsIsRefused) {
  if (!have_data()) GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh"}, embed::Method::Pca);
  const MapFile file = read_map_file(lib.file, {.model = false});
  ASSERT_TRUE(file.blend.has_value());
  const int joints = lib.clips[0].skeleton.num_joints();
  const Eigen::Vector2d p(file.coordinates(5, 0), file.coordinates(5, 1));
  synth::BlendOptions idw;
  idw.mode = synth::BlendMode::Idw;
  const auto pose_message = [&](const MapFile& f) {
    try {
      SavedMap(f).pose_at(p, 4);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto blender_message = [&](const MapFile& f) {
    try {
      make_blender(std::make_shared<const SavedMap>(f), idw);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  {
    MapFile bad = file;
    bad.blend->motion_root = joints;
    const std::string m = pose_message(bad);
    EXPECT_NE(m.find(lib.file + ": the blend record names joint " + std::to_string(joints) +
                     " as the motion root, but "),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("64_08.bvh has " + std::to_string(joints) + " joints"), std::string::npos)
        << m;
    const std::string b = blender_message(bad);
    EXPECT_NE(b.find("map: the clips' summary names joint " + std::to_string(joints) +
                     " as the motion root"),
              std::string::npos)
        << b;
  }
  {
    MapFile bad = file;
    bad.blend->moving = {joints + 2};
    const std::string m = pose_message(bad);
    EXPECT_NE(m.find(": the blend record lists joint " + std::to_string(joints + 2) +
                     " as moving; expected increasing joints of "),
              std::string::npos)
        << m;
    EXPECT_NE(blender_message(bad).find("the clips' summary lists joint " +
                                        std::to_string(joints + 2) + " as moving"),
              std::string::npos);
  }
  {
    MapFile bad = file;
    bad.blend->moving = {3, 3};
    EXPECT_NE(pose_message(bad).find("lists joint 3 as moving"), std::string::npos);
    EXPECT_NE(blender_message(bad).find("lists joint 3 as moving"), std::string::npos);
  }
}

TEST(SavedMapBlender, EqualsTheBlenderOfEveryClipAndReadsOnlyTheClipsItBlends) {
  if (!have_data() || !fs::exists(kData + "/cmu/02_03.bvh"))
    GTEST_SKIP() << "no shared data in " << kData;
  TempDir dir;
  // Two subjects: their offsets differ, so some joints' translations are blended.
  const SavedLibrary lib =
      save_library(dir, {"cmu/64_08.bvh", "cmu/64_09.bvh", "cmu/02_03.bvh"}, embed::Method::Mds);
  const Eigen::MatrixXd& xy = lib.map.embedding.coordinates;
  const features::FeatureSet& set = *lib.map.features;
  const MapFile file = read_map_file(lib.file, {.model = false});
  ASSERT_TRUE(file.blend.has_value());
  const synth::ClipsSummary full_summary = synth::summarize_clips(lib.clips, set);
  EXPECT_EQ(file.blend->motion_root, full_summary.motion_root);
  EXPECT_EQ(file.blend->moving, full_summary.moving);
  EXPECT_FALSE(full_summary.moving.empty());  // 02 and 64 have other bone lengths

  // Points on samples of the last clip, between samples, and far outside (clamped).
  const int n = static_cast<int>(xy.rows());
  const int last = file.clips.back().first_sample;
  const std::vector<Eigen::Vector2d> points = {
      xy.row(last + 40).head<2>().transpose(),
      0.5 * (xy.row(last + 100).head<2>() + xy.row(last + 101).head<2>()).transpose(),
      xy.row(n / 3).head<2>().transpose() + Eigen::Vector2d(1e-3, -2e-3),
      xy.row(5).head<2>().transpose() + Eigen::Vector2d(1e4, 0.0)};
  synth::MapPath path;
  for (int i = 60; i < 200; i += 10) path.points.push_back(xy.row(i).head<2>().transpose());

  for (const synth::BlendMode mode : {synth::BlendMode::Local, synth::BlendMode::Idw}) {
    const std::string name(synth::blend_mode_name(mode));
    synth::BlendOptions options;
    options.mode = mode;
    const synth::MapBlender full(lib.clips, set, xy, options);
    auto saved = std::make_shared<const SavedMap>(file, static_cast<int>(file.clips.size()));
    const synth::MapBlender lazy = make_blender(saved, options);
    // Set-up reads the first clip only (its skeleton) and builds no local system.
    EXPECT_EQ(saved->loads(), 1) << name;
    EXPECT_EQ(lazy.num_local_systems(), 0) << name;
    EXPECT_EQ(lazy.motion_root(), full.motion_root()) << name;
    EXPECT_EQ(lazy.median_speed(), full.median_speed()) << name;
    EXPECT_EQ(lazy.num_points(), full.num_points()) << name;

    std::set<int> read = {0};
    for (std::size_t q = 0; q < points.size(); ++q) {
      const std::string what = name + " point " + std::to_string(q);
      const synth::MapWeights a = full.locate(points[q]), b = lazy.locate(points[q]);
      EXPECT_EQ(a.samples, b.samples) << what;
      EXPECT_EQ(a.weights, b.weights) << what;
      EXPECT_EQ(a.validity.point, b.validity.point) << what;
      EXPECT_EQ(a.validity.clamped, b.validity.clamped) << what;
      expect_same_motion(full.pose(a), lazy.pose(b), what);
      // Only the clips of the samples blended were read, each once.
      for (int s : b.samples) read.insert(set.clip_of[s]);
      EXPECT_EQ(saved->loads(), static_cast<int>(read.size())) << what;
    }
    if (mode == synth::BlendMode::Local) {
      EXPECT_GT(lazy.num_local_systems(), 0);
      EXPECT_LT(lazy.num_local_systems(), full.num_local_systems());
    }

    // A synthesis along a path, with and without smoothing of the weights.
    for (const double smooth : {0.0, 0.05}) {
      synth::SynthOptions so;
      so.smooth = smooth;
      const synth::SynthResult a = synth::synthesize(full, path, so);
      const synth::SynthResult b = synth::synthesize(lazy, path, so);
      expect_same_motion(a.motion, b.motion, name + " synth, smooth " + std::to_string(smooth));
      EXPECT_EQ(a.clamped_frames, b.clamped_frames);
    }
  }

  // A path `share` of the way from the first swing's curve to the second's, over 6 s.
  const int second = file.clips[1].first_sample;
  const auto toward_second = [&](double share) {
    synth::MapPath path;
    for (int i = 60; i <= 340; i += 10) {
      path.points.push_back(
          ((1.0 - share) * xy.row(i) + share * xy.row(second + i)).head<2>().transpose());
      path.times.push_back(6.0 * (i - 60) / 280.0);
    }
    return path;
  };

  // With one clip kept, a smoothed synthesis of 720 frames (three blocks of 256 blended) reads
  // each clip once for the gait phases and once for the samples it blends (those the smoothing
  // moves onto included, read together before the frames are blended), not once per block, nor
  // clip after clip frame by frame.
  {
    auto one = std::make_shared<const SavedMap>(file, 1);
    const synth::MapBlender lazy = make_blender(one, {});
    const int before = one->loads();
    synth::SynthOptions so;
    so.smooth = 0.05;
    // Halfway between the two swings' curves: each frame blends both.
    const synth::SynthResult r = synth::synthesize(lazy, toward_second(0.5), so);
    ASSERT_EQ(r.motion.num_frames, 721);
    EXPECT_LE(one->loads() - before, 2 * static_cast<int>(file.clips.size()))
        << one->loads() - before << " clips read";
  }

  // A blender that keeps fewer states than a synthesis reads: the samples a prefetch finds kept
  // stay kept while states are dropped for the others, so its frames' blends read no clip again
  // (once, every one dropped, each frame read its clips again, clip by clip).
  {
    auto one = std::make_shared<const SavedMap>(file, 1);
    synth::BlendOptions few;
    few.kept_states = 100;
    const synth::MapBlender lazy = make_blender(one, few);
    synth::SynthOptions so;
    so.smooth = 0.05;
    synth::SynthResult first;
    // Halfway between the two swings' curves, then a quarter of the way: the second path blends
    // some samples the first kept and some it did not.
    for (const double share : {0.5, 0.25}) {
      const int before = one->loads();
      const synth::SynthResult r = synth::synthesize(lazy, toward_second(share), so);
      EXPECT_LE(one->loads() - before, 2 * static_cast<int>(file.clips.size()))
          << one->loads() - before << " clips read, " << share << " of the way";
      if (share == 0.5) first = r;
    }
    // Keeping few states changes what is read, not what is blended.
    expect_same_motion(first.motion,
                       synth::synthesize(make_blender(one, {}), toward_second(0.5), so).motion,
                       "kept_states 100");
  }

  // A map file without the blend record (an older one): every clip is read once for it, and the
  // blender is the same.
  MapFile old = file;
  old.blend.reset();
  const std::string old_path = dir.file("old.mmap.h5");
  write_map_file(old_path, old);
  auto saved_old = std::make_shared<const SavedMap>(read_map_file(old_path, {.model = false}), 1);
  ASSERT_FALSE(saved_old->file().blend.has_value());
  const synth::ClipsSummary scanned = saved_old->clips_summary();
  EXPECT_EQ(saved_old->loads(), 3);
  EXPECT_EQ(scanned.motion_root, full_summary.motion_root);
  EXPECT_EQ(scanned.moving, full_summary.moving);
  EXPECT_EQ(scanned.frames, full_summary.frames);
  EXPECT_EQ(scanned.frame_times, full_summary.frame_times);
  const synth::MapBlender full(lib.clips, set, xy, {});
  const synth::MapBlender lazy = make_blender(saved_old, {});
  expect_same_motion(full.pose_at(points[1]), lazy.pose_at(points[1]), "older map file");

  // A clip no blend touches is never read: with 02_03.bvh (clip 2, a walk among golf swings)
  // removed, a pose on a golf sample blended from golf samples only is still made.
  int golf = -1;
  for (int i = 0; i < file.clips[2].first_sample && golf < 0; i += 7) {
    const synth::MapWeights w = full.locate(xy.row(i).head<2>().transpose());
    if (std::none_of(w.samples.begin(), w.samples.end(),
                     [&](int s) { return set.clip_of[s] == 2; }))
      golf = i;
  }
  ASSERT_GE(golf, 0);
  fs::remove(dir.file("02_03.bvh"));
  auto without = std::make_shared<const SavedMap>(file, 3);
  const synth::MapBlender partial = make_blender(without, {});
  const Eigen::Vector2d at = xy.row(golf).head<2>().transpose();
  expect_same_motion(full.pose_at(at), partial.pose_at(at), "with a clip removed");
  EXPECT_FALSE(without->is_loaded(2));
  // One that needs it says which file is missing.
  try {
    (void)partial.pose_at(xy.row(file.clips[2].first_sample + 30).head<2>().transpose());
    ADD_FAILURE() << "no error for a missing clip";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("02_03.bvh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is missing"), std::string::npos) << e.what();
  }

  // Kriging blends every sample: refused on demand.
  synth::BlendOptions kriging;
  kriging.mode = synth::BlendMode::Kriging;
  EXPECT_THROW(make_blender(saved_old, kriging), ParameterError);
}

}  // namespace
}  // namespace motionmap::mapfile
