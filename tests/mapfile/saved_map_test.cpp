// Saved maps opened for use (mapfile::SavedMap, mapfile::PointIndex): the 2-D index against a
// brute-force search on real maps, clips loaded on demand and checked against the SHA-256 the
// map file recorded (a changed, missing or wrong clip is an error naming the file and what was
// expected), and poses blended on a saved map equal to the idw blend of the same clips mapped
// directly.
#include "motionmap/mapfile/saved_map.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/synth/blender.h"

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

}  // namespace
}  // namespace motionmap::mapfile
