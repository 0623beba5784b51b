#include "motionmap/embed/neighbors.h"

#include <algorithm>
#include <limits>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/k_range.h"

namespace motionmap::embed {

namespace {
constexpr int kFramesPerChunk = 64;
}  // namespace

void k_nearest(const double* values, int n, int self, int k, int* index, double* nearest) {
  // A sorted array of the k best so far, ordered by (value, index), so the result does not
  // depend on the order candidates arrive in: of equal values the smaller index wins. Most
  // candidates are rejected by the first comparison with the current k-th.
  int size = 0;
  auto offer = [&](int j) {
    const double d = values[j];
    if (size == k && !(d < nearest[k - 1] || (d == nearest[k - 1] && j < index[k - 1]))) return;
    int p = size == k ? k - 1 : size++;
    while (p > 0 && (nearest[p - 1] > d || (nearest[p - 1] == d && index[p - 1] > j))) {
      nearest[p] = nearest[p - 1];
      index[p] = index[p - 1];
      --p;
    }
    nearest[p] = d;
    index[p] = j;
  };
  // The frames around `self` first: along a clip they are usually among the nearest, so the k-th
  // best drops at once. (In index order, a column of a clip's D falls towards `self`, and every
  // frame approaching it would be inserted, O(n·k).)
  const int lo = std::clamp(self - k, 0, n), hi = std::clamp(self + k + 1, lo, n);
  for (int j = lo; j < hi; ++j) {
    if (j != self) offer(j);
  }
  // Then the rest, skipping four candidates at a time while all are beyond the current k-th
  // (offer would reject each; the k-th only ever decreases): the same offers in the same order.
  auto scan = [&](int from, int to) {
    int j = from;
    while (j < to && size < k) offer(j++);
    for (; j + 4 <= to; j += 4) {
#if defined(__SSE2__)
      const __m128d kth = _mm_set1_pd(nearest[k - 1]);
      const int beyond = _mm_movemask_pd(_mm_cmpgt_pd(_mm_loadu_pd(values + j), kth)) &
                         _mm_movemask_pd(_mm_cmpgt_pd(_mm_loadu_pd(values + j + 2), kth));
      if (beyond == 3) continue;
#else
      const double kth = nearest[k - 1];
      if (values[j] > kth && values[j + 1] > kth && values[j + 2] > kth && values[j + 3] > kth) {
        continue;
      }
#endif
      for (int q = 0; q < 4; ++q) offer(j + q);
    }
    for (; j < to; ++j) offer(j);
  };
  scan(0, lo);
  scan(hi, n);
}

NeighborLists knn_from_distances(const Eigen::MatrixXd& D, int k, const Control& control) {
  const int n = static_cast<int>(D.rows());
  check_neighbor_count(k, max_neighbors(n), n, "frames");
  NeighborLists out;
  out.k = k;
  out.index.resize(std::size_t(n) * k);
  out.distance.resize(std::size_t(n) * k);

  auto select = [&](int i) {
    k_nearest(D.col(i).data(), n, i, k, out.index.data() + std::size_t(i) * k,
              out.distance.data() + std::size_t(i) * k);
  };
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  parallel_chunks(
      chunks,
      [&](int c, int) {
        const int end = std::min(n, (c + 1) * kFramesPerChunk);
        for (int i = c * kFramesPerChunk; i < end; ++i) select(i);
      },
      [&](int done) { control.update(double(done) / chunks); });
  return out;
}

Graph knn_graph(const NeighborLists& neighbors, const Eigen::MatrixXd& D,
                const std::vector<Edge>& extra) {
  const int n = neighbors.frames();
  // Every chosen pair goes into both rows; rows are then sorted and de-duplicated.
  std::vector<int> count(std::size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i) {
    for (int j : neighbors.of(i)) {
      ++count[i];
      ++count[j];
    }
  }
  for (const Edge& e : extra) {
    ++count[e.a];
    ++count[e.b];
  }
  std::vector<int> start(std::size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i) start[i + 1] = start[i] + count[i];
  std::vector<int> raw(static_cast<std::size_t>(start[n]));
  std::vector<int> fill(start.begin(), start.end() - 1);
  auto add = [&](int a, int b) {
    raw[fill[a]++] = b;
    raw[fill[b]++] = a;
  };
  for (int i = 0; i < n; ++i) {
    for (int j : neighbors.of(i)) add(i, j);
  }
  for (const Edge& e : extra) add(e.a, e.b);

  Graph g;
  g.offsets.assign(std::size_t(n) + 1, 0);
  g.targets.reserve(raw.size());
  for (int i = 0; i < n; ++i) {
    auto first = raw.begin() + start[i];
    auto last = raw.begin() + start[i + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    for (auto it = first; it != last; ++it) {
      if (*it == i) continue;
      g.targets.push_back(*it);
      g.weights.push_back(pair_distance(D, i, *it));
    }
    g.offsets[i + 1] = static_cast<int>(g.targets.size());
  }
  return g;
}

Components connected_components(const Graph& graph, bool positive_only) {
  const int n = graph.frames();
  Components c;
  c.label.assign(std::size_t(n), -1);
  std::vector<int> stack;
  for (int s = 0; s < n; ++s) {
    if (c.label[s] >= 0) continue;
    const int id = c.count++;
    c.label[s] = id;
    stack.push_back(s);
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      for (int e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e) {
        const int v = graph.targets[e];
        if (c.label[v] >= 0 || (positive_only && !(graph.weights[e] > 0.0))) continue;
        c.label[v] = id;
        stack.push_back(v);
      }
    }
  }
  return c;
}

std::vector<Edge> joining_edges(const Eigen::MatrixXd& D, const Components& components,
                                const Control& control) {
  const int n = static_cast<int>(components.label.size());
  std::vector<Edge> edges;
  if (components.count <= 1) return edges;
  std::vector<std::vector<int>> members(static_cast<std::size_t>(components.count));
  for (int i = 0; i < n; ++i) members[components.label[i]].push_back(i);

  // Prim's algorithm on the complete graph whose intra-component edges are free: best[v] is the
  // shortest distance from v to the tree so far, from[v] the tree frame that realises it.
  std::vector<char> in_tree(std::size_t(n), 0);
  std::vector<double> best(std::size_t(n), std::numeric_limits<double>::infinity());
  std::vector<int> from(std::size_t(n), -1);
  int added = 0;
  auto add_component = [&](int id) {
    for (int u : members[id]) in_tree[u] = 1;
    for (int u : members[id]) {
      for (int v = 0; v < n; ++v) {
        if (in_tree[v]) continue;
        const double d = pair_distance(D, u, v);
        if (d < best[v] || (d == best[v] && u < from[v])) {
          best[v] = d;
          from[v] = u;
        }
      }
      ++added;
      if (added % 64 == 0) control.update(double(added) / n);
    }
  };
  add_component(components.label[0]);
  for (int step = 1; step < components.count; ++step) {
    int v_min = -1;
    for (int v = 0; v < n; ++v) {
      if (!in_tree[v] && (v_min < 0 || best[v] < best[v_min])) v_min = v;
    }
    edges.push_back({std::min(from[v_min], v_min), std::max(from[v_min], v_min), best[v_min]});
    add_component(components.label[v_min]);
  }
  return edges;
}

void check_neighbor_count(int k, int most, int count, std::string_view what) {
  if (k < kMinNeighbors || k > most) {
    throw ParameterError("k = " + std::to_string(k) + " neighbours is out of range: with " +
                         std::to_string(count) + " " + std::string(what) + " it must be in [1, " +
                         std::to_string(most) + "]");
  }
}

void join_components(NeighborGraph& ng, const EmbedOptions& options, Embedding& out,
                     Progress& progress, double begin, double end, const Joiner& joiner) {
  const Components components = connected_components(ng.graph);
  out.k_used = options.k;
  out.graph_components = components.count;
  if (components.count <= 1) return;
  const std::string what = "the k-NN graph (k = " + std::to_string(options.k) + ") has " +
                           std::to_string(components.count) + " connected components";
  if (options.strict) {
    throw NumericalError(std::string(method_name(options.method)) + ": " + what +
                         "; use a larger k (or turn strict off to join them" +
                         std::string(joiner.strict_hint) + ")");
  }
  progress.stage("joining components", begin, end);
  ng.joins = joiner.join(components);
  ng.graph = joiner.rebuild(ng.joins);
  out.connecting_edges = static_cast<int>(ng.joins.size());
  out.warnings.push_back(what + "; joined them with " + std::to_string(ng.joins.size()) +
                         " edge(s) " + std::string(joiner.how) +
                         ". Distances across the joins are unreliable; a larger k avoids them");
}

NeighborGraph build_neighbor_graph(const Eigen::MatrixXd& D, const EmbedOptions& options,
                                   Embedding& out, Progress& progress, double begin, double end) {
  const double mid = begin + 0.8 * (end - begin);
  progress.stage("neighbours", begin, mid);
  NeighborGraph ng;
  ng.lists = knn_from_distances(D, options.k, progress.control());
  ng.graph = knn_graph(ng.lists, D);
  join_components(ng, options, out, progress, mid, end,
                  {"between their closest frames", " through their closest pairs",
                   [&](const Components& c) { return joining_edges(D, c, progress.control()); },
                   [&](const std::vector<Edge>& joins) { return knn_graph(ng.lists, D, joins); }});
  return ng;
}

}  // namespace motionmap::embed
