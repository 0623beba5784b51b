#include "motionmap/embed/graph.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "motionmap/embed/parallel.h"
#include "motionmap/embed/progress.h"

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
  /// Empties the heap (entries left when a search stops early).
  void clear() {
    for (const auto& item : m_heap) m_pos[item.second] = -1;
    m_heap.clear();
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

constexpr int kSourcesPerChunk = 8;

}  // namespace

Eigen::MatrixXd shortest_paths(const Graph& graph, Progress* progress) {
  const int n = graph.frames();
  Eigen::MatrixXd out(n, n);
  const int chunks = (n + kSourcesPerChunk - 1) / kSourcesPerChunk;
  std::vector<IndexedHeap> heaps;  // one per thread; empty again after every source
  for (int t = 0; t < worker_count(chunks); ++t) heaps.emplace_back(n);

  // Only the lower triangle is computed: Dijkstra from s stops as soon as every frame t > s is
  // settled (distances are symmetric, so the rest of column s is row s of earlier columns);
  // this saves a quarter to a half of the work. The upper triangle is mirrored afterwards.
  auto run_source = [&](IndexedHeap& heap, int s) {
    double* dist = out.col(s).data();
    std::fill(dist, dist + n, std::numeric_limits<double>::infinity());
    dist[s] = 0.0;
    heap.push(s, 0.0);
    const int* offsets = graph.offsets.data();
    const int* targets = graph.targets.data();
    const double* weights = graph.weights.data();
    int remaining = n - 1 - s;
    while (!heap.empty() && remaining > 0) {
      const int u = heap.pop();
      if (u > s) --remaining;
      const double du = dist[u];
      for (int e = offsets[u]; e < offsets[u + 1]; ++e) {
        const int v = targets[e];
        const double nd = du + weights[e];
        if (nd < dist[v]) {
          const bool queued = heap.contains(v);
          dist[v] = nd;
          if (queued) {
            heap.decrease(v, nd);
          } else {
            heap.push(v, nd);
          }
        }
      }
    }
    heap.clear();
  };

  parallel_chunks(
      chunks,
      [&](int c, int worker) {
        const int end = std::min(n, (c + 1) * kSourcesPerChunk);
        for (int s = c * kSourcesPerChunk; s < end; ++s) run_source(heaps[worker], s);
      },
      [&](int done) {
        if (progress) progress->update(double(done) / chunks);
      });
  // Mirror the lower triangle into the upper one, in cache-sized tiles.
  constexpr int kTile = 64;
  const int tiles = (n + kTile - 1) / kTile;
  parallel_chunks(tiles, [&](int t, int) {
    const int c0 = t * kTile, w = std::min(kTile, n - c0);
    for (int r0 = c0; r0 < n; r0 += kTile) {
      const int h = std::min(kTile, n - r0);
      for (int c = c0; c < c0 + w; ++c) {
        for (int r = std::max(r0, c + 1); r < r0 + h; ++r) out(c, r) = out(r, c);
      }
    }
  });
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
