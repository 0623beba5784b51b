// The neighbour graph of the points path: k-NN lists from knn_from_points, edge lengths from the
// lists themselves, and components joined through max-min landmarks instead of all pairs.
#include <algorithm>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"

namespace motionmap::embed {

namespace {

// The symmetric k-NN graph with each edge's length as the lists (or the join) give it; a pair in
// both lists has the same length in both (the metric is symmetric to the bit).
Graph knn_graph_from_lists(const NeighborLists& lists, const std::vector<Edge>& extra) {
  const int n = lists.frames();
  // Every pair goes into both rows of one flat array; rows are then sorted and de-duplicated.
  std::vector<std::size_t> start(std::size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i) {
    start[i + 1] += std::size_t(lists.k);
    for (int j : lists.of(i)) ++start[j + 1];
  }
  for (const Edge& e : extra) {
    ++start[e.a + 1];
    ++start[e.b + 1];
  }
  for (int i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<std::pair<int, double>> raw(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  auto add = [&](int a, int b, double length) {
    raw[fill[a]++] = {b, length};
    raw[fill[b]++] = {a, length};
  };
  for (int i = 0; i < n; ++i) {
    const auto index = lists.of(i);
    const auto distance = lists.distances_of(i);
    for (int a = 0; a < lists.k; ++a) add(i, index[a], distance[a]);
  }
  for (const Edge& e : extra) add(e.a, e.b, e.length);
  Graph g;
  g.offsets.assign(std::size_t(n) + 1, 0);
  g.targets.reserve(raw.size());
  g.weights.reserve(raw.size());
  for (int i = 0; i < n; ++i) {
    const auto first = raw.begin() + std::ptrdiff_t(start[i]);
    const auto last = raw.begin() + std::ptrdiff_t(start[i + 1]);
    std::sort(first, last);
    int previous = -1;
    for (auto it = first; it != last; ++it) {
      if (it->first == previous || it->first == i) continue;
      previous = it->first;
      g.targets.push_back(it->first);
      g.weights.push_back(it->second);
    }
    g.offsets[i + 1] = static_cast<int>(g.targets.size());
  }
  return g;
}

// count − 1 edges joining the components, by Borůvka's algorithm over the candidate edges
// frame–landmark (every frame to every landmark of another component): each round gives every
// group of components its shortest candidate edge to another group (ties: the smaller frame, then
// the smaller landmark), and merges along them. Every component has a candidate (its frames reach
// a landmark elsewhere, or other frames reach its landmark), so the rounds end in one group, after
// at most log2(count) passes over the #frames·L distances.
std::vector<Edge> joining_edges(const Components& components, const std::vector<int>& landmarks,
                                const Eigen::MatrixXd& distances) {
  const int n = static_cast<int>(components.label.size());
  const int c = components.count;
  std::vector<int> group(static_cast<std::size_t>(c));
  for (int g = 0; g < c; ++g) group[g] = g;
  auto find = [&](int g) {
    while (group[g] != g) g = group[g] = group[group[g]];
    return g;
  };
  auto better = [](const Edge& e, double d, int f, int l) {
    return e.a < 0 || d < e.length || (d == e.length && (f < e.a || (f == e.a && l < e.b)));
  };
  std::vector<Edge> edges;
  for (int groups = c; groups > 1;) {
    // best[g]: the shortest candidate leaving group g; a = the frame, b = the landmark's frame.
    std::vector<Edge> best(static_cast<std::size_t>(c), Edge{-1, -1, 0.0});
    for (int f = 0; f < n; ++f) {
      const int gf = find(components.label[f]);
      for (std::size_t l = 0; l < landmarks.size(); ++l) {
        const int gl = find(components.label[landmarks[l]]);
        if (gl == gf) continue;
        const double d = distances(Eigen::Index(l), f);
        for (int g : {gf, gl}) {
          if (better(best[g], d, f, landmarks[l])) best[g] = {f, landmarks[l], d};
        }
      }
    }
    bool merged = false;
    for (int g = 0; g < c; ++g) {
      const Edge& e = best[g];
      if (e.a < 0 || find(g) != g) continue;
      const int ga = find(components.label[e.a]), gb = find(components.label[e.b]);
      if (ga == gb) continue;
      group[std::max(ga, gb)] = std::min(ga, gb);
      edges.push_back({std::min(e.a, e.b), std::max(e.a, e.b), e.length});
      --groups;
      merged = true;
    }
    if (!merged) {
      throw NumericalError("the landmarks do not reach every component of the k-NN graph");
    }
  }
  return edges;
}

NeighborSearch to_search(EmbedOptions::Search s) {
  switch (s) {
    case EmbedOptions::Search::Exact:
      return NeighborSearch::Exact;
    case EmbedOptions::Search::Approximate:
      return NeighborSearch::Approximate;
    case EmbedOptions::Search::Auto:
      break;
  }
  return NeighborSearch::Auto;
}

}  // namespace

NeighborGraph build_neighbor_graph(const PointSet& points, const EmbedOptions& options,
                                   Embedding& out, Progress& progress, double begin, double end) {
  const double mid = begin + 0.8 * (end - begin);
  progress.stage("neighbours", begin, mid);
  NeighborGraph ng;
  NeighborSearchReport report;
  ng.lists =
      knn_from_points(points, options.k, to_search(options.search), progress.control(), &report);
  out.neighbor_search = report.description();
  ng.graph = knn_graph_from_lists(ng.lists, {});
  join_components(
      ng, options, out, progress, mid, end,
      {"between a frame and a landmark of another component", "",
       [&](const Components& components) {
         Eigen::MatrixXd distances;
         const std::vector<int> landmarks = maxmin_landmarks(
             points, std::min(points.frames(), kDefaultLandmarks), distances, progress.control());
         return joining_edges(components, landmarks, distances);
       },
       [&](const std::vector<Edge>& joins) { return knn_graph_from_lists(ng.lists, joins); }});
  return ng;
}

}  // namespace motionmap::embed
