#include "motionmap/embed/detail/sparse_ldlt.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <string>
#include <utility>

#include <Eigen/OrderingMethods>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"

namespace motionmap::embed {

namespace {

// Pivot columns eliminated per dense panel before the trailing update.
constexpr int kPanel = 64;
// Fronts with at least this many rows left after a panel split the trailing update into
// kProductBlocks column blocks over the thread pool (only the fronts above the parallel subtrees).
constexpr int kParallelRows = 512;
constexpr int kProductBlocks = 16;
// The subtrees run in parallel are split until none holds more than this share of the work.
constexpr double kTaskShare = 1.0 / 16.0;

// The first w columns of the symmetric front F (lower triangle) eliminated: F = [F₁₁ F₂₁ᵀ; F₂₁ F₂₂]
// becomes L₁₁ (unit lower, strictly below the diagonal), L₂₁ below it, and F₂₂ − L₂₁·D·L₂₁ᵀ (the
// update matrix, lower triangle) at the bottom right; D in d. Panels of kPanel columns, each
// finished column by column, then one product for everything to its right. With `control` (on
// the calling thread only), polled before every panel.
void partial_ldlt(Eigen::MatrixXd& F, int w, double* d, bool parallel_products,
                  const Control* control) {
  const int m = static_cast<int>(F.rows());
  Eigen::MatrixXd W;
  for (int k0 = 0; k0 < w; k0 += kPanel) {
    const int kb = std::min(kPanel, w - k0);
    if (control) control->check();
    for (int j = k0; j < k0 + kb; ++j) {
      const double pivot = F(j, j);
      if (pivot == 0.0 || !std::isfinite(pivot)) {
        throw NumericalError("pivot " + format_number(pivot, 6));
      }
      d[j] = pivot;
      // The panel's later columns: F(i, c) −= F(i, j)·F(c, j) ÷ pivot for i ≥ c.
      for (int c = j + 1; c < k0 + kb; ++c) {
        const double f = F(c, j) / pivot;
        F.col(c).tail(m - c) -= f * F.col(j).tail(m - c);
      }
      F.col(j).tail(m - j - 1) /= pivot;
    }
    const int r0 = k0 + kb, rest = m - r0;
    if (rest == 0) continue;
    const auto Lp = F.block(r0, k0, rest, kb);
    W = Lp * Eigen::Map<const Eigen::VectorXd>(d + k0, kb).asDiagonal();
    if (!parallel_products || rest < kParallelRows) {
      F.bottomRightCorner(rest, rest).triangularView<Eigen::Lower>() -= Lp * W.transpose();
      continue;
    }
    // Column blocks [c0, c1) of the trailing part: the triangle on the diagonal, the rectangle
    // below it; a fixed split, so the sums are those of any thread count.
    const int width = (rest + kProductBlocks - 1) / kProductBlocks;
    parallel_chunks(kProductBlocks, [&](int b, int) {
      const int c0 = std::min(rest, b * width), c1 = std::min(rest, c0 + width);
      if (c0 == c1) return;
      F.block(r0 + c0, r0 + c0, c1 - c0, c1 - c0).triangularView<Eigen::Lower>() -=
          Lp.middleRows(c0, c1 - c0) * W.middleRows(c0, c1 - c0).transpose();
      if (c1 < rest) {
        F.block(r0 + c1, r0 + c0, rest - c1, c1 - c0).noalias() -=
            Lp.bottomRows(rest - c1) * W.middleRows(c0, c1 - c0).transpose();
      }
    });
  }
}

}  // namespace

SupernodalLdlt::SupernodalLdlt(const Eigen::SparseMatrix<double>& A, const Control& control) {
  const int n = static_cast<int>(A.rows());
  m_n = n;
  // 1. The ordering of SimplicialLDLT: approximate minimum degree on the symmetric pattern
  //    (Eigen's, postordered); the permuted lower triangle, and its transpose (the rows above).
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  {
    const Eigen::SparseMatrix<double> C = A.selfadjointView<Eigen::Lower>();
    Eigen::AMDOrdering<int> amd;
    amd(C, inverse);
  }
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm = inverse.inverse();
  m_perm.assign(perm.indices().data(), perm.indices().data() + n);
  Eigen::SparseMatrix<double> lower(n, n);
  lower.selfadjointView<Eigen::Lower>() = A.selfadjointView<Eigen::Lower>().twistedBy(perm);
  const Eigen::SparseMatrix<double> upper = lower.transpose();
  control.check();

  // 2. The elimination tree (Liu's algorithm with path compression).
  std::vector<int> parent(std::size_t(n), -1), ancestor(std::size_t(n), -1);
  for (int j = 0; j < n; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(upper, j); it; ++it) {
      for (int i = static_cast<int>(it.row()); i != -1 && i < j;) {
        const int next = ancestor[i];
        ancestor[i] = j;
        if (next == -1) parent[i] = j;
        i = next;
      }
    }
  }
  std::vector<int> child_head(std::size_t(n), -1), child_next(std::size_t(n), -1);
  for (int j = n - 1; j >= 0; --j) {
    if (parent[j] >= 0) {
      child_next[j] = child_head[parent[j]];
      child_head[parent[j]] = j;
    }
  }

  // 3. Each column's structure below the diagonal: its own rows below j and its children's
  //    structures but j (unsorted, one flat array).
  std::vector<std::int64_t> start(std::size_t(n) + 1, 0);
  std::vector<int> flat;
  flat.reserve(std::size_t(lower.nonZeros()) * 2);
  std::vector<int> mark(std::size_t(n), -1);
  for (int j = 0; j < n; ++j) {
    if (j % 4096 == 0) control.check();
    start[j] = static_cast<std::int64_t>(flat.size());
    mark[j] = j;
    for (Eigen::SparseMatrix<double>::InnerIterator it(lower, j); it; ++it) {
      const int i = static_cast<int>(it.row());
      if (i > j && mark[i] != j) {
        mark[i] = j;
        flat.push_back(i);
      }
    }
    for (int c = child_head[j]; c != -1; c = child_next[c]) {
      for (std::int64_t e = start[c]; e < start[c + 1]; ++e) {
        const int i = flat[std::size_t(e)];
        if (mark[i] != j) {
          mark[i] = j;
          flat.push_back(i);
        }
      }
    }
  }
  start[n] = static_cast<std::int64_t>(flat.size());
  m_entries = start[n];
  auto count = [&](int j) { return start[j + 1] - start[j]; };

  // 4. Supernodes: runs of columns where each is its predecessor's parent, with one entry fewer
  //    below (so the same rows below the run); their rows from the run's first column.
  std::vector<int> node_of(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    if (!(j > 0 && parent[j - 1] == j && count(j - 1) == count(j) + 1)) {
      m_nodes.emplace_back();
      m_nodes.back().first = j;
    }
    m_nodes.back().last = j + 1;
    node_of[j] = static_cast<int>(m_nodes.size()) - 1;
  }
  const int S = static_cast<int>(m_nodes.size());
  std::vector<std::vector<int>> children(static_cast<std::size_t>(S));
  for (int s = 0; s < S; ++s) {
    Node& node = m_nodes[s];
    node.rows.reserve(std::size_t(count(node.first)) + 1);
    node.rows.push_back(node.first);
    node.rows.insert(node.rows.end(), flat.begin() + start[node.first],
                     flat.begin() + start[node.first + 1]);
    std::sort(node.rows.begin() + 1, node.rows.end());
    const int p = parent[node.last - 1];
    node.parent = p < 0 ? -1 : node_of[p];
    if (node.parent >= 0) children[node.parent].push_back(s);
  }
  flat = std::vector<int>();
  control.check();

  // 5. The numbers. The tree is cut into subtrees of at most kTaskShare of the work each, run in
  //    parallel (each in column order: children first); the nodes above them run after, in
  //    column order, their big products split over the pool.
  std::vector<double> work(static_cast<std::size_t>(S), 0.0);  // of the subtree
  for (int s = 0; s < S; ++s) {
    const double m = double(m_nodes[s].rows.size());
    work[s] += m * m * double(m_nodes[s].last - m_nodes[s].first);
    if (m_nodes[s].parent >= 0) work[m_nodes[s].parent] += work[s];
  }
  double total = 0.0;
  std::priority_queue<std::pair<double, int>> open;  // (work, root), largest first
  for (int s = 0; s < S; ++s) {
    if (m_nodes[s].parent < 0) {
      open.emplace(work[s], s);
      total += work[s];
    }
  }
  std::vector<char> top(static_cast<std::size_t>(S), 0);
  std::vector<int> roots;
  while (!open.empty()) {
    const auto [w, s] = open.top();
    open.pop();
    if (w > kTaskShare * total && !children[s].empty()) {
      top[s] = 1;
      for (int c : children[s]) open.emplace(work[c], c);
    } else {
      roots.push_back(s);
    }
  }
  std::sort(roots.begin(), roots.end(),
            [&](int a, int b) { return work[a] > work[b] || (work[a] == work[b] && a < b); });
  m_diag.assign(std::size_t(n), 0.0);
  std::vector<Eigen::MatrixXd> updates(static_cast<std::size_t>(S));
  std::vector<std::vector<int>> slots(static_cast<std::size_t>(worker_count()));
  auto run = [&](int s, int worker, bool parallel_products) {
    std::vector<int>& slot = slots[std::size_t(worker)];
    if (slot.empty()) slot.assign(std::size_t(n), -1);
    factorize_node(s, lower, children[s], updates, slot, parallel_products ? &control : nullptr);
  };
  const int tasks = static_cast<int>(roots.size());
  parallel_chunks(
      tasks,
      [&](int t, int worker) {
        // The subtree's nodes, ascending (a child's columns come before its parent's).
        std::vector<int> nodes{roots[t]};
        for (std::size_t a = 0; a < nodes.size(); ++a) {
          for (int c : children[nodes[a]]) nodes.push_back(c);
        }
        std::sort(nodes.begin(), nodes.end());
        for (int s : nodes) run(s, worker, false);
      },
      [&](int done) { control.update(0.9 * done / std::max(tasks, 1)); });
  for (int s = 0; s < S; ++s) {
    if (!top[s]) continue;
    control.check();
    run(s, 0, true);
  }
}

void SupernodalLdlt::factorize_node(int s, const Eigen::SparseMatrix<double>& lower,
                                    const std::vector<int>& children,
                                    std::vector<Eigen::MatrixXd>& updates, std::vector<int>& slot,
                                    const Control* control) {
  Node& node = m_nodes[s];
  const int m = static_cast<int>(node.rows.size()), w = node.last - node.first;
  for (int a = 0; a < m; ++a) slot[node.rows[a]] = a;
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(m, m);
  for (int j = node.first; j < node.last; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(lower, j); it; ++it) {
      F(slot[it.row()], j - node.first) += it.value();
    }
  }
  // The children's update matrices, added where their rows are (extend-add), then freed.
  for (int c : children) {
    const Node& child = m_nodes[c];
    const int cw = child.last - child.first;
    Eigen::MatrixXd& U = updates[c];
    const int um = static_cast<int>(U.rows());
    for (int b = 0; b < um; ++b) {
      const int col = slot[child.rows[cw + b]];
      for (int a = b; a < um; ++a) F(slot[child.rows[cw + a]], col) += U(a, b);
    }
    U = Eigen::MatrixXd();
  }
  try {
    partial_ldlt(F, w, m_diag.data() + node.first, control != nullptr, control);
  } catch (const NumericalError& e) {
    throw NumericalError(std::string("supernodal LDLT: ") + e.what() + " at column " +
                         std::to_string(node.first) + " of " + std::to_string(m_n));
  }
  node.L = F.leftCols(w);
  if (m > w) updates[s] = F.bottomRightCorner(m - w, m - w);
}

void SupernodalLdlt::solve(double* x) const {
  const Eigen::Index n = m_n;
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) y[m_perm[i]] = x[i];
  Eigen::VectorXd below;
  // L·z = y, node by node: the diagonal block, then the rows below.
  for (const Node& node : m_nodes) {
    const int m = static_cast<int>(node.rows.size()), w = node.last - node.first;
    auto ys = y.segment(node.first, w);
    node.L.topRows(w).triangularView<Eigen::UnitLower>().solveInPlace(ys);
    if (m > w) {
      below.noalias() = node.L.bottomRows(m - w) * ys;
      for (int a = 0; a < m - w; ++a) y[node.rows[w + a]] -= below[a];
    }
  }
  y.array() /= Eigen::Map<const Eigen::ArrayXd>(m_diag.data(), n);
  // Lᵀ·x = z, in reverse.
  for (auto it = m_nodes.rbegin(); it != m_nodes.rend(); ++it) {
    const Node& node = *it;
    const int m = static_cast<int>(node.rows.size()), w = node.last - node.first;
    auto ys = y.segment(node.first, w);
    if (m > w) {
      below.resize(m - w);
      for (int a = 0; a < m - w; ++a) below[a] = y[node.rows[w + a]];
      ys.noalias() -= node.L.bottomRows(m - w).transpose() * below;
    }
    node.L.topRows(w).triangularView<Eigen::UnitLower>().transpose().solveInPlace(ys);
  }
  for (Eigen::Index i = 0; i < n; ++i) x[i] = y[m_perm[i]];
}

}  // namespace motionmap::embed
