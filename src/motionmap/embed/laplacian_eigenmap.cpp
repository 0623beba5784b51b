// Laplacian eigenmap (Belkin & Niyogi 2003): heat-kernel weights on the k-NN graph of D, then
// the generalised problem L·y = λ·Deg·y (L = Deg − W); the eigenvectors of the 2nd, 3rd (…)
// smallest eigenvalues, normalised yᵀ·Deg·y = 1, are the map. Solved in the symmetric
// normalised form L_sym·z = λ·z, y = Deg^{−½}·z, which is sparse and skips the known null
// vector √deg (y = constant).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/stats.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

namespace {

// The automatic heat: the median (numpy's) squared k-NN distance; if more than half of those are 0
// (duplicate frames), the median of the positive ones; 0 when every distance is 0.
double automatic_heat(const NeighborLists& lists) {
  std::vector<double> squared;
  squared.reserve(lists.distance.size());
  for (double d : lists.distance) squared.push_back(d * d);
  const double m = median(squared);
  if (m > 0.0) return m;
  std::vector<double> positive;
  for (double s : squared) {
    if (s > 0.0) positive.push_back(s);
  }
  return positive.empty() ? 0.0 : median(positive);
}

// Weight slot of edge a→b in a CSR row (rows are sorted by neighbour).
int slot(const Graph& g, int a, int b) {
  const auto first = g.targets.begin() + g.offsets[a];
  const auto last = g.targets.begin() + g.offsets[a + 1];
  return static_cast<int>(std::lower_bound(first, last, b) - g.targets.begin());
}

}  // namespace

void run_laplacian_eigenmap(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
                            Progress& progress) {
  laplacian_eigenmap_on(build_neighbor_graph(D, options, out, progress, 0.02, 0.3), options, out,
                        progress, 0.3);
}

void laplacian_eigenmap_on(const NeighborGraph& ng, const EmbedOptions& options, Embedding& out,
                           Progress& progress, double begin, double end) {
  const int n = ng.graph.frames();
  const double weights_end = begin + 0.05 * (end - begin) / 0.7;
  progress.stage("weights", begin, weights_end);
  const double auto_heat = automatic_heat(ng.lists);
  double heat = options.heat ? *options.heat : auto_heat;
  if (!options.heat && auto_heat == 0.0) {
    heat = 0.0;
    out.warnings.push_back("every k-NN distance is 0 (all frames identical); all weights are 1");
  }
  out.heat_used = std::max(heat, 0.0);

  Graph w = ng.graph;
  for (std::size_t e = 0; e < w.weights.size(); ++e) {
    const double len = w.weights[e];
    w.weights[e] = heat > 0.0 ? std::exp(-len * len / heat) : 1.0;
  }
  // A joining edge is usually far longer than the k-NN edges and its weight would underflow,
  // leaving the graph disconnected after all: keep it at the smallest normal double, so the
  // components stay joined and show as separate clusters.
  for (const Edge& j : ng.joins) {
    for (const auto& [a, b] : {std::pair{j.a, j.b}, std::pair{j.b, j.a}}) {
      double& weight = w.weights[slot(w, a, b)];
      weight = std::max(weight, std::numeric_limits<double>::min());
    }
  }
  // What to suggest: heat auto unless it is what failed.
  const std::string heat_text = (options.heat ? "= " : "auto = ") + format_number(heat, 6);
  const std::string hint =
      options.heat ? "use heat auto (here " + format_number(auto_heat, 6) + "), a larger heat"
                   : "use a larger heat";
  for (int i = 0; i < n; ++i) {
    bool any = false;
    double nearest = std::numeric_limits<double>::infinity();
    for (int e = w.offsets[i]; e < w.offsets[i + 1]; ++e) {
      any = any || w.weights[e] > 0.0;
      nearest = std::min(nearest, ng.graph.weights[e]);
    }
    if (!any) {
      throw NumericalError("le: every heat-kernel weight exp(−d²/heat) of frame " +
                           std::to_string(i) + " underflows to 0 (nearest neighbour at distance " +
                           format_number(nearest, 6) + ", heat " + heat_text + "); " + hint +
                           ", or drop the frame");
    }
  }
  const Components positive = connected_components(w, true);
  if (positive.count > 1) {
    throw NumericalError("le: heat-kernel weights that underflow to 0 split the k-NN graph into " +
                         std::to_string(positive.count) + " components (heat " + heat_text + "); " +
                         hint + ", or a larger k");
  }

  progress.stage("eigen", weights_end, end);
  Eigen::VectorXd degrees;
  const Eigen::SparseMatrix<double> L = normalized_laplacian(w, degrees);
  const Eigen::VectorXd q = degrees.cwiseSqrt().normalized();
  const EigenPairs low = smallest_eigenpairs_excluding(
      L, q, options.dimensions, "le", progress.control(), kDenseEigenLimit,
      out.from_points ? kPointsShiftInvert : ShiftInvert{});
  out.eigenvalues = low.values;
  out.coordinates = degrees.cwiseSqrt().cwiseInverse().asDiagonal() * low.vectors;
}

}  // namespace motionmap::embed
