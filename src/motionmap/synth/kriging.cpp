#include "motionmap/synth/detail/kriging.h"

#include <algorithm>
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>

#include <Eigen/LU>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"

namespace motionmap::synth::detail {

namespace {

// Columns of the global matrix filled per chunk (a few MB).
constexpr int kFillColumns = 256;
// Local systems set up between two progress reports / cancellation polls.
constexpr int kLocalPollEvery = 64;

}  // namespace

GlobalKriging::GlobalKriging(std::span<const Eigen::Vector2d> points, const Control& control)
    : m_points(points.begin(), points.end()) {
  const int np = num_points();
  const Control fill = control.part(0.0, 0.01);
  const Control factor = control.part(0.01, 0.95);
  const Control condition = control.part(0.95, 1.0);

  // [A 1; 1ᵀ 0], column by column (each chunk writes its own columns).
  Eigen::MatrixXd a(np + 1, np + 1);
  const int chunks = (np + 1 + kFillColumns - 1) / kFillColumns;
  parallel_chunks(
      chunks,
      [&](int c, int) {
        const int b0 = c * kFillColumns, b1 = std::min(np + 1, b0 + kFillColumns);
        for (int b = b0; b < b1; ++b) {
          if (b == np) {
            a.col(np).head(np).setOnes();
            a(np, np) = 0.0;
            continue;
          }
          for (int r = 0; r < np; ++r) a(r, b) = (m_points[r] - m_points[b]).norm();
          a(np, b) = 1.0;
        }
      },
      [&](int done) { fill.update(static_cast<double>(done) / chunks); });

  // In place: the (N+1)² factors replace the matrix, no second copy.
  m_lu = BlockedLu(std::move(a), factor);
  const double rcond = m_lu.rcond(condition);
  if (!(rcond > 1e-15)) {
    throw NumericalError("the kriging system is singular (reciprocal condition " +
                         format_number(rcond) + "); use the local mode");
  }
}

Eigen::MatrixXd GlobalKriging::solve(std::span<const Eigen::Vector2d> queries,
                                     std::span<double> variance) const {
  const int np = num_points();
  const auto m = static_cast<Eigen::Index>(queries.size());
  Eigen::MatrixXd rhs(np + 1, m);
  for (Eigen::Index c = 0; c < m; ++c) {
    const Eigen::Vector2d& p = queries[static_cast<std::size_t>(c)];
    for (int r = 0; r < np; ++r) rhs(r, c) = (m_points[r] - p).norm();
    rhs(np, c) = 1.0;
  }
  Eigen::MatrixXd x = rhs;
  m_lu.solve_in_place(x);
  for (Eigen::Index c = 0; c < m; ++c) {
    variance[static_cast<std::size_t>(c)] = x.col(c).head(np).dot(rhs.col(c).head(np)) + x(np, c);
  }
  return x;
}

struct LocalKriging::Lazy {
  mutable std::mutex mutex;
  // Node-based: a system's address stays valid while others are added.
  mutable std::unordered_map<int, System> systems;
};

LocalKriging::LocalKriging(const MapIndex& index, int neighbors, double separation,
                           const Control& control, bool lazy)
    : m_neighbors(neighbors), m_separation(separation) {
  const int np = index.num_points();
  if (lazy) {
    control.check();
    m_lazy = std::make_unique<Lazy>();
    m_max_hood = std::min(neighbors, np);
    return;
  }
  m_hood_start.push_back(0);
  m_inverse_start.push_back(0);
  for (int j = 0; j < np; ++j) {
    if (j % kLocalPollEvery == 0) control.update(static_cast<double>(j) / np);
    const System sys = build(index, j);
    m_max_hood = std::max(m_max_hood, static_cast<int>(sys.hood.size()));
    m_hood.insert(m_hood.end(), sys.hood.begin(), sys.hood.end());
    m_hood_start.push_back(static_cast<int>(m_hood.size()));
    m_inverses.insert(m_inverses.end(), sys.inverse.begin(), sys.inverse.end());
    m_inverse_start.push_back(m_inverses.size());
  }
  control.finish();
}

LocalKriging::~LocalKriging() = default;
LocalKriging::LocalKriging(LocalKriging&&) noexcept = default;
LocalKriging& LocalKriging::operator=(LocalKriging&&) noexcept = default;

int LocalKriging::num_built() const {
  if (!m_lazy) return static_cast<int>(m_hood_start.size()) - 1;
  const std::lock_guard lock(m_lazy->mutex);
  return static_cast<int>(m_lazy->systems.size());
}

LocalKriging::System LocalKriging::build(const MapIndex& index, int j) const {
  const int np = index.num_points();
  const std::span<const Eigen::Vector2d> points = index.points();
  const int K = std::min(m_neighbors, np);
  const double separation = m_separation;
  std::vector<std::uint32_t> idx;
  std::vector<double> dist;
  std::vector<int> chosen;
  const Eigen::Vector2d& cj = points[j];
  // Greedy: nearest first, skipping candidates closer than `separation` to one already chosen;
  // widen the candidate list while too few are far enough apart.
  int candidates = std::min(np, 4 * K);
  for (;;) {
    idx.resize(static_cast<std::size_t>(candidates));
    dist.resize(static_cast<std::size_t>(candidates));
    const int found = index.nearest(cj, candidates, idx.data(), dist.data());
    chosen.assign(1, j);
    for (int c = 0; c < found && static_cast<int>(chosen.size()) < K; ++c) {
      const int cand = static_cast<int>(idx[c]);
      if (cand == j) continue;
      const Eigen::Vector2d& pc = points[cand];
      bool apart = true;
      for (int s : chosen) apart = apart && (pc - points[s]).norm() >= separation;
      if (apart) chosen.push_back(cand);
    }
    // Give up widening at 64·K candidates (a crowd of samples closer than the separation):
    // a smaller system is still exact at its own sample, and set-up stays O(N·K log N).
    if (static_cast<int>(chosen.size()) == K || candidates == np || candidates >= 64 * K) break;
    candidates = static_cast<int>(std::min<long long>(np, 4LL * candidates));
  }
  const auto k = static_cast<Eigen::Index>(chosen.size());
  Eigen::MatrixXd M(k + 1, k + 1);
  for (Eigen::Index a = 0; a < k; ++a) {
    for (Eigen::Index b = 0; b < k; ++b) M(a, b) = (points[chosen[a]] - points[chosen[b]]).norm();
    M(a, k) = M(k, a) = 1.0;
  }
  M(k, k) = 0.0;
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(M);
  if (!(lu.rcond() > 1e-13)) {
    throw NumericalError("local kriging system of map point " + std::to_string(j) +
                         " is singular (reciprocal condition " + format_number(lu.rcond()) + ")");
  }
  const Eigen::MatrixXd inv = lu.inverse();
  System sys;
  sys.hood = std::move(chosen);
  sys.inverse.assign(inv.data(), inv.data() + inv.size());
  return sys;
}

double LocalKriging::predict(const MapIndex& index, int j, const Eigen::Vector2d& p, double scale,
                             std::vector<std::pair<int, double>>& out, std::span<double> rhs,
                             std::span<double> sol) const {
  const std::span<const Eigen::Vector2d> points = index.points();
  const int* hood = nullptr;
  const double* inverse = nullptr;
  int k = 0;
  if (m_lazy) {
    const System* sys = nullptr;
    {
      const std::lock_guard lock(m_lazy->mutex);
      if (const auto hit = m_lazy->systems.find(j); hit != m_lazy->systems.end())
        sys = &hit->second;
    }
    if (!sys) {
      System built = build(index, j);  // outside the lock; a racing thread builds the same
      const std::lock_guard lock(m_lazy->mutex);
      sys = &m_lazy->systems.emplace(j, std::move(built)).first->second;
    }
    hood = sys->hood.data();
    inverse = sys->inverse.data();
    k = static_cast<int>(sys->hood.size());
  } else {
    const auto uj = static_cast<std::size_t>(j);
    hood = m_hood.data() + m_hood_start[uj];
    inverse = m_inverses.data() + m_inverse_start[uj];
    k = m_hood_start[uj + 1] - m_hood_start[uj];
  }
  for (int a = 0; a < k; ++a) rhs[a] = (points[hood[a]] - p).norm();
  rhs[k] = 1.0;
  const Eigen::Map<const Eigen::MatrixXd> inv(inverse, k + 1, k + 1);
  Eigen::Map<Eigen::VectorXd> x(sol.data(), k + 1);
  x.noalias() = inv * Eigen::Map<const Eigen::VectorXd>(rhs.data(), k + 1);
  double var = x[k];
  for (int a = 0; a < k; ++a) {
    var += x[a] * rhs[a];
    out.emplace_back(hood[a], scale * x[a]);
  }
  return var;
}

}  // namespace motionmap::synth::detail
