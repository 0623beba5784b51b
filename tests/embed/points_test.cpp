// The points path (embed.h, "Two paths") against the dense one: the exact k-NN search of
// knn_from_points equals knn_from_distances on D bit for bit (real clips, ties, duplicates); the
// max-min landmarks are those of the definition; landmark Isomap's geodesic distances are the
// dense shortest paths' bits. (The maps themselves against the dense ones: points_path_test.cpp.)
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"
#include "motionmap/embed/placement.h"
#include "motionmap/embed/points.h"
#include "motionmap/features/features.h"
#include "motionmap/io/load.h"
#include "support/test_data.h"

namespace motionmap::embed {
namespace {

// Exact search from the points against knn_from_distances on D: the same frames in the same
// order (ties to the smaller index) and the same distance bits.
void expect_same_lists(const RowMatrix& points, const Eigen::MatrixXd& D, int k,
                       const std::string& what) {
  const NeighborLists want = knn_from_distances(D, k);
  NeighborSearchReport report;
  const NeighborLists got =
      knn_from_points({&points, Metric::Euclidean}, k, NeighborSearch::Exact, {}, &report);
  EXPECT_FALSE(report.approximate);
  ASSERT_EQ(got.k, k);
  ASSERT_EQ(got.index.size(), want.index.size());
  for (int i = 0; i < want.frames(); ++i) {
    for (int a = 0; a < k; ++a) {
      ASSERT_EQ(got.of(i)[a], want.of(i)[a]) << what << " k " << k << " frame " << i << " #" << a;
      ASSERT_EQ(got.distances_of(i)[a], want.distances_of(i)[a])
          << what << " k " << k << " frame " << i << " #" << a;
    }
  }
}

// n points near a `manifold`-dimensional curved sheet in `d` dimensions, turned at random (as
// poses are: many coordinates, few degrees of freedom), or integers in {0…3} (many exact ties).
RowMatrix sheet_points(int n, int d, int manifold, unsigned seed, bool integer = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> small(0, 3);
  RowMatrix P(n, d);
  if (integer) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < d; ++j) P(i, j) = small(rng);
    }
    return P;
  }
  Eigen::MatrixXd mix(manifold, d);
  for (int a = 0; a < manifold; ++a) {
    for (int j = 0; j < d; ++j) mix(a, j) = u(rng);
  }
  for (int i = 0; i < n; ++i) {
    Eigen::RowVectorXd t(manifold);
    for (int a = 0; a < manifold; ++a) t[a] = u(rng);
    P.row(i) = (t.array().sin() * 3.0).matrix() * mix;
    for (int j = 0; j < d; ++j) P(i, j) += 1e-3 * u(rng);
  }
  return P;
}

Eigen::MatrixXd distances_of(const RowMatrix& P) {
  return features::pairwise_distances(P);
}

TEST(EmbedPoints, PrincipalAxesAreOrthonormalLargestSpreadFirst) {
  // Points spread 10 along (1, 1, 0)/√2, 3 along z, 0.1 along (1, −1, 0)/√2.
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  RowMatrix points(500, 3);
  const Eigen::Vector3d a = Eigen::Vector3d(1, 1, 0).normalized(), b(0, 0, 1),
                        c = Eigen::Vector3d(1, -1, 0).normalized();
  for (Eigen::Index i = 0; i < points.rows(); ++i)
    points.row(i) = (10 * g(rng) * a + 3 * g(rng) * b + 0.1 * g(rng) * c).transpose();
  for (const Eigen::Index samples : {Eigen::Index(500), Eigen::Index(50)}) {
    const Eigen::MatrixXd axes = principal_axes(points, samples);
    ASSERT_EQ(axes.rows(), 3);
    ASSERT_EQ(axes.cols(), 3);
    EXPECT_LT((axes.transpose() * axes - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_GT(std::abs(axes.col(0).dot(a)), 0.99) << samples;
    EXPECT_GT(std::abs(axes.col(1).dot(b)), 0.99) << samples;
    EXPECT_GT(std::abs(axes.col(2).dot(c)), 0.99) << samples;
  }
  EXPECT_THROW(principal_axes(RowMatrix(0, 3)), ParameterError);
  EXPECT_THROW(principal_axes(RowMatrix(4, 0)), ParameterError);
  EXPECT_THROW(principal_axes(points, 0), ParameterError);
}

TEST(EmbedPoints, ExactSearchEqualsDistanceMatrixOnRealClips) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/64_09.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/02_03.bvh");
  for (const std::vector<std::string>& names :
       {std::vector<std::string>{"cmu/64_08.bvh", "cmu/64_09.bvh"},
        std::vector<std::string>{"cmu/02_03.bvh"}}) {
    std::vector<Clip> clips;
    for (const std::string& name : names) clips.push_back(io::load_clip(test::shared_file(name)));
    const features::FeatureSet set = features::build_features(clips, {});
    ASSERT_TRUE(set.has_distances());
    for (int k : {1, 5, 20, 60}) expect_same_lists(set.distance_input, set.D, k, names[0]);
  }
}

TEST(EmbedPoints, ExactSearchEqualsDistanceMatrixWithTiesAndDuplicates) {
  // Integer coordinates in {0…3}⁵: 1024 possible points, so thousands of exact ties and
  // duplicates, which the search settles by a radius search, as every pair would.
  for (int n : {3, 30, 700, 3000}) {
    const RowMatrix P = sheet_points(n, 5, 0, unsigned(n), true);
    const Eigen::MatrixXd D = distances_of(P);
    std::vector<int> ks{1, 2, std::min(20, n - 1)};
    if (n <= 700) ks.push_back(n - 1);
    for (int k : ks) expect_same_lists(P, D, k, "integers n " + std::to_string(n));
  }
  // Every frame the same pose.
  const RowMatrix same = RowMatrix::Constant(50, 7, 0.25);
  expect_same_lists(same, distances_of(same), 10, "one pose");
}

TEST(EmbedPoints, ExactSearchEqualsDistanceMatrixNearAManifold) {
  for (const auto& [n, d, m] : {std::tuple{400, 60, 3}, std::tuple{2500, 114, 6},
                                std::tuple{2000, 9, 9}, std::tuple{1500, 1, 1}}) {
    const RowMatrix P = sheet_points(n, d, m, unsigned(n + d));
    const Eigen::MatrixXd D = distances_of(P);
    for (int k : {1, 20}) {
      expect_same_lists(P, D, k, "sheet n " + std::to_string(n) + " d " + std::to_string(d));
    }
  }
}

// Max-min landmarks by their definition: frame 0, then each time the frame farthest from those
// chosen (ties: the smaller index), until `count` or every frame is at distance 0.
std::vector<int> maxmin_by_definition(const Eigen::MatrixXd& D, int count) {
  const int n = static_cast<int>(D.rows());
  std::vector<int> chosen{0};
  std::vector<double> nearest(static_cast<std::size_t>(n));
  for (int f = 0; f < n; ++f) nearest[f] = D(0, f);
  while (int(chosen.size()) < count) {
    const int next =
        static_cast<int>(std::max_element(nearest.begin(), nearest.end()) - nearest.begin());
    if (!(nearest[next] > 0.0)) break;
    chosen.push_back(next);
    for (int f = 0; f < n; ++f) nearest[f] = std::min(nearest[f], D(next, f));
  }
  return chosen;
}

TEST(EmbedPoints, MaxMinLandmarksFollowTheirDefinition) {
  for (bool integer : {false, true}) {
    for (int n : {1, 2, 40, 900}) {
      const RowMatrix P = sheet_points(n, 4, 2, unsigned(7 * n), integer);
      const Eigen::MatrixXd D = distances_of(P);
      for (int count : {1, 3, 64, n}) {
        const std::vector<int> want = maxmin_by_definition(D, std::min(count, n));
        const PointSet points{&P, Metric::Euclidean};
        EXPECT_EQ(maxmin_landmarks(points, count, {}), want)
            << "n " << n << " count " << count << " integer " << integer;
        Eigen::MatrixXd distances;
        ASSERT_EQ(maxmin_landmarks(points, count, distances, {}), want);
        ASSERT_EQ(distances.rows(), Eigen::Index(want.size()));
        for (std::size_t l = 0; l < want.size(); ++l) {
          for (int f = 0; f < n; ++f) ASSERT_EQ(distances(Eigen::Index(l), f), D(want[l], f));
        }
      }
    }
  }
}

// The real clips as points and as D.
features::FeatureSet real_set(const std::vector<std::string>& names) {
  std::vector<Clip> clips;
  for (const std::string& name : names) clips.push_back(io::load_clip(test::shared_file(name)));
  return features::build_features(clips, {});
}

TEST(EmbedPoints, LandmarkIsomapGeodesicsAreTheShortestPaths) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const features::FeatureSet set = real_set({"cmu/64_08.bvh"});
  for (int k : {10, 20}) {
    EmbedOptions options;
    options.method = Method::Isomap;
    options.k = k;
    options.landmarks = 40;
    const Embedding map =
        embed({.points = &set.distance_input, .metric = Metric::Euclidean}, options);
    ASSERT_TRUE(map.landmarks);
    ASSERT_EQ(map.graph_components, 1) << "k " << k;
    const Eigen::MatrixXd geodesic = shortest_paths(knn_graph(knn_from_distances(set.D, k), set.D));
    const LandmarkFit& fit = *map.landmarks;
    ASSERT_EQ(fit.frames.size(), 40u);
    // shortest_paths searches from the smaller frame of each pair: the sums of a path from the
    // landmark are its bits where the frame comes after the landmark, the reverse order's
    // elsewhere.
    for (std::size_t l = 0; l < fit.frames.size(); ++l) {
      const int from = fit.frames[l];
      for (int f = 0; f < set.num_samples(); ++f) {
        const double got = fit.geodesic(Eigen::Index(l), f);
        if (f >= from) {
          ASSERT_EQ(got, geodesic(f, from)) << "k " << k << " landmark " << l << " frame " << f;
        } else {
          ASSERT_NEAR(got, geodesic(f, from), 1e-12 * geodesic(f, from));
        }
      }
    }
  }
}

TEST(EmbedPoints, NearestSamplesAreThoseOfEveryPair) {
  for (bool integer : {false, true}) {
    const RowMatrix P = sheet_points(1500, 12, 3, 11u, integer);
    const Eigen::MatrixXd D = distances_of(P);
    // Every 3rd frame a sample; the queries are every frame, samples included.
    std::vector<int> sample, frames(1500);
    for (int f = 0; f < 1500; f += 3) sample.push_back(f);
    std::iota(frames.begin(), frames.end(), 0);
    RowMatrix S(Eigen::Index(sample.size()), P.cols());
    for (std::size_t j = 0; j < sample.size(); ++j) S.row(Eigen::Index(j)) = P.row(sample[j]);
    for (int k : {1, 7, 20}) {
      const NeighborLists nn =
          knn_to_samples({&S, Metric::Euclidean}, {&P, Metric::Euclidean}, frames, k);
      for (int f = 0; f < 1500; ++f) {
        std::vector<int> order(sample.size());
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(),
                         [&](int a, int b) { return D(sample[a], f) < D(sample[b], f); });
        for (int a = 0; a < k; ++a) {
          ASSERT_EQ(nn.of(f)[a], order[a]) << "frame " << f << " k " << k << " #" << a;
          ASSERT_EQ(nn.distances_of(f)[a], D(sample[order[a]], f));
        }
      }
    }
  }
}

// Searching prepared samples, or with bad arguments: the lists of a fresh search, or a clear
// error.
TEST(EmbedPoints, APreparedSearchAndBadArguments) {
  const RowMatrix P = sheet_points(300, 12, 3, 5u, false);
  const RowMatrix S = P.topRows(100);
  const RowMatrix narrow = P.leftCols(6);
  std::vector<int> frames(300);
  std::iota(frames.begin(), frames.end(), 0);
  const SampleSearch search({&S, Metric::Euclidean});
  const NeighborLists fresh =
      knn_to_samples({&S, Metric::Euclidean}, {&P, Metric::Euclidean}, frames, 5);
  for (int round = 0; round < 2; ++round) {
    const NeighborLists kept = search.nearest({&P, Metric::Euclidean}, frames, 5);
    EXPECT_EQ(kept.index, fresh.index);
    EXPECT_EQ(kept.distance, fresh.distance);
  }
  auto message = [](auto&& call) {
    try {
      call();
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no ParameterError");
  };
  EXPECT_EQ(message([&] {
              SampleSearch({nullptr, Metric::Euclidean});
            }),
            "knn: no samples were given");
  EXPECT_EQ(message([&] {
              search.nearest({nullptr, Metric::Euclidean}, frames, 5);
            }),
            "knn: no queries were given");
  EXPECT_EQ(message([&] {
              search.nearest({&P, Metric::Euclidean}, frames, 101);
            }),
            "k = 101 neighbours is out of range: with 100 samples it must be in [1, 100]");
  EXPECT_EQ(message([&] {
              search.nearest({&narrow, Metric::Euclidean}, frames, 5);
            }),
            "knn: the samples and the queries are points of different kinds");
  EXPECT_EQ(message([&] {
              knn_to_samples({&S, Metric::Euclidean}, {&P, Metric::QuaternionAngles}, frames, 5);
            }),
            "knn: the samples and the queries are points of different kinds");
}

// The sampled le and lle (embed.h, kGraphSampleLimit) are the method on the sample plus the
// placement of every other frame on that map (placement.h), here with a sample of every 3rd frame
// of a real walk.
TEST(EmbedPoints, SampledGraphMethodsAreTheSampleMapPlusPlacement) {
  MOTIONMAP_REQUIRE_SHARED("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh");
  const features::FeatureSet set = real_set({"other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"});
  const int n = set.num_samples(), limit = (n + 2) / 3;
  for (Method method : {Method::LaplacianEigenmap, Method::Lle}) {
    EmbedOptions options;
    options.method = method;
    options.k = 10;
    Embedding sampled;
    sampled.method = method;
    sampled.from_points = true;
    Progress progress;
    run_sampled_graph_method(&set.X, {&set.distance_input, Metric::Euclidean}, options, sampled,
                             progress, limit);
    ASSERT_EQ(sampled.warnings.size(), 1u);
    EXPECT_NE(sampled.warnings[0].find("every 3rd frame"), std::string::npos)
        << sampled.warnings[0];
    // The sample on its own, and the other frames placed on its map.
    std::vector<int> sample, others;
    for (int f = 0; f < n; ++f) (f % 3 == 0 ? sample : others).push_back(f);
    RowMatrix sample_points(Eigen::Index(sample.size()), set.distance_input.cols());
    Eigen::MatrixXd sample_X(Eigen::Index(sample.size()), set.X.cols());
    for (std::size_t j = 0; j < sample.size(); ++j) {
      sample_points.row(Eigen::Index(j)) = set.distance_input.row(sample[j]);
      sample_X.row(Eigen::Index(j)) = set.X.row(sample[j]);
    }
    const EmbedInput sample_input{
        .features = &sample_X, .points = &sample_points, .metric = Metric::Euclidean};
    const Embedding alone = embed(sample_input, options);
    RowMatrix other_points(Eigen::Index(others.size()), set.distance_input.cols());
    Eigen::MatrixXd other_X(Eigen::Index(others.size()), set.X.cols());
    for (std::size_t j = 0; j < others.size(); ++j) {
      other_points.row(Eigen::Index(j)) = set.distance_input.row(others[j]);
      other_X.row(Eigen::Index(j)) = set.X.row(others[j]);
    }
    const Eigen::MatrixXd placed =
        place(make_model(sample_input, options, alone), {&other_X, &other_points});
    // embed() flips each axis to make its largest entry positive; the sampled map is unflipped.
    for (Eigen::Index c = 0; c < alone.coordinates.cols(); ++c) {
      const double sign = alone.coordinates(0, c) * sampled.coordinates(0, c) < 0.0 ? -1.0 : 1.0;
      const double scale = alone.coordinates.col(c).cwiseAbs().maxCoeff();
      for (std::size_t j = 0; j < sample.size(); ++j) {
        ASSERT_EQ(sign * sampled.coordinates(sample[j], c), alone.coordinates(Eigen::Index(j), c))
            << method_name(method) << " sample " << j;
      }
      for (std::size_t j = 0; j < others.size(); ++j) {
        ASSERT_NEAR(sign * sampled.coordinates(others[j], c), placed(Eigen::Index(j), c),
                    1e-12 * scale)
            << method_name(method) << " frame " << others[j];
      }
    }
    // The map's model is the sample's map (the frames it was fitted on, not every frame), and
    // placing any frame of the map again lands exactly on its row.
    EXPECT_EQ(sampled.fitted_frames, sample);
    const EmbedInput all{
        .features = &set.X, .points = &set.distance_input, .metric = Metric::Euclidean};
    const MapModel model = make_model(all, options, sampled);
    EXPECT_EQ(model.points.rows(), Eigen::Index(sample.size()));
    EXPECT_EQ(model.coordinates.rows(), Eigen::Index(sample.size()));
    if (method == Method::Lle) {
      EXPECT_EQ(model.features.rows(), Eigen::Index(sample.size()));
    }
    const Eigen::MatrixXd again = place(model, {&set.X, &set.distance_input});
    for (int f = 0; f < n; ++f) {
      ASSERT_EQ(again.row(f), sampled.coordinates.row(f)) << method_name(method) << " frame " << f;
    }
  }
}

}  // namespace
}  // namespace motionmap::embed
