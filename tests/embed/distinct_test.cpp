// Frames that repeat a pose exactly (detail/distinct.h): a looped take, a held pose. The graph
// methods map each distinct pose once and place every repeat on its first occurrence, so a clip
// looped and held gives, row for row, the map of the clip itself, bit for bit, on both paths;
// its model places new frames as the clip's own model does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "motionmap/embed/detail/distinct.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/placement.h"
#include "motionmap/features/features.h"
#include "motionmap/io/load.h"
#include "support/test_data.h"

namespace motionmap::embed {
namespace {

features::FeatureSet features_of(const std::string& relative) {
  const Clip clip = io::load_clip(test::shared_file(relative));
  return features::build_features(std::span(&clip, 1), features::FeatureOptions{});
}

// The clip three times over, with frame 100 held for 20 more frames after its first showing:
// every frame of the result, and where it first appears in the clip.
std::vector<int> looped_and_held(int frames) {
  std::vector<int> order;
  for (int loop = 0; loop < 3; ++loop) {
    for (int f = 0; f < frames; ++f) {
      order.push_back(f);
      if (loop == 0 && f == 100) order.insert(order.end(), 20, 100);
    }
  }
  return order;
}

struct Inputs {
  Eigen::MatrixXd X, D;
  RowMatrix points;
};

Inputs rows(const features::FeatureSet& set, const std::vector<int>& order) {
  const Eigen::Map<const Eigen::VectorXi> at(order.data(), Eigen::Index(order.size()));
  return {set.X(at, Eigen::all), set.D(at, at), set.distance_input(at, Eigen::all)};
}

TEST(DistinctPoses, FindsTheFirstOccurrenceOfEveryRepeatedRow) {
  RowMatrix points(6, 2);
  points << 1, 2, 3, 4, 1, 2, -0.0, 5, 0.0, 5, 3, 4;
  const DistinctPoses rows = distinct_rows({&points, Metric::Euclidean});
  EXPECT_EQ(rows.first, (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(rows.pose_of, (std::vector<int>{0, 1, 0, 2, 2, 1}));
  EXPECT_EQ(rows.repeats(), 3);

  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(6, 6);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) D(i, j) = (points.row(i) - points.row(j)).norm();
  }
  const DistinctPoses dense = distinct_in_distances(D);
  EXPECT_EQ(dense.first, rows.first);
  EXPECT_EQ(dense.pose_of, rows.pose_of);
}

// The tolerance merges no two frames of real captures: the nearest two differing poses of a
// 120-fps or 30-fps take are orders of magnitude further apart.
TEST(DistinctPoses, RealCapturesHaveNoRepeats) {
  for (const char* clip :
       {"cmu/64_08.bvh", "cmu/02_03.bvh", "other/20tab_test_mocapbank.bvh",
        "other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh", "bandai/dataset-1_walk_angry_001.bvh",
        "bandai/dataset-1_bow_old_001.bvh"}) {
    const features::FeatureSet set = features_of(clip);
    const PointSet points{&set.distance_input, Metric::Euclidean};
    EXPECT_EQ(distinct_rows(points).repeats(), 0) << clip;
    EXPECT_EQ(distinct_in_distances(set.D).repeats(), 0) << clip;
    // How close the closest two frames come, against the tolerance.
    double closest = std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 1; j < set.D.cols(); ++j)
      closest = std::min(closest, set.D.col(j).head(j).minCoeff());
    const double scale = std::sqrt(set.D.squaredNorm() / (2.0 * set.D.size()));
    EXPECT_GT(closest, 100 * kRepeatTolerance * scale) << clip;
    std::printf("%s: closest frames %.3g of the scale\n", clip, closest / scale);
  }
}

class RepeatedFrames : public ::testing::TestWithParam<Method> {};

TEST_P(RepeatedFrames, MapTheDistinctPosesOnceBitForBit) {
  const features::FeatureSet set = features_of("cmu/64_08.bvh");
  const int frames = set.num_samples();
  const std::vector<int> order = looped_and_held(frames);
  const Inputs looped = rows(set, order);
  EmbedOptions options;
  options.method = GetParam();
  options.k = 10;
  for (const bool on_points : {false, true}) {
    SCOPED_TRACE(on_points ? "points path" : "dense path");
    // The points are there on the dense path too: make_model keeps them to place frames.
    const EmbedInput clip_input{&set.X, on_points ? nullptr : &set.D, &set.distance_input};
    const EmbedInput looped_input{&looped.X, on_points ? nullptr : &looped.D, &looped.points};
    const Embedding clip = embed(clip_input, options);
    ASSERT_EQ(clip.repeated_frames, 0);
    ASSERT_TRUE(clip.notes.empty());
    const Embedding map = embed(looped_input, options);
    ASSERT_EQ(map.coordinates.rows(), Eigen::Index(order.size()));
    for (std::size_t f = 0; f < order.size(); ++f) {
      ASSERT_EQ(map.coordinates.row(Eigen::Index(f)), clip.coordinates.row(order[f])) << f;
    }
    EXPECT_EQ(map.repeated_frames, int(order.size()) - frames);
    ASSERT_EQ(map.notes.size(), 1u);
    EXPECT_NE(map.notes[0].find(std::to_string(frames) + " distinct poses"), std::string::npos)
        << map.notes[0];
    EXPECT_EQ(map.graph_components, clip.graph_components);

    // Its model places new frames (another swing) where the clip's own model places them.
    const features::FeatureSet other = features_of("cmu/64_09.bvh");
    const MapModel clip_model = make_model(clip_input, options, clip);
    const MapModel looped_model = make_model(looped_input, options, map);
    const PlaceInput place_input{&other.X, &other.distance_input};
    EXPECT_EQ(place(looped_model, place_input), place(clip_model, place_input));
  }
}

INSTANTIATE_TEST_SUITE_P(GraphMethods, RepeatedFrames,
                         ::testing::Values(Method::Isomap, Method::LaplacianEigenmap, Method::Lle),
                         [](const auto& info) { return std::string(method_name(info.param)); });

TEST(RepeatedFrames, KIsCappedByTheDistinctPosesAndTooFewAreMappedAsTheyAre) {
  const features::FeatureSet set = features_of("cmu/64_08.bvh");
  // 30 distinct poses, each shown 10 times in a row.
  std::vector<int> order;
  for (int f = 0; f < 30; ++f) order.insert(order.end(), 10, f + 1);
  const Inputs held = rows(set, order);
  EmbedOptions options;
  options.method = Method::Isomap;
  options.k = 40;
  const Embedding map = embed({&held.X, &held.D}, options);
  EXPECT_EQ(map.k_used, 29);
  ASSERT_FALSE(map.warnings.empty());
  EXPECT_NE(map.warnings.back().find("k = 29 used"), std::string::npos) << map.warnings.back();

  // Too few distinct poses for a 2-D map (3; a static clip has 1): the frames are mapped as
  // they are, as before, with no note.
  const std::vector<int> three = {5, 6, 7, 5, 6, 7, 5, 6, 7};
  const Inputs few = rows(set, three);
  options.k = 2;
  const Embedding degenerate = embed({&few.X, &few.D}, options);
  EXPECT_TRUE(degenerate.coordinates.allFinite());
  EXPECT_EQ(degenerate.repeated_frames, 0);
  EXPECT_TRUE(degenerate.notes.empty());
}

}  // namespace
}  // namespace motionmap::embed
