#pragma once
// Graph routines: geodesic distances (all-pairs shortest paths) for Isomap and the normalised
// graph Laplacian for the Laplacian eigenmap.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

/// Shortest-path length between every pair of frames along the graph's edges (weights =
/// lengths ≥ 0): a label-correcting search (binary heap) from blocks of consecutive frames at
/// once, which gives Dijkstra's sums, in parallel. Returns #frames by #frames, symmetric (+inf
/// between components). `control` gets the fraction of sources done. @throws Cancelled.
Eigen::MatrixXd shortest_paths(const Graph& graph, const Control& control = {});

/// The symmetric normalised Laplacian of a graph whose weights are edge weights w_ij > 0:
///   1. deg_i = Σ_j w_ij,
///   2. L_sym = I − Deg^{−½}·W·Deg^{−½}  (eigenvalues in [0, 2]; L_sym·√deg = 0).
/// L_sym·z = λ·z  ⇔  (Deg − W)·y = λ·Deg·y with y = Deg^{−½}·z, and yᵀ·Deg·y = zᵀz.
/// `degrees` receives deg (#frames); every degree must be > 0 (the caller checks).
Eigen::SparseMatrix<double> normalized_laplacian(const Graph& weighted, Eigen::VectorXd& degrees);

}  // namespace motionmap::embed
