#pragma once
// Neighbour routines shared by Isomap, the Laplacian eigenmap and LLE: k nearest neighbours from
// a distance matrix, the symmetric k-NN graph in CSR form, its connected components, and the
// edges that join the components when the graph falls apart.
//
//   NeighborLists nn = knn_from_distances(D, 10);   // frame i's 10 nearest: nn.of(i)
//   Graph g = knn_graph(nn, D);                     // i–j when either chose the other
//   Components c = connected_components(g);        // c.count == 1: connected
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

/// The length of pair {i, j} as every routine reads it: D's lower triangle, D(max, min).
inline double pair_distance(const Eigen::MatrixXd& D, int i, int j) {
  return i > j ? D(i, j) : D(j, i);
}

/// Each frame's k nearest other frames, nearest first.
struct NeighborLists {
  int k = 0;
  std::vector<int> index;        ///< #frames·k: frame i's neighbours at [i·k, i·k + k)
  std::vector<double> distance;  ///< the same layout: their distances

  int frames() const { return k > 0 ? static_cast<int>(index.size()) / k : 0; }
  std::span<const int> of(int i) const {
    return {index.data() + std::size_t(i) * k, std::size_t(k)};
  }
  std::span<const double> distances_of(int i) const {
    return {distance.data() + std::size_t(i) * k, std::size_t(k)};
  }
};

/// The k smallest of values[0 … n) other than values[self], as indices (nearest first) and
/// values; of equal values the smaller index wins. One pass, O(n) for small k (entries next to
/// `self` are looked at first, which along a clip finds the nearest early).
void k_nearest(const double* values, int n, int self, int k, int* index, double* nearest);

/// The k nearest neighbours of every frame by D (column i of D; the frame itself excluded; of
/// equal distances the smaller frame index wins). D: #frames by #frames, symmetric, validated.
/// Runs in parallel; `control` gets the fraction of frames done and may throw
/// Cancelled. @throws ParameterError unless 1 ≤ k ≤ #frames − 1.
NeighborLists knn_from_distances(const Eigen::MatrixXd& D, int k, const Control& control = {});

/// The one check of a neighbour count: k neighbours among `count` `what` ("frames", "samples")
/// must be in [1, most]. @throws ParameterError "k = 0 neighbours is out of range: with 364
/// frames it must be in [1, 363]".
void check_neighbor_count(int k, int most, int count, std::string_view what);

/// An undirected edge between frames a and b of the given length.
struct Edge {
  int a = 0;
  int b = 0;
  double length = 0.0;
};

/// Undirected weighted graph over the frames in CSR form: every edge is stored in both of its
/// rows; each row is sorted by neighbour index.
struct Graph {
  std::vector<int> offsets;     ///< #frames + 1
  std::vector<int> targets;     ///< neighbour of each stored entry
  std::vector<double> weights;  ///< its weight (a length, or a kernel weight)

  int frames() const { return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1; }
  /// Number of undirected edges.
  std::size_t edge_count() const { return targets.size() / 2; }
};

/// The symmetric k-NN graph: an edge i–j when j is among i's neighbours or i among j's, of
/// length pair_distance(D, i, j); plus `extra` edges (joins). Duplicates are merged.
Graph knn_graph(const NeighborLists& neighbors, const Eigen::MatrixXd& D,
                const std::vector<Edge>& extra = {});

/// Connected components of a graph.
struct Components {
  std::vector<int> label;  ///< #frames: component of each frame, numbered by their first frame
  int count = 0;
};

/// Components of `graph`, considering only edges whose weight is > 0 when `positive_only`.
Components connected_components(const Graph& graph, bool positive_only = false);

/// count − 1 edges that join the components into one: a minimum spanning tree over the
/// components, where joining two costs their closest pair of frames by D (Prim's algorithm grown
/// from frame 0's component; ties go to the smaller frame index). O(#frames²).
std::vector<Edge> joining_edges(const Eigen::MatrixXd& D, const Components& components,
                                const Control& control = {});

}  // namespace motionmap::embed
