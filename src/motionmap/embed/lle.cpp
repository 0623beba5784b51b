// Locally linear embedding (Roweis & Saul 2000), as sklearn's LocallyLinearEmbedding but with
// the neighbours taken from D: each frame's reconstruction weights from its neighbours in X,
// then the bottom eigenvectors of M = (I − W)ᵀ(I − W), skipping the constant one.
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

namespace {
constexpr int kFramesPerChunk = 32;
}  // namespace

void run_lle(const Eigen::MatrixXd& X, const Eigen::MatrixXd& D, const EmbedOptions& options,
             Embedding& out, Progress& progress) {
  lle_on(X, build_neighbor_graph(D, options, out, progress, 0.02, 0.2), options, out, progress,
         0.2);
}

void lle_on(const Eigen::MatrixXd& X, const NeighborGraph& ng, const EmbedOptions& options,
            Embedding& out, Progress& progress, double begin, double end) {
  const double weights_end = begin + 0.25 * (end - begin);
  const int n = static_cast<int>(X.rows());
  const int k = ng.lists.k;
  // A joining edge a–b makes each end an extra neighbour of the other, which couples the
  // components' weights (otherwise M would be block diagonal with one null vector per block).
  std::vector<std::vector<int>> extra(static_cast<std::size_t>(n));
  for (const Edge& e : ng.joins) {
    extra[e.a].push_back(e.b);
    extra[e.b].push_back(e.a);
  }
  std::vector<int> offsets(std::size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i) offsets[i + 1] = offsets[i] + k + int(extra[i].size());
  std::vector<int> columns(static_cast<std::size_t>(offsets[n]));
  std::vector<double> weights(columns.size());

  progress.stage("weights", begin, weights_end);
  // Row-major, so gathering a frame's neighbours reads contiguous rows.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = X;
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  parallel_chunks(
      chunks,
      [&](int c, int) {
        Eigen::MatrixXd Z, C;
        const int end = std::min(n, (c + 1) * kFramesPerChunk);
        for (int i = c * kFramesPerChunk; i < end; ++i) {
          int* nb = columns.data() + offsets[i];
          const auto own = ng.lists.of(i);
          std::copy(own.begin(), own.end(), nb);
          std::copy(extra[i].begin(), extra[i].end(), nb + k);
          const int m = offsets[i + 1] - offsets[i];
          // 1. Z = X[nbrs] − X[i];  2. C = Z·Zᵀ + reg·trace(C)·I (reg alone when the trace is 0,
          // e.g. duplicate frames);  3. C·w = 1;  4. w /= Σw.
          Z.resize(m, X.cols());
          for (int a = 0; a < m; ++a) Z.row(a) = rows.row(nb[a]) - rows.row(i);
          // (C is symmetric: only its lower triangle is computed, and read by LLT.)
          C.setZero(m, m);
          C.selfadjointView<Eigen::Lower>().rankUpdate(Z);
          const double trace = C.trace();
          C.diagonal().array() += trace > 0.0 ? options.reg * trace : options.reg;
          Eigen::VectorXd w = C.llt().solve(Eigen::VectorXd::Ones(m));
          w /= w.sum();
          std::copy(w.data(), w.data() + m, weights.data() + offsets[i]);
        }
      },
      [&](int done) { progress.update(double(done) / chunks); });

  progress.stage("eigen", weights_end, end);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(weights.size() + std::size_t(n));
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 1.0);
    for (int e = offsets[i]; e < offsets[i + 1]; ++e)
      entries.emplace_back(i, columns[e], -weights[e]);
  }
  Eigen::SparseMatrix<double> A(n, n);  // I − W
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> M = Eigen::SparseMatrix<double>(A.transpose()) * A;
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(n, 1.0 / std::sqrt(double(n)));
  const EigenPairs low = smallest_eigenpairs_excluding(
      M, q, options.dimensions, "lle", progress.control(), kDenseEigenLimit,
      out.from_points ? kPointsShiftInvert : ShiftInvert{});
  out.eigenvalues = low.values;
  out.coordinates = low.vectors;
}

}  // namespace motionmap::embed
