#include "motionmap/embed/graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/progress.h"

namespace motionmap::embed {

namespace {

// Binary min-heap of (distance, frame) with decrease-key; pos[frame] is the frame's slot or −1.
class IndexedHeap {
 public:
  explicit IndexedHeap(int n) : m_pos(std::size_t(n), -1) { m_heap.reserve(std::size_t(n)); }

  bool empty() const { return m_heap.empty(); }
  bool contains(int v) const { return m_pos[v] >= 0; }

  void push(int v, double key) {
    m_heap.push_back({key, v});
    sift_up(static_cast<int>(m_heap.size()) - 1);
  }
  void decrease(int v, double key) {
    m_heap[m_pos[v]].first = key;
    sift_up(m_pos[v]);
  }
  int pop() {
    const int top = m_heap.front().second;
    m_pos[top] = -1;
    const auto last = m_heap.back();
    m_heap.pop_back();
    if (!m_heap.empty()) {
      m_heap.front() = last;
      sift_down(0);
    }
    return top;
  }

 private:
  void place(int i, const std::pair<double, int>& item) {
    m_heap[i] = item;
    m_pos[item.second] = i;
  }
  void sift_up(int i) {
    const auto item = m_heap[i];
    while (i > 0) {
      const int parent = (i - 1) / 2;
      if (!(item.first < m_heap[parent].first)) break;
      place(i, m_heap[parent]);
      i = parent;
    }
    place(i, item);
  }
  void sift_down(int i) {
    const auto item = m_heap[i];
    const int size = static_cast<int>(m_heap.size());
    while (true) {
      int child = 2 * i + 1;
      if (child >= size) break;
      if (child + 1 < size && m_heap[child + 1].first < m_heap[child].first) ++child;
      if (!(m_heap[child].first < item.first)) break;
      place(i, m_heap[child]);
      i = child;
    }
    place(i, item);
  }

  std::vector<std::pair<double, int>> m_heap;
  std::vector<int> m_pos;
};

// Sources searched at once by shortest_paths. More lanes mean fewer searches but more work per
// edge, and more re-queued frames when the block's sources are far apart (fast motion): 8 was
// the best of 4, 8, 16 and 32 on CMU 64 (816 frames) and the sample swing (2000, 8000 frames).
constexpr int kLanes = 8;

// Shortest paths from `kLanes` consecutive sources at once (see shortest_paths below): columns
// s0 … s0 + kLanes − 1 of `out`, on and below the diagonal. `dist` is #frames·kLanes scratch:
// frame v's tentative distances from the block's sources at [v·kLanes, v·kLanes + kLanes).
void block_paths(const Graph& graph, int s0, IndexedHeap& heap, std::vector<double>& dist,
                 Eigen::MatrixXd& out) {
  const int n = graph.frames();
  const int lanes = std::min(kLanes, n - s0);
  const double inf = std::numeric_limits<double>::infinity();
  dist.assign(std::size_t(n) * kLanes, inf);
  for (int l = 0; l < lanes; ++l) {
    dist[std::size_t(s0 + l) * kLanes + l] = 0.0;
    heap.push(s0 + l, 0.0);
  }
  const int* offsets = graph.offsets.data();
  const int* targets = graph.targets.data();
  const double* weights = graph.weights.data();
  double du[kLanes];
  while (!heap.empty()) {
    const int u = heap.pop();
    std::copy_n(dist.data() + std::size_t(u) * kLanes, kLanes, du);
    for (int e = offsets[u]; e < offsets[u + 1]; ++e) {
      const double w = weights[e];
      double* dv = dist.data() + std::size_t(targets[e]) * kLanes;
      // Most edges improve nothing: test all lanes first (branch-free, vectorised), update only
      // when one improves.
      long improves = 0;
      for (int l = 0; l < kLanes; ++l) improves |= du[l] + w < dv[l] ? -1L : 0L;
      if (improves == 0) continue;
      double key = inf;
      for (int l = 0; l < kLanes; ++l) {
        dv[l] = std::min(dv[l], du[l] + w);
        key = std::min(key, dv[l]);
      }
      const int v = targets[e];
      if (heap.contains(v)) {
        heap.decrease(v, key);
      } else {
        heap.push(v, key);
      }
    }
  }
  for (int l = 0; l < lanes; ++l) {
    double* col = out.col(s0 + l).data();
    for (int v = s0 + l; v < n; ++v) col[v] = dist[std::size_t(v) * kLanes + l];
  }
}

}  // namespace

// A label-correcting search from a block of consecutive sources at once (kLanes of them): every
// frame holds one tentative distance per source; a frame is queued, keyed by its smallest one,
// whenever one of them decreases, and relaxes its edges for all sources together when popped.
// When the queue is empty every edge satisfies d[v] ≤ d[u] + w for every source, so the
// distances are exact; each is the sum of the edge lengths along its path in path order, the
// same floating-point sums as Dijkstra's. Consecutive frames are close, so their shortest-path
// trees are alike and a frame is popped about once per block (measured on mocap k-NN graphs: 1
// to 2 times): a block costs about one Dijkstra, and the lane loops vectorise. Only the lower
// triangle is kept (column s from source s); the upper one is mirrored from it.
Eigen::MatrixXd shortest_paths(const Graph& graph, const Control& control) {
  const int n = graph.frames();
  Eigen::MatrixXd out(n, n);
  const int chunks = (n + kLanes - 1) / kLanes;
  const int workers = worker_count(chunks);
  std::vector<IndexedHeap> heaps;  // per thread; empty again after every block
  for (int t = 0; t < workers; ++t) heaps.emplace_back(n);
  std::vector<std::vector<double>> scratch(static_cast<std::size_t>(workers));
  parallel_chunks(
      chunks,
      [&](int c, int worker) {
        block_paths(graph, c * kLanes, heaps[worker], scratch[worker], out);
      },
      [&](int done) { control.update(double(done) / chunks); });
  // Mirror the lower triangle into the upper one, in cache-sized tiles, polling for cancellation
  // between tiles: n² copies, which would otherwise run to the end after a Cancel.
  constexpr int kTile = 64;
  const int tiles = (n + kTile - 1) / kTile;
  parallel_chunks(
      tiles,
      [&](int t, int) {
        const int c0 = t * kTile, w = std::min(kTile, n - c0);
        for (int r0 = c0; r0 < n; r0 += kTile) {
          const int h = std::min(kTile, n - r0);
          for (int c = c0; c < c0 + w; ++c) {
            for (int r = std::max(r0, c + 1); r < r0 + h; ++r) out(c, r) = out(r, c);
          }
        }
      },
      [&](int) { control.check(); });
  return out;
}

Eigen::SparseMatrix<double> normalized_laplacian(const Graph& weighted, Eigen::VectorXd& degrees) {
  const int n = weighted.frames();
  degrees.setZero(n);
  for (int i = 0; i < n; ++i) {
    for (int e = weighted.offsets[i]; e < weighted.offsets[i + 1]; ++e) {
      degrees[i] += weighted.weights[e];
    }
  }
  const Eigen::VectorXd inv_sqrt = degrees.array().sqrt().inverse();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(weighted.targets.size() + std::size_t(n));
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 1.0);
    for (int e = weighted.offsets[i]; e < weighted.offsets[i + 1]; ++e) {
      const int j = weighted.targets[e];
      entries.emplace_back(i, j, -weighted.weights[e] * inv_sqrt[i] * inv_sqrt[j]);
    }
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(entries.begin(), entries.end());
  return L;
}

}  // namespace motionmap::embed
