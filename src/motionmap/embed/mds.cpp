// Classical (Torgerson) MDS: B = −½·J·D²·J is the Gram matrix of centred points whose distances
// are D when D is Euclidean; its top eigenpairs give coordinates U·√λ. Shared with Isomap.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/metrics.h"

namespace motionmap::embed {

namespace {

// Fixed, so that the summation order (and the result) does not depend on the thread count.
constexpr int kProductChunks = 16;
// Below this many frames a product is too quick to be worth starting threads for.
constexpr int kParallelFrames = 1500;

// y = B·x = −½·J·S·J·x with S_ij = T_ij² read from T's lower triangle, without forming S or B:
// one pass over the lower triangle per product (the product is memory-bound, squaring on the
// fly is free), split into column chunks of equal area with a partial sum each.
class DoubleCentredProduct {
 public:
  DoubleCentredProduct(const Eigen::MatrixXd& T, const Control& control)
      : m_T(T), m_n(T.rows()), m_control(control), m_u(m_n) {
    const double total = 0.5 * double(m_n) * double(m_n - 1);
    m_bounds.push_back(0);
    double area = 0.0;
    Eigen::Index j = 0;
    for (int c = 1; c < kProductChunks; ++c) {
      while (j < m_n && area < total * c / kProductChunks) area += double(m_n - 1 - j++);
      m_bounds.push_back(j);
    }
    m_bounds.push_back(m_n);
    m_partial.assign(kProductChunks, Eigen::VectorXd(m_n));
  }

  void operator()(const double* x, double* y) {
    m_control.check();
    const Eigen::Map<const Eigen::VectorXd> xv(x, m_n);
    m_u = xv.array() - xv.mean();
    parallel_chunks(
        kProductChunks,
        [&](int c, int) {
          Eigen::VectorXd& part = m_partial[c];
          part.setZero();
          for (Eigen::Index j = m_bounds[c]; j < m_bounds[c + 1]; ++j) {
            const Eigen::Index m = m_n - 1 - j;
            if (m == 0) continue;
            const auto s = m_T.col(j).tail(m).array().square();
            part.tail(m).array() += m_u[j] * s;
            part[j] += (s * m_u.tail(m).array()).sum();
          }
        },
        {}, m_n < kParallelFrames);
    Eigen::Map<Eigen::VectorXd> yv(y, m_n);
    yv = m_partial[0];
    for (int c = 1; c < kProductChunks; ++c) yv += m_partial[c];
    yv = -0.5 * (yv.array() - yv.mean());
  }

 private:
  const Eigen::MatrixXd& m_T;
  Eigen::Index m_n;
  Control m_control;
  std::vector<Eigen::Index> m_bounds;
  std::vector<Eigen::VectorXd> m_partial;
  Eigen::VectorXd m_u;
};

}  // namespace

void classical_mds(const Eigen::MatrixXd& T, const EmbedOptions& options, Embedding& out,
                   Progress& progress, double begin, double end) {
  const std::string_view what = method_name(options.method);
  const int dims = options.dimensions;
  const Eigen::Index n = T.rows();
  progress.stage("eigen", begin, begin + 0.9 * (end - begin));
  EigenPairs top;
  if (n <= kDenseEigenLimit) {
    // Small: form B and take the whole spectrum, which also counts the negative eigenvalues.
    Eigen::MatrixXd S = T.selfadjointView<Eigen::Lower>();
    S = S.array().square().matrix();
    const Eigen::VectorXd r = S.rowwise().mean();
    const double mean = r.mean();
    const Eigen::MatrixXd B =
        (-0.5 * (((S.colwise() - r).rowwise() - r.transpose()).array() + mean)).matrix();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(B);
    if (solver.info() != Eigen::Success) {
      throw NumericalError(std::string(what) + ": the dense eigen solver did not converge");
    }
    const Eigen::VectorXd& all = solver.eigenvalues();  // ascending
    top.values = all.reverse().head(dims);
    top.vectors = solver.eigenvectors().rowwise().reverse().leftCols(dims);
    const double largest = std::max(all[n - 1], 0.0);
    out.negative.count = static_cast<int>((all.array() < -1e-9 * largest).count());
    out.negative.most_negative = *out.negative.count > 0 ? all[0] : 0.0;
  } else {
    DoubleCentredProduct op(T, progress.control());
    const Product product = [&op](const double* x, double* y) { op(x, y); };
    // Every product reads all of T, so products are what costs: Spectra checks convergence once
    // per restart, and on MDS spectra (a few dominant eigenvalues) 2 eigenpairs converge to
    // 1e-10 after ~10 products, so a 10-vector subspace (not the default 20) halves the work.
    top = largest_eigenpairs(n, product, dims, what, kEigenTolerance, std::max(10, 2 * dims + 4));
    // The most negative eigenvalue, estimated for free by the solve's smallest Ritz value: never
    // below λ_min, so the report never overstates how non-Euclidean D is.
    out.negative.most_negative = std::min(0.0, top.smallest_ritz);
    if (out.negative.most_negative > -1e-9 * std::max(top.values[0], 0.0)) {
      out.negative.most_negative = 0.0;
    }
  }
  const double largest = std::max(top.values[0], 0.0);
  out.negative.relative = largest > 0.0 && out.negative.most_negative < 0.0
                              ? -out.negative.most_negative / largest
                              : 0.0;
  out.eigenvalues = top.values;
  out.coordinates = top.vectors * top.values.cwiseMax(0.0).cwiseSqrt().asDiagonal();
  for (int a = 0; a < dims; ++a) {
    if (!(top.values[a] > 1e-12 * largest)) {
      out.warnings.push_back("axis " + std::to_string(a + 1) + " has eigenvalue " +
                             format_number(top.values[a], 3) + " ≤ 0, so it is flat (all 0): the " +
                             "distances have fewer than " + std::to_string(dims) +
                             " positive dimensions");
    }
  }
  // What placing frames needs (placement.h): every frame a landmark, P = (Y ÷ λ)ᵀ, μ = the
  // column means of T².
  LandmarkFit all;
  all.frames.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) all.frames[i] = static_cast<int>(i);
  all.projection.resize(dims, n);
  for (int a = 0; a < dims; ++a) {
    all.projection.row(a) = top.values[a] > 0.0
                                ? (out.coordinates.col(a) / top.values[a]).transpose().eval()
                                : Eigen::RowVectorXd::Zero(n).eval();
  }
  all.mean_squared = Eigen::VectorXd::Zero(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j + 1; i < n; ++i) {
      const double s = T(i, j) * T(i, j);
      all.mean_squared[i] += s;
      all.mean_squared[j] += s;
    }
  }
  all.mean_squared /= double(n);
  all.offset = Eigen::VectorXd::Zero(dims);
  out.landmarks = std::move(all);
  progress.stage("stress", begin + 0.9 * (end - begin), end);
  out.stress = normalized_stress(T, out.coordinates, progress.control());
}

void run_mds(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
             Progress& progress) {
  classical_mds(D, options, out, progress, 0.02, 1.0);
}

}  // namespace motionmap::embed
