// Neighbour and graph routines against brute force: k-NN (with ties), the symmetric graph,
// components, the joining edges (a minimum spanning tree over components), shortest paths
// (Floyd–Warshall) and the normalised Laplacian.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {
namespace {

Eigen::MatrixXd random_points(int n, int d, unsigned seed, bool integer = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> small(0, 3);
  Eigen::MatrixXd X(n, d);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < d; ++j) X(i, j) = integer ? small(rng) : u(rng);
  }
  return X;
}

// Brute force: sort the other frames by (distance, index).
std::vector<int> brute_knn(const Eigen::MatrixXd& D, int i, int k) {
  std::vector<int> order;
  for (int j = 0; j < D.rows(); ++j) {
    if (j != i) order.push_back(j);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return D(a, i) < D(b, i); });
  order.resize(std::size_t(k));
  return order;
}

TEST(EmbedNeighbors, KnnMatchesBruteForce) {
  // Integer coordinates in {0…3}³ make many exact ties: they must go to the smaller index.
  for (bool ties : {false, true}) {
    for (int n : {5, 37, 300, 1100}) {
      const Eigen::MatrixXd X = random_points(n, 3, unsigned(n), ties);
      const Eigen::MatrixXd D = test::euclidean_distances(X);
      for (int k : {1, 4, std::min(20, n - 1), n - 1}) {
        const NeighborLists nn = knn_from_distances(D, k);
        ASSERT_EQ(nn.frames(), n);
        for (int i = 0; i < n; ++i) {
          const auto got = nn.of(i);
          const std::vector<int> want = brute_knn(D, i, k);
          ASSERT_EQ(std::vector<int>(got.begin(), got.end()), want)
              << "n " << n << " k " << k << " frame " << i << " ties " << ties;
          for (int a = 0; a < k; ++a) EXPECT_EQ(nn.distances_of(i)[a], D(want[a], i));
        }
      }
    }
  }
}

TEST(EmbedNeighbors, KnnRejectsBadK) {
  const Eigen::MatrixXd D = test::euclidean_distances(random_points(6, 2, 1));
  for (int k : {0, 6, -1}) {
    try {
      knn_from_distances(D, k);
      ADD_FAILURE() << "k " << k;
    } catch (const ParameterError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("k = " + std::to_string(k) +
                                                 " neighbours is out of range: with 6 frames it "
                                                 "must be in [1, 5]"));
    }
  }
}

TEST(EmbedNeighbors, GraphIsTheSymmetrisedKnn) {
  const int n = 200, k = 6;
  const Eigen::MatrixXd D = test::euclidean_distances(random_points(n, 3, 7));
  const NeighborLists nn = knn_from_distances(D, k);
  const Graph g = knn_graph(nn, D);
  std::set<std::pair<int, int>> want;
  for (int i = 0; i < n; ++i) {
    for (int j : nn.of(i)) {
      want.insert({i, j});
      want.insert({j, i});
    }
  }
  std::set<std::pair<int, int>> got;
  for (int i = 0; i < n; ++i) {
    for (int e = g.offsets[i]; e < g.offsets[i + 1]; ++e) {
      got.insert({i, g.targets[e]});
      EXPECT_EQ(g.weights[e], pair_distance(D, i, g.targets[e]));
      if (e > g.offsets[i]) {
        EXPECT_LT(g.targets[e - 1], g.targets[e]);  // sorted, no duplicates
      }
    }
  }
  EXPECT_EQ(got, want);
  EXPECT_EQ(g.edge_count(), want.size() / 2);
}

TEST(EmbedNeighbors, ComponentsAndJoiningEdgesAreAMinimumSpanningTree) {
  // Four clusters far apart (and at different gaps), k = 3: four components.
  Eigen::MatrixXd X = random_points(80, 2, 3);
  for (int i = 0; i < 80; ++i) X(i, 0) += (i / 20) * (10.0 + 3.0 * (i / 20));
  const Eigen::MatrixXd D = test::euclidean_distances(X);
  const NeighborLists nn = knn_from_distances(D, 3);
  const Components c = connected_components(knn_graph(nn, D));
  ASSERT_EQ(c.count, 4);
  for (int i = 0; i < 80; ++i) EXPECT_EQ(c.label[i], i / 20);

  const std::vector<Edge> joins = joining_edges(D, c);
  ASSERT_EQ(joins.size(), 3u);
  const Graph joined = knn_graph(nn, D, joins);
  EXPECT_EQ(connected_components(joined).count, 1);
  // Brute force: the closest pair between every two components, then Kruskal.
  double closest[4][4];
  for (auto& row : closest) std::fill(row, row + 4, std::numeric_limits<double>::infinity());
  for (int i = 0; i < 80; ++i) {
    for (int j = 0; j < 80; ++j) {
      const int a = c.label[i], b = c.label[j];
      if (a != b) closest[a][b] = std::min(closest[a][b], D(i, j));
    }
  }
  std::vector<std::tuple<double, int, int>> pairs;
  for (int a = 0; a < 4; ++a) {
    for (int b = a + 1; b < 4; ++b) pairs.emplace_back(closest[a][b], a, b);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> parent(4);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x];
    return x;
  };
  double mst = 0.0;
  for (const auto& [w, a, b] : pairs) {
    if (find(a) != find(b)) {
      parent[find(a)] = find(b);
      mst += w;
    }
  }
  double total = 0.0;
  for (const Edge& e : joins) {
    EXPECT_EQ(e.length, D(e.a, e.b));
    EXPECT_NE(c.label[e.a], c.label[e.b]);
    total += e.length;
  }
  EXPECT_DOUBLE_EQ(total, mst);
}

TEST(EmbedNeighbors, PositiveOnlyComponentsIgnoreZeroWeights) {
  Graph g;  // path 0–1–2–3 with the middle edge weight 0
  g.offsets = {0, 1, 3, 5, 6};
  g.targets = {1, 0, 2, 1, 3, 2};
  g.weights = {1.0, 1.0, 0.0, 0.0, 1.0, 1.0};
  EXPECT_EQ(connected_components(g).count, 1);
  const Components c = connected_components(g, true);
  EXPECT_EQ(c.count, 2);
  EXPECT_EQ(c.label, (std::vector<int>{0, 0, 1, 1}));
}

TEST(EmbedGraph, ShortestPathsMatchFloydWarshall) {
  for (int n : {2, 50, 333}) {
    const Eigen::MatrixXd D = test::euclidean_distances(random_points(n, 3, unsigned(10 + n)));
    const Graph g = knn_graph(knn_from_distances(D, std::min(4, n - 1)), D);
    const Eigen::MatrixXd got = shortest_paths(g);
    Eigen::MatrixXd fw = Eigen::MatrixXd::Constant(n, n, std::numeric_limits<double>::infinity());
    for (int i = 0; i < n; ++i) {
      fw(i, i) = 0.0;
      for (int e = g.offsets[i]; e < g.offsets[i + 1]; ++e) fw(i, g.targets[e]) = g.weights[e];
    }
    for (int m = 0; m < n; ++m) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) fw(i, j) = std::min(fw(i, j), fw(i, m) + fw(m, j));
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        if (std::isinf(fw(i, j))) {
          EXPECT_TRUE(std::isinf(got(i, j)));
        } else {
          EXPECT_NEAR(got(i, j), fw(i, j), 1e-12 * (1.0 + fw(i, j))) << i << " " << j;
        }
      }
    }
  }
}

TEST(EmbedGraph, ShortestPathsAcrossComponentsAreInfinite) {
  Graph g;  // 0–1 and 2–3, weights 2 and 0 (a duplicate frame)
  g.offsets = {0, 1, 2, 3, 4};
  g.targets = {1, 0, 3, 2};
  g.weights = {2.0, 2.0, 0.0, 0.0};
  const Eigen::MatrixXd p = shortest_paths(g);
  EXPECT_EQ(p(0, 1), 2.0);
  EXPECT_EQ(p(2, 3), 0.0);
  EXPECT_TRUE(std::isinf(p(0, 2)));
  EXPECT_TRUE(std::isinf(p(3, 1)));
}

TEST(EmbedGraph, NormalizedLaplacian) {
  Graph g;  // triangle with weights 1, 2, 3
  g.offsets = {0, 2, 4, 6};
  g.targets = {1, 2, 0, 2, 0, 1};
  g.weights = {1.0, 3.0, 1.0, 2.0, 3.0, 2.0};
  Eigen::VectorXd deg;
  const Eigen::MatrixXd L = Eigen::MatrixXd(normalized_laplacian(g, deg));
  EXPECT_EQ(deg, Eigen::Vector3d(4.0, 3.0, 5.0));
  Eigen::Matrix3d W;
  W << 0, 1, 3, 1, 0, 2, 3, 2, 0;
  const Eigen::Vector3d s = deg.cwiseSqrt().cwiseInverse();
  const Eigen::Matrix3d want = Eigen::Matrix3d::Identity() - s.asDiagonal() * W * s.asDiagonal();
  EXPECT_LE((L - want).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((L * deg.cwiseSqrt()).norm(), 1e-14);  // √deg spans the null space
}

}  // namespace
}  // namespace motionmap::embed
