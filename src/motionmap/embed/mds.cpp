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
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/metrics.h"

namespace motionmap::embed {

namespace {

// Fixed, so that the summation order (and the result) does not depend on the thread count.
constexpr int kProductChunks = 16;
// Below this many frames a product is too quick to be worth starting threads for.
constexpr int kParallelFrames = 1500;

// One column of the lower triangle in one pass: p[i] += uj·t[i]² for i < m, and the return value
// Σ t[i]²·u[i], summed exactly as Eigen sums (t.square() * u).sum() with 2-double packets (its
// vectorised reduction: two packet accumulators over blocks of 4, a last packet, the packet's two
// lanes, then the odd element), so the products, and so the maps, stay those of the two-pass
// Eigen expression it replaces while T is read once, not twice.
double column_product(const double* t, const double* u, double uj, double* p, Eigen::Index m) {
  if (m < 2) {
    const double s = t[0] * t[0];
    p[0] += uj * s;
    return s * u[0];
  }
  const Eigen::Index packets = m & ~Eigen::Index(1), blocks = m & ~Eigen::Index(3);
  double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
  Eigen::Index i = 0;
  if (packets > 2) {
    // The first block starts the accumulators (Eigen loads it; 0 + x would equal x anyway).
    const double s0 = t[0] * t[0], s1 = t[1] * t[1], s2 = t[2] * t[2], s3 = t[3] * t[3];
    p[0] += uj * s0;
    p[1] += uj * s1;
    p[2] += uj * s2;
    p[3] += uj * s3;
    a0 = s0 * u[0];
    a1 = s1 * u[1];
    a2 = s2 * u[2];
    a3 = s3 * u[3];
    for (i = 4; i < blocks; i += 4) {
      const double s0 = t[i] * t[i], s1 = t[i + 1] * t[i + 1], s2 = t[i + 2] * t[i + 2],
                   s3 = t[i + 3] * t[i + 3];
      p[i] += uj * s0;
      p[i + 1] += uj * s1;
      p[i + 2] += uj * s2;
      p[i + 3] += uj * s3;
      a0 += s0 * u[i];
      a1 += s1 * u[i + 1];
      a2 += s2 * u[i + 2];
      a3 += s3 * u[i + 3];
    }
    a0 += a2;
    a1 += a3;
  }
  if (packets > i) {  // the last whole packet (or, for m < 4, the only one)
    const double s0 = t[i] * t[i], s1 = t[i + 1] * t[i + 1];
    p[i] += uj * s0;
    p[i + 1] += uj * s1;
    a0 = i == 0 ? s0 * u[i] : a0 + s0 * u[i];
    a1 = i == 0 ? s1 * u[i + 1] : a1 + s1 * u[i + 1];
    i += 2;
  }
  double sum = a0 + a1;
  if (i < m) {
    const double s = t[i] * t[i];
    p[i] += uj * s;
    sum += s * u[i];
  }
  return sum;
}

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
            part[j] += column_product(m_T.col(j).data() + j + 1, m_u.data() + j + 1, m_u[j],
                                      part.data() + j + 1, m);
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

// Σⱼ T_xj² for every frame x over the lower triangle (j ≠ x), each summed from 0 in one fixed
// order: row x left to right, then column x top to bottom (the order of a serial pass over the
// columns, which this replaces). In two parallel passes: the rows' parts a block of rows at a
// time, column by column (contiguous runs, every row's sum still left to right), then the
// columns' parts kColumns columns at a time, whose sums (each a chain of dependent additions)
// advance together.
Eigen::VectorXd squared_sums(const Eigen::MatrixXd& T) {
  constexpr Eigen::Index kRows = 256, kColumns = 8;
  const Eigen::Index n = T.rows();
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(n);
  double* acc = sums.data();
  const bool serial = n < kParallelFrames;
  parallel_chunks(
      static_cast<int>((n + kRows - 1) / kRows),
      [&](int b, int) {
        const Eigen::Index r0 = b * kRows, r1 = std::min(n, r0 + kRows);
        for (Eigen::Index j = 0; j + 1 < r1; ++j) {
          const double* t = T.col(j).data();
          for (Eigen::Index i = std::max(r0, j + 1); i < r1; ++i) acc[i] += t[i] * t[i];
        }
      },
      {}, serial);
  parallel_chunks(
      static_cast<int>((n + kColumns - 1) / kColumns),
      [&](int b, int) {
        const Eigen::Index c0 = b * kColumns, c1 = std::min(n, c0 + kColumns);
        double s[kColumns];
        const double* t[kColumns];
        for (Eigen::Index c = c0; c < c1; ++c) {
          s[c - c0] = acc[c];
          t[c - c0] = T.col(c).data();
          for (Eigen::Index i = c + 1; i < c1; ++i) s[c - c0] += t[c - c0][i] * t[c - c0][i];
        }
        if (c1 - c0 == kColumns) {
          for (Eigen::Index i = c1; i < n; ++i) {
            for (Eigen::Index q = 0; q < kColumns; ++q) s[q] += t[q][i] * t[q][i];
          }
        } else {
          for (Eigen::Index q = 0; q < c1 - c0; ++q) {
            for (Eigen::Index i = c1; i < n; ++i) s[q] += t[q][i] * t[q][i];
          }
        }
        for (Eigen::Index c = c0; c < c1; ++c) acc[c] = s[c - c0];
      },
      {}, serial);
  return sums;
}

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
  all.mean_squared = squared_sums(T);
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
