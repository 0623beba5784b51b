// UMAP (McInnes, Healy & Melville 2018): the fuzzy simplicial set of the k-NN graph, a spectral
// start from its normalised Laplacian, then a force layout by stochastic gradient descent with
// negative sampling, as umap-learn 0.5 does it (docs/methods/umap.md says what differs).
//
// Determinism: the layout runs on one thread, edges in CSR order, negative samples drawn from one
// std::mt19937_64 seeded with EmbedOptions::seed, so one seed gives the same map bit for bit
// whatever the thread pool's size (the k-NN search and the eigen solve before it are themselves
// independent of the thread count).
#include "motionmap/embed/umap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/detail/umap_layout.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/graph.h"

namespace motionmap::embed {

namespace {

constexpr double kSmoothTolerance = 1e-5;   // umap-learn's SMOOTH_K_TOLERANCE
constexpr double kMinDistanceScale = 1e-3;  // MIN_K_DIST_SCALE
constexpr int kBisectionSteps = 64;
constexpr int kNegativeSamples = 5;
constexpr double kRepulsion = 1.0;  // gamma
constexpr double kLearningRate = 1.0;
constexpr double kGradientClip = 4.0;
// Above this many frames (their positions over 1 MiB) the layout runs in breadth-first order.
constexpr int kLocalityOrderFrames = 65536;

double clip(double v) {
  return std::clamp(v, -kGradientClip, kGradientClip);
}

// x^p (x > 0) in single precision, as umap-learn's layout computes it: glibc's powf takes about
// 60 % of pow's time, and the power is most of the layout's arithmetic (7 per edge visit).
double power(double x, float p) {
  return static_cast<double>(std::pow(static_cast<float>(x), p));
}

// Uniform on [0, 1) from 53 random bits, and a standard normal (Box–Muller): written out, so the
// same seed draws the same numbers with every standard library.
double uniform(std::mt19937_64& rng) {
  return double(rng() >> 11) * 0x1.0p-53;
}
double normal(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform(rng);  // (0, 1]
  const double u2 = uniform(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

Graph to_graph(const Eigen::SparseMatrix<double>& S) {
  Graph g;
  const int n = static_cast<int>(S.cols());
  g.offsets.assign(std::size_t(n) + 1, 0);
  for (int c = 0; c < n; ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(S, c); it; ++it) {
      if (it.value() > 0.0) {
        g.targets.push_back(static_cast<int>(it.row()));
        g.weights.push_back(it.value());
      }
    }
    g.offsets[std::size_t(c) + 1] = static_cast<int>(g.targets.size());
  }
  return g;
}

// Each axis to [0, 10] (umap-learn's start of the layout); a constant axis to 0.
void rescale_to_ten(Eigen::MatrixXd& Y) {
  for (Eigen::Index a = 0; a < Y.cols(); ++a) {
    const double lo = Y.col(a).minCoeff(), hi = Y.col(a).maxCoeff();
    if (hi > lo) {
      Y.col(a) = (10.0 * (Y.col(a).array() - lo) / (hi - lo)).matrix();
    } else {
      Y.col(a).setZero();
    }
  }
}

}  // namespace

int umap_default_epochs(int frames) {
  return frames <= 10000 ? 500 : 200;
}

double umap_sigma(const double* d, int count, double rho, double target) {
  double lo = 0.0, hi = std::numeric_limits<double>::infinity(), mid = 1.0;
  for (int step = 0; step < kBisectionSteps; ++step) {
    double psum = 0.0;
    for (int j = 0; j < count; ++j) {
      const double excess = d[j] - rho;
      psum += excess > 0.0 ? std::exp(-(excess / mid)) : 1.0;
    }
    if (std::abs(psum - target) < kSmoothTolerance) break;
    if (psum > target) {
      hi = mid;
      mid = (lo + hi) / 2.0;
    } else {
      lo = mid;
      mid = std::isinf(hi) ? mid * 2.0 : (lo + hi) / 2.0;
    }
  }
  return mid;
}

UmapGraph umap_fuzzy_graph(const NeighborLists& lists, int n_neighbors) {
  const int n = lists.frames();
  const int m = lists.k;  // others per frame: n_neighbors − 1
  UmapGraph out;
  out.rho.assign(std::size_t(n), 0.0);
  out.sigma.assign(std::size_t(n), 0.0);
  const double target = std::log2(double(n_neighbors));
  double total = 0.0;
  for (double d : lists.distance) total += d;
  // The mean over the k-NN matrix with each frame's own column of zeros, as umap-learn has it.
  const double mean_all = n > 0 ? total / (double(n) * n_neighbors) : 0.0;
  std::vector<Eigen::Triplet<double>> directed;
  directed.reserve(lists.index.size());
  for (int i = 0; i < n; ++i) {
    const std::span<const double> d = lists.distances_of(i);
    double rho = 0.0;
    for (double v : d) {
      if (v > 0.0) {
        rho = v;  // nearest first: the first positive distance
        break;
      }
    }
    double sigma = umap_sigma(d.data(), m, rho, target);
    if (rho > 0.0) {
      double sum = 0.0;
      for (double v : d) sum += v;
      sigma = std::max(sigma, kMinDistanceScale * sum / n_neighbors);
    } else {
      sigma = std::max(sigma, kMinDistanceScale * mean_all);
    }
    out.rho[std::size_t(i)] = rho;
    out.sigma[std::size_t(i)] = sigma;
    const std::span<const int> nb = lists.of(i);
    for (int j = 0; j < m; ++j) {
      if (nb[std::size_t(j)] == i) continue;
      const double excess = d[std::size_t(j)] - rho;
      const double w = excess <= 0.0 || sigma == 0.0 ? 1.0 : std::exp(-(excess / sigma));
      directed.emplace_back(i, nb[std::size_t(j)], w);
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(directed.begin(), directed.end());
  const Eigen::SparseMatrix<double> At = A.transpose();
  const Eigen::SparseMatrix<double> S = A + At - A.cwiseProduct(At);
  out.graph = to_graph(S);
  return out;
}

UmapCurve umap_curve(double min_dist, double spread) {
  constexpr int kPoints = 300;
  Eigen::VectorXd x(kPoints), y(kPoints);
  for (int i = 0; i < kPoints; ++i) {
    x[i] = 3.0 * spread * i / (kPoints - 1);
    y[i] = x[i] < min_dist ? 1.0 : std::exp(-(x[i] - min_dist) / spread);
  }
  // f(x) = 1 / (1 + a·x^(2b)); x = 0 gives 1 for any a, b (no derivative there).
  auto residuals = [&](double a, double b, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
    r.resize(kPoints);
    if (J) J->resize(kPoints, 2);
    for (int i = 0; i < kPoints; ++i) {
      const double p = x[i] > 0.0 ? std::pow(x[i], 2.0 * b) : 0.0;
      const double f = 1.0 / (1.0 + a * p);
      r[i] = f - y[i];
      if (J) {
        (*J)(i, 0) = -p * f * f;
        (*J)(i, 1) = x[i] > 0.0 ? -a * p * 2.0 * std::log(x[i]) * f * f : 0.0;
      }
    }
  };
  double a = 1.0, b = 1.0, lambda = 1e-3;
  Eigen::VectorXd r, r_try;
  Eigen::MatrixXd J;
  residuals(a, b, r, &J);
  double cost = r.squaredNorm();
  for (int iteration = 0; iteration < 1000; ++iteration) {
    const Eigen::Matrix2d JtJ = J.transpose() * J;
    const Eigen::Vector2d g = J.transpose() * r;
    Eigen::Matrix2d H = JtJ;
    H.diagonal() += lambda * JtJ.diagonal();
    const Eigen::Vector2d step = H.ldlt().solve(-g);
    const double a_try = a + step[0], b_try = b + step[1];
    residuals(a_try, b_try, r_try, nullptr);
    const double cost_try = r_try.squaredNorm();
    if (std::isfinite(cost_try) && cost_try < cost) {
      const double gain = cost - cost_try;
      a = a_try;
      b = b_try;
      residuals(a, b, r, &J);
      cost = cost_try;
      lambda = std::max(lambda / 10.0, 1e-12);
      if (gain <= 1e-15 * cost && step.norm() <= 1e-12 * (std::abs(a) + std::abs(b))) break;
      if (step.norm() <= 1e-13 * (std::abs(a) + std::abs(b))) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e16) break;
    }
  }
  return {a, b};
}

std::vector<int> umap_breadth_first_order(const Graph& graph) {
  const int n = static_cast<int>(graph.offsets.size()) - 1;
  std::vector<int> order;
  order.reserve(std::size_t(std::max(n, 0)));
  std::vector<char> seen(std::size_t(std::max(n, 0)), 0);
  for (int root = 0; root < n; ++root) {
    if (seen[std::size_t(root)]) continue;
    seen[std::size_t(root)] = 1;
    std::size_t at = order.size();
    order.push_back(root);
    for (; at < order.size(); ++at) {
      const int i = order[at];
      for (int e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
        const int j = graph.targets[e];
        if (!seen[std::size_t(j)]) {
          seen[std::size_t(j)] = 1;
          order.push_back(j);
        }
      }
    }
  }
  return order;
}

int umap_layout_chunk_count(int frames) {
  return std::max(1, std::min(worker_count(), frames / 1000));
}

UmapChunks umap_layout_chunks(std::span<const int> head, int frames, int count) {
  count = std::max(1, std::min(count, std::max(frames, 1)));
  UmapChunks chunks;
  chunks.first.assign(std::size_t(count) + 1, frames);
  chunks.edge.assign(std::size_t(count) + 1, head.size());
  chunks.first[0] = 0;
  chunks.edge[0] = 0;
  for (int c = 1; c < count; ++c) {
    // The first edge of the frame at or after the c-th equal share of the edges.
    std::size_t at = head.size() * std::size_t(c) / std::size_t(count);
    while (at > 0 && at < head.size() && head[at - 1] == head[at]) ++at;
    const int frame = at < head.size() ? head[at] : frames;
    chunks.first[std::size_t(c)] = std::max(frame, chunks.first[std::size_t(c) - 1]);
    chunks.edge[std::size_t(c)] = std::max(at, chunks.edge[std::size_t(c) - 1]);
  }
  return chunks;
}

void umap_layout(const UmapEdges& edges, const UmapChunks& chunks, const UmapCurve& curve,
                 int epochs, std::uint64_t seed, Eigen::MatrixXd& Y, std::mt19937_64& rng,
                 Progress& progress, bool serial) {
  const int n = static_cast<int>(Y.rows());
  const int dims = static_cast<int>(Y.cols());
  const int count = chunks.count();
  const std::size_t E = edges.head.size();
  const std::vector<int>& head = edges.head;
  const std::vector<int>& tail = edges.tail;
  const std::vector<double>& every = edges.every;
  std::vector<double> every_negative(E), next(every), next_negative(E);
  for (std::size_t e = 0; e < E; ++e) {
    every_negative[e] = every[e] / kNegativeSamples;
    next_negative[e] = every_negative[e];
  }
  // Each chunk's random numbers, drawn kAhead ahead of their use so that the frames they pick
  // are fetched from memory before they are needed (the numbers and their order are those of
  // drawing each when it is used). Chunk 0 continues `rng` (one chunk: the serial layout's
  // numbers); chunk c > 0 has its own stream.
  constexpr int kAhead = 32;
  struct Stream {
    std::mt19937_64* rng = nullptr;
    std::uint64_t ahead[kAhead] = {};
    int at = 0;
  };
  std::vector<std::mt19937_64> own_rngs;
  own_rngs.reserve(std::size_t(std::max(count - 1, 0)));
  for (int c = 1; c < count; ++c) {
    std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * std::uint64_t(c);  // SplitMix64 of (seed, c)
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    own_rngs.emplace_back(z ^ (z >> 31));
  }
  std::vector<Stream> streams(std::size_t(std::max(count, 1)));
  for (int c = 0; c < count; ++c) {
    Stream& s = streams[std::size_t(c)];
    s.rng = c == 0 ? &rng : &own_rngs[std::size_t(c) - 1];
    for (std::uint64_t& v : s.ahead) v = (*s.rng)();
  }
  const double a = curve.a, b = curve.b;
  const float fb = static_cast<float>(b);
  // The positions frame by frame (x, y[, z] side by side: one cache line per frame), copied
  // back into Y at the end; what the other chunks' frames were when the epoch began.
  std::vector<double> live(std::size_t(n) * std::size_t(dims));
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < dims; ++d) live[std::size_t(i) * dims + d] = Y(i, d);
  }
  std::vector<double> frozen_copy(count > 1 ? live.size() : 0);
  double* pos = live.data();
  const double* frozen = count > 1 ? frozen_copy.data() : pos;
  double alpha = kLearningRate;
  auto run_chunk = [&](int c, int epoch) {
    Stream& s = streams[std::size_t(c)];
    const auto draw = [&]() {
      const std::uint64_t v = s.ahead[s.at];
      const std::uint64_t w = (*s.rng)();
      s.ahead[s.at] = w;
      s.at = (s.at + 1) % kAhead;
      const std::size_t o = std::size_t(w % static_cast<std::uint64_t>(n)) * std::size_t(dims);
      __builtin_prefetch(pos + o);
      __builtin_prefetch(frozen + o);
      return v;
    };
    const int lo = chunks.first[std::size_t(c)], hi = chunks.first[std::size_t(c) + 1];
    const auto own = [&](int v) { return v >= lo && v < hi; };
    const std::size_t last = chunks.edge[std::size_t(c) + 1];
    constexpr std::size_t kFetch = 16;  // edges between fetching a tail and using it
    for (std::size_t e = chunks.edge[std::size_t(c)]; e < last; ++e) {
      if (e + kFetch < last) {
        const int t = tail[e + kFetch];
        __builtin_prefetch((own(t) ? pos : frozen) + std::size_t(t) * dims);
      }
      if (next[e] > epoch) continue;
      const int j = head[e], k = tail[e];
      const bool mine = own(k);
      double* yj = pos + std::size_t(j) * dims;
      double* yk_live = pos + std::size_t(k) * dims;
      const double* yk = mine ? yk_live : frozen + std::size_t(k) * dims;
      double d2 = 0.0;
      for (int d = 0; d < dims; ++d) d2 += (yj[d] - yk[d]) * (yj[d] - yk[d]);
      double coefficient = 0.0;
      if (d2 > 0.0) {
        const double pw = power(d2, fb);  // d²ᵇ
        coefficient = -2.0 * a * b * (pw / d2) / (a * pw + 1.0);
      }
      if (mine) {
        for (int d = 0; d < dims; ++d) {
          const double grad = clip(coefficient * (yj[d] - yk_live[d]));
          yj[d] += grad * alpha;
          yk_live[d] -= grad * alpha;
        }
      } else {
        // j → k of another chunk: k is moved by its own edge k → j, and j takes the pull that
        // edge would have given it as well.
        for (int d = 0; d < dims; ++d) {
          const double grad = clip(coefficient * (yj[d] - yk[d]));
          yj[d] += 2.0 * grad * alpha;
        }
      }
      next[e] += every[e];
      const int negatives = static_cast<int>((epoch - next_negative[e]) / every_negative[e]);
      for (int p = 0; p < negatives; ++p) {
        const int o = static_cast<int>(draw() % static_cast<std::uint64_t>(n));
        const double* yo = (own(o) ? pos : frozen) + std::size_t(o) * dims;
        double q2 = 0.0;
        double diff[3];
        for (int d = 0; d < dims; ++d) {
          diff[d] = yj[d] - yo[d];
          q2 += diff[d] * diff[d];
        }
        if (q2 > 0.0) {
          const double push = 2.0 * kRepulsion * b / ((0.001 + q2) * (a * power(q2, fb) + 1.0));
          for (int d = 0; d < dims; ++d) yj[d] += clip(push * diff[d]) * alpha;
        } else if (j != o) {
          for (int d = 0; d < dims; ++d) yj[d] += kGradientClip * alpha;
        }
      }
      next_negative[e] += std::max(negatives, 0) * every_negative[e];
    }
  };
  for (int epoch = 0; epoch < epochs; ++epoch) {
    if (count > 1) {
      std::copy(live.begin(), live.end(), frozen_copy.begin());
      parallel_chunks(
          count, [&](int c, int) { run_chunk(c, epoch); }, {}, serial);
    } else {
      run_chunk(0, epoch);
    }
    alpha = kLearningRate * (1.0 - double(epoch) / epochs);
    progress.update(double(epoch + 1) / epochs);
  }
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < dims; ++d) Y(i, d) = live[std::size_t(i) * dims + d];
  }
}

static void umap_on(const NeighborGraph& ng, int n_neighbors, const EmbedOptions& options,
                    Embedding& out, Progress& progress, double begin, double end) {
  const int n = ng.lists.frames();
  const int dims = options.dimensions;
  const double graph_end = begin + 0.05 * (end - begin);
  const double init_end = begin + 0.15 * (end - begin);
  progress.stage("fuzzy graph", begin, graph_end);
  UmapGraph fuzzy = umap_fuzzy_graph(ng.lists, n_neighbors);
  out.k_used = n_neighbors;
  const int epochs = options.epochs > 0 ? options.epochs : umap_default_epochs(n);

  // The spectral start: the normalised Laplacian of the fuzzy graph, its components joined by
  // the graph's joining edges at the smallest membership (so they stay apart in the start).
  progress.stage("eigen", graph_end, init_end);  // the spectral start
  std::mt19937_64 rng(static_cast<std::uint64_t>(options.seed));
  Eigen::MatrixXd Y(n, dims);
  bool spectral = false;
  {
    Graph w = fuzzy.graph;
    if (!ng.joins.empty()) {
      const double smallest = *std::min_element(w.weights.begin(), w.weights.end());
      std::vector<Eigen::Triplet<double>> t;
      for (int i = 0; i < n; ++i) {
        for (int e = w.offsets[i]; e < w.offsets[i + 1]; ++e)
          t.emplace_back(i, w.targets[e], w.weights[e]);
      }
      for (const Edge& j : ng.joins) {
        t.emplace_back(j.a, j.b, smallest);
        t.emplace_back(j.b, j.a, smallest);
      }
      Eigen::SparseMatrix<double> S(n, n);
      S.setFromTriplets(t.begin(), t.end(), [](double x, double y) { return std::max(x, y); });
      w = to_graph(S);
    }
    std::string failure;
    if (connected_components(w, true).count > 1) {
      failure = "the fuzzy graph is disconnected";
    } else {
      try {
        Eigen::VectorXd degrees;
        const Eigen::SparseMatrix<double> L = normalized_laplacian(w, degrees);
        const Eigen::VectorXd q = degrees.cwiseSqrt().normalized();
        const EigenPairs low =
            smallest_eigenpairs_excluding(L, q, dims, "umap", progress.control(), kDenseEigenLimit,
                                          out.from_points ? kPointsShiftInvert : ShiftInvert{});
        out.eigenvalues = low.values;
        Y = low.vectors;
        spectral = Y.allFinite() && Y.cwiseAbs().maxCoeff() > 0.0;
        if (!spectral) failure = "its eigenvectors are degenerate";
      } catch (const NumericalError& e) {
        failure = e.what();
      }
    }
    if (spectral) {
      Y *= 10.0 / Y.cwiseAbs().maxCoeff();
      for (Eigen::Index i = 0; i < Y.rows(); ++i) {
        for (int a = 0; a < dims; ++a) Y(i, a) += 1e-4 * normal(rng);
      }
    } else {
      out.notes.push_back("umap: the spectral start failed (" + failure +
                          "); the layout started from random positions (seed " +
                          std::to_string(options.seed) + ")");
      out.eigenvalues = Eigen::VectorXd::Zero(dims);
      for (Eigen::Index i = 0; i < Y.rows(); ++i) {
        for (int a = 0; a < dims; ++a) Y(i, a) = -10.0 + 20.0 * uniform(rng);
      }
    }
  }
  rescale_to_ten(Y);

  // The edges the layout samples: both directions of every membership ≥ max ÷ epochs, each
  // every max ÷ w epochs, in CSR order (grouped by head frame).
  progress.stage("layout", init_end, end);
  const Graph& g = fuzzy.graph;
  const double largest =
      g.weights.empty() ? 0.0 : *std::max_element(g.weights.begin(), g.weights.end());
  // Large maps are laid out in the breadth-first order of the graph, so that a frame's
  // neighbours lie near it in memory (and a chunk's frames are a region of the graph).
  const std::vector<int> order =
      n > kLocalityOrderFrames ? umap_breadth_first_order(g) : std::vector<int>();
  std::vector<int> place(order.empty() ? 0 : std::size_t(n));
  for (std::size_t v = 0; v < order.size(); ++v) place[std::size_t(order[v])] = int(v);
  UmapEdges edges;
  for (int v = 0; v < n; ++v) {
    const int i = order.empty() ? v : order[std::size_t(v)];
    for (int e = g.offsets[i]; e < g.offsets[i + 1]; ++e) {
      if (g.weights[e] < largest / epochs) continue;
      edges.head.push_back(v);
      edges.tail.push_back(order.empty() ? g.targets[e] : place[std::size_t(g.targets[e])]);
      edges.every.push_back(largest / g.weights[e]);
    }
  }
  fuzzy = UmapGraph();  // the layout needs only its edges: the graph's memory goes back
  if (!order.empty()) {
    const Eigen::MatrixXd start = Y;
    for (int v = 0; v < n; ++v) Y.row(v) = start.row(order[std::size_t(v)]);
  }
  const UmapChunks chunks = umap_layout_chunks(edges.head, n, umap_layout_chunk_count(n));
  umap_layout(edges, chunks, umap_curve(options.min_dist, 1.0), epochs,
              static_cast<std::uint64_t>(options.seed), Y, rng, progress);
  if (!order.empty()) {
    const Eigen::MatrixXd laid = Y;
    for (int v = 0; v < n; ++v) Y.row(order[std::size_t(v)]) = laid.row(v);
  }
  out.coordinates = std::move(Y);
}

void run_umap(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
              Progress& progress) {
  EmbedOptions o = options;
  o.k = options.k - 1;
  umap_on(build_neighbor_graph(D, o, out, progress, 0.02, 0.2), options.k, options, out, progress,
          0.2, 1.0);
}

void run_umap(const PointSet& points, const EmbedOptions& options, Embedding& out,
              Progress& progress) {
  EmbedOptions o = options;
  o.k = options.k - 1;
  umap_on(build_neighbor_graph(points, o, out, progress, 0.02, 0.2), options.k, options, out,
          progress, 0.2, 1.0);
}

}  // namespace motionmap::embed
