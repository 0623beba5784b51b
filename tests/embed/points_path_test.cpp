// The points path of embed() (embed.h, "Two paths") against the dense path on real clips: with
// every frame a landmark, landmark MDS and Isomap are the dense maps; the Laplacian eigenmap and
// LLE on the points' k-NN graph are the dense ones; the exact k-NN search finds what D's columns
// give; the approximate one reports its recall; components are joined.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/points.h"
#include "motionmap/features/features.h"
#include "motionmap/io/load.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::embed {
namespace {

using ::testing::HasSubstr;

struct ClipData {
  features::FeatureSet set;  // X, D and the points D is computed from
  Metric metric = Metric::Euclidean;
};

ClipData clip_data(const std::string& relative,
                   features::DistanceKind kind = features::DistanceKind::PointCloud) {
  const Clip clip = io::load_clip(test::shared_file(relative));
  features::FeatureOptions options;
  options.distance = kind;
  ClipData out{features::build_features(std::span(&clip, 1), options)};
  out.metric =
      kind == features::DistanceKind::Geodesic ? Metric::QuaternionAngles : Metric::Euclidean;
  return out;
}

EmbedOptions with(Method method, int landmarks = 0) {
  EmbedOptions o;
  o.method = method;
  o.k = 10;
  o.landmarks = landmarks;
  return o;
}

class PointsPath : public ::testing::TestWithParam<std::string> {};

TEST_P(PointsPath, EveryFrameALandmarkOrTheSameGraphGivesTheDenseMap) {
  const ClipData d = clip_data(GetParam());
  const int frames = d.set.num_samples();
  for (Method m : {Method::Mds, Method::Isomap, Method::LaplacianEigenmap, Method::Lle}) {
    const EmbedOptions options = with(m, frames);
    const Embedding dense = embed({&d.set.X, &d.set.D}, options);
    const Embedding points =
        embed({.features = &d.set.X, .points = &d.set.distance_input, .metric = d.metric}, options);
    EXPECT_FALSE(dense.from_points);
    EXPECT_TRUE(points.from_points);
    EXPECT_LE(test::procrustes_disparity(dense.coordinates, points.coordinates), 1e-8)
        << method_name(m);
    if (m == Method::Mds || m == Method::Isomap) {
      ASSERT_TRUE(points.landmarks);
      EXPECT_EQ(int(points.landmarks->frames.size()), frames);
      EXPECT_NEAR(*points.stress, *dense.stress, 1e-8) << method_name(m);
    }
  }
}

TEST_P(PointsPath, FewLandmarksStayCloseToTheDenseMap) {
  const ClipData d = clip_data(GetParam());
  for (Method m : {Method::Mds, Method::Isomap}) {
    const Embedding dense = embed({&d.set.X, &d.set.D}, with(m));
    const Embedding points =
        embed({.features = &d.set.X, .points = &d.set.distance_input}, with(m, 64));
    EXPECT_EQ(points.landmarks->frames.size(), 64u);
    EXPECT_LE(test::procrustes_disparity(dense.coordinates, points.coordinates), 0.005)
        << method_name(m);
  }
}

TEST_P(PointsPath, ExactNeighboursAreTheColumnsOfD) {
  for (auto kind : {features::DistanceKind::PointCloud, features::DistanceKind::Geodesic}) {
    const ClipData d = clip_data(GetParam(), kind);
    const NeighborLists from_d = knn_from_distances(d.set.D, 10);
    NeighborSearchReport report;
    const NeighborLists from_points =
        knn_from_points({&d.set.distance_input, d.metric}, 10, NeighborSearch::Exact, {}, &report);
    EXPECT_EQ(from_points.index, from_d.index);
    EXPECT_EQ(from_points.distance, from_d.distance);
    EXPECT_FALSE(report.approximate);
    EXPECT_EQ(report.description(), "exact");
  }
}

INSTANTIATE_TEST_SUITE_P(RealClips, PointsPath,
                         ::testing::Values("cmu/64_08.bvh", "cmu/02_03.bvh",
                                           "other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"),
                         test::file_test_name);

TEST(PointsPath, ApproximateNeighboursReportTheirRecall) {
  const ClipData d = clip_data("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh");
  NeighborSearchReport report;
  const NeighborLists lists = knn_from_points({&d.set.distance_input, d.metric}, 10,
                                              NeighborSearch::Approximate, {}, &report);
  EXPECT_TRUE(report.approximate);
  EXPECT_EQ(report.recall_queries, 200);
  EXPECT_GE(report.recall, 0.95);
  EXPECT_THAT(report.description(), HasSubstr("approximate (HNSW), recall"));
  // Every list is sorted and never holds the frame itself.
  for (int i = 0; i < lists.frames(); ++i) {
    const auto nb = lists.of(i);
    const auto nd = lists.distances_of(i);
    EXPECT_EQ(std::count(nb.begin(), nb.end(), i), 0);
    EXPECT_TRUE(std::is_sorted(nd.begin(), nd.end()));
  }
}

TEST(PointsPath, MaxMinLandmarksAreEachTheFarthestFromThoseBefore) {
  const ClipData d = clip_data("cmu/64_08.bvh");
  const Embedding map =
      embed({.features = &d.set.X, .points = &d.set.distance_input}, with(Method::Mds, 20));
  const std::vector<int>& l = map.landmarks->frames;
  ASSERT_EQ(l.size(), 20u);
  EXPECT_EQ(l[0], 0);
  const PointSet points{&d.set.distance_input};
  for (std::size_t a = 1; a < l.size(); ++a) {
    auto nearest_chosen = [&](int f) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t b = 0; b < a; ++b) best = std::min(best, points.distance(l[b], f));
      return best;
    };
    const double chosen = nearest_chosen(l[a]);
    for (int f = 0; f < points.frames(); ++f) EXPECT_LE(nearest_chosen(f), chosen);
  }
}

TEST(PointsPath, ComponentsAreJoinedOrStrictlyRefused) {
  // Two clips far apart: a clip's points and the same points moved 10 m away.
  const ClipData d = clip_data("cmu/64_08.bvh");
  const Eigen::Index n = d.set.distance_input.rows();
  RowMatrix points(2 * n, d.set.distance_input.cols());
  points.topRows(n) = d.set.distance_input;
  points.bottomRows(n) = d.set.distance_input.array() + 1000.0;
  for (Method m : {Method::Isomap, Method::LaplacianEigenmap}) {
    EmbedOptions options = with(m);
    const Embedding map = embed({.points = &points}, options);
    EXPECT_EQ(map.graph_components, 2);
    EXPECT_EQ(map.connecting_edges, 1);
    ASSERT_FALSE(map.warnings.empty());
    EXPECT_THAT(map.warnings[0], HasSubstr("has 2 connected components; joined them with 1 "
                                           "edge(s) between a frame and a landmark"));
    options.strict = true;
    EXPECT_THAT(test::error_message<NumericalError>([&] { embed({.points = &points}, options); }),
                HasSubstr("has 2 connected components; use a larger k"));
  }
}

TEST(PointsPath, ManyComponentsAreJoinedIntoAChain) {
  // Five copies of a clip, 10 m apart along a line: four joins, between neighbouring copies, so
  // Isomap's first axis orders the copies as the line does.
  const ClipData d = clip_data("cmu/02_03.bvh");
  const Eigen::Index n = d.set.distance_input.rows();
  RowMatrix points(5 * n, d.set.distance_input.cols());
  for (int c = 0; c < 5; ++c) {
    points.middleRows(c * n, n) = d.set.distance_input;
    points.middleRows(c * n, n).col(0).array() += 1000.0 * c;
  }
  const Embedding map = embed({.points = &points}, with(Method::Isomap, 100));
  EXPECT_EQ(map.graph_components, 5);
  EXPECT_EQ(map.connecting_edges, 4);
  std::vector<double> centre(5);
  for (int c = 0; c < 5; ++c) centre[c] = map.coordinates.col(0).segment(c * n, n).mean();
  EXPECT_TRUE(std::is_sorted(centre.begin(), centre.end()) ||
              std::is_sorted(centre.rbegin(), centre.rend()))
      << centre[0] << " " << centre[1] << " " << centre[2] << " " << centre[3] << " " << centre[4];
}

TEST(PointsPath, BadPointsAndOptionsAreClearErrors) {
  const ClipData d = clip_data("cmu/02_03.bvh");
  RowMatrix bad = d.set.distance_input;
  bad(3, 4) = std::numeric_limits<double>::infinity();
  EXPECT_THAT(
      test::error_message<ParameterError>([&] { embed({.points = &bad}, with(Method::Mds)); }),
      HasSubstr("mds: points(3, 4) is inf; every value must be finite"));
  EXPECT_THAT(test::error_message<ParameterError>(
                  [&] { embed({.points = &d.set.distance_input}, with(Method::Mds, 2)); }),
              HasSubstr("landmarks = 2 is out of range; give 0 (the default, 256) or at least 3"));
  const Eigen::MatrixXd short_x = d.set.X.topRows(10);
  EXPECT_THAT(test::error_message<ParameterError>([&] {
                embed({.features = &short_x, .points = &d.set.distance_input}, with(Method::Lle));
              }),
              HasSubstr("lle: X has 10 rows but the points have"));
}

TEST(PointsPath, TriangulationPlacesEachFrameOnItsOwn) {
  const ClipData d = clip_data("cmu/64_08.bvh");
  const Embedding map =
      embed({.features = &d.set.X, .points = &d.set.distance_input}, with(Method::Mds, 30));
  RowMatrix landmarks(30, d.set.distance_input.cols());
  for (int l = 0; l < 30; ++l)
    landmarks.row(l) = d.set.distance_input.row(map.landmarks->frames[l]);
  const EuclideanToLandmarks to_landmarks(landmarks);
  const int n = d.set.num_samples();
  Eigen::MatrixXd distances(30, n);
  to_landmarks.compute(d.set.distance_input, 0, n, distances);
  EXPECT_EQ(triangulate(*map.landmarks, distances), map.coordinates);
  // Frame 7's distances computed alone are the same bits, and it lands on its coordinates.
  Eigen::MatrixXd seventh(30, 1);
  to_landmarks.compute(d.set.distance_input, 7, 1, seventh);
  EXPECT_EQ(seventh, distances.col(7));
  const Eigen::MatrixXd one = triangulate(*map.landmarks, seventh);
  EXPECT_EQ(one.row(0), map.coordinates.row(7));
}

TEST(PointsPath, DistancesToLandmarksAreTheMetricsToRounding) {
  const ClipData d = clip_data("cmu/02_03.bvh");
  const PointSet points{&d.set.distance_input};
  const int n = d.set.num_samples();
  const std::vector<int> chosen = {0, 5, 17, n / 2, n / 2 + 1, n - 1};
  RowMatrix landmarks(Eigen::Index(chosen.size()), d.set.distance_input.cols());
  for (std::size_t l = 0; l < chosen.size(); ++l) {
    landmarks.row(Eigen::Index(l)) = d.set.distance_input.row(chosen[l]);
  }
  Eigen::MatrixXd distances(Eigen::Index(chosen.size()), n);
  EuclideanToLandmarks(landmarks).compute(d.set.distance_input, 0, n, distances);
  const double size = d.set.distance_input.cwiseAbs().maxCoeff();
  for (int f = 0; f < n; ++f) {
    for (std::size_t l = 0; l < chosen.size(); ++l) {
      // ‖p‖² + ‖q‖² − 2·p·q loses digits to cancellation: about 1e-7 of the points' size for
      // frames close to a landmark.
      EXPECT_NEAR(distances(Eigen::Index(l), f), points.distance(chosen[l], f), 1e-6 * size)
          << "frame " << f << ", landmark " << chosen[l];
    }
  }
}

}  // namespace
}  // namespace motionmap::embed
