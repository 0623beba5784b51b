#pragma once
// UMAP (McInnes, Healy & Melville 2018) as embed() runs it, in pieces the tests check against
// umap-learn one at a time (docs/methods/umap.md):
//
//   UmapGraph g = umap_fuzzy_graph(lists, 15);     // rho, sigma, symmetric memberships
//   UmapCurve c = umap_curve(0.1, 1.0);            // a, b of 1 / (1 + a·d^(2b))
//
// n_neighbors counts the frame itself, as umap-learn's does: the k-NN lists hold the
// n_neighbors − 1 nearest other frames, and a frame's memberships sum to log2(n_neighbors).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

/// The fuzzy simplicial set of a k-NN graph.
struct UmapGraph {
  std::vector<double> rho;  ///< per frame: distance to its nearest neighbour at distance > 0
  std::vector<double> sigma;  ///< per frame: Σ_j exp(−max(0, d_j − rho)/sigma) = log2(n_neighbors)
  /// Symmetric memberships a + b − a·b of the directed ones a = exp(−max(0, d − rho)/sigma)
  /// (fuzzy union), in CSR form; every stored weight is > 0.
  Graph graph;
};

/// The fuzzy simplicial set of `lists` (each frame's n_neighbors − 1 nearest others, nearest
/// first): umap-learn's smooth_knn_dist (64 bisection steps on sigma, stopping within 1e-5 of the
/// target; sigma at least 1e-3 times the mean distance to the neighbours, the frame itself
/// counted as a neighbour at distance 0) and compute_membership_strengths, then the fuzzy union.
UmapGraph umap_fuzzy_graph(const NeighborLists& lists, int n_neighbors);

/// umap-learn's bisection for sigma (64 steps from 1, stopping within 1e-5 of `target`):
/// Σ_j exp(−max(0, d_j − rho)/sigma) = target over the `count` distances d; before any floor.
double umap_sigma(const double* d, int count, double rho, double target);

/// The curve 1 / (1 + a·d^(2b)) that the layout's attraction and repulsion use.
struct UmapCurve {
  double a = 0.0;
  double b = 0.0;
};

/// a and b fitted by least squares (Levenberg–Marquardt, from a = b = 1) to 1 for d < min_dist
/// and exp(−(d − min_dist)/spread) beyond, at 300 points d evenly spaced on [0, 3·spread]:
/// umap-learn's find_ab_params.
UmapCurve umap_curve(double min_dist, double spread = 1.0);

/// The layout's epochs when EmbedOptions::epochs is 0: 500 up to 10 000 frames, 200 above
/// (umap-learn's).
int umap_default_epochs(int frames);

}  // namespace motionmap::embed
