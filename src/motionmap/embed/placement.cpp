#include "motionmap/embed/placement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/points.h"
#include "motionmap/embed/umap.h"

namespace motionmap::embed {

namespace {

constexpr int kFramesPerChunk = 256;

std::string who(Method method) {
  return "place (" + std::string(method_name(method)) + "): ";
}

// −½·P·(δ² − μ) + c for one frame's distances δ to the landmarks, summed in a fixed order.
void triangulate_one(const LandmarkFit& fit, const double* delta, double* x) {
  const Eigen::Index L = fit.projection.cols();
  for (Eigen::Index a = 0; a < fit.projection.rows(); ++a) {
    double sum = 0.0;
    for (Eigen::Index l = 0; l < L; ++l) {
      sum += fit.projection(a, l) * (delta[l] * delta[l] - fit.mean_squared[l]);
    }
    x[a] = -0.5 * sum + fit.offset[a];
  }
}

// Shortest-path lengths from a new frame that joins `graph` through `entry` (sample, length)
// edges, to every sample (Dijkstra with lazy deletion).
void geodesics_from(const Graph& graph, std::span<const int> entry, std::span<const double> length,
                    std::vector<double>& dist) {
  const int n = graph.frames();
  dist.assign(std::size_t(n), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::vector<Item> heap;
  auto push = [&](double d, int v) {
    heap.emplace_back(d, v);
    std::push_heap(heap.begin(), heap.end(), std::greater<>());
  };
  for (std::size_t a = 0; a < entry.size(); ++a) {
    if (length[a] < dist[entry[a]]) {
      dist[entry[a]] = length[a];
      push(length[a], entry[a]);
    }
  }
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto [d, u] = heap.back();
    heap.pop_back();
    if (d > dist[u]) continue;
    for (int e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e) {
      const double candidate = d + graph.weights[e];
      if (candidate < dist[graph.targets[e]]) {
        dist[graph.targets[e]] = candidate;
        push(candidate, graph.targets[e]);
      }
    }
  }
}

void check_rows(const Eigen::Ref<const Eigen::MatrixXd>& rows, Eigen::Index columns,
                const char* what, Method method) {
  if (rows.cols() != columns) {
    throw ParameterError(who(method) + "the new frames' " + what + " have " +
                         std::to_string(rows.cols()) + " values per frame; the map's have " +
                         std::to_string(columns));
  }
  if (!rows.allFinite()) {
    for (Eigen::Index r = 0; r < rows.rows(); ++r) {
      if (!rows.row(r).allFinite()) {
        throw ParameterError(who(method) + "frame " + std::to_string(r) + "'s " + what +
                             " are not all finite");
      }
    }
  }
}

}  // namespace

MapModel make_model(const EmbedInput& input, const EmbedOptions& options, Embedding map) {
  MapModel model;
  model.method = map.method;
  model.dimensions = static_cast<int>(map.coordinates.cols());
  model.coordinates = std::move(map.coordinates);
  const Eigen::Index n = model.coordinates.rows();
  const std::string w = who(map.method);
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw ParameterError(w + what + " of the " + std::to_string(n) + " mapped frames");
  };
  switch (map.method) {
    case Method::Gplvm: {
      require(input.features && input.features->rows() == n, "make_model needs the features X");
      require(map.gplvm_kernel.size() == 4, "make_model needs the GP-LVM's kernel");
      const Eigen::MatrixXd& X = *input.features;
      model.mean = X.colwise().mean();
      model.features = RowMatrix(X);
      const GplvmKernel kernel{map.gplvm_kernel[0], map.gplvm_kernel[1], map.gplvm_kernel[2],
                               map.gplvm_kernel[3]};
      model.gplvm =
          gplvm_predictive(X.rowwise() - model.mean, model.coordinates, map.gplvm_inducing, kernel);
      break;
    }
    case Method::Pca:
    case Method::Svd: {
      require(input.features && input.features->rows() == n, "make_model needs the features X");
      const Eigen::MatrixXd& X = *input.features;
      if (map.method == Method::Pca) {
        model.mean = X.colwise().mean();
        if (options.standardize) model.scale = standardization_scale(X, model.mean, nullptr);
      }
      // Y = Z·V with Z the centred (scaled) X, so Zᵀ·Y = V·Σ² and V = Zᵀ·Y ÷ Σ².
      Eigen::MatrixXd Z = X;
      if (model.mean.size() > 0) Z.rowwise() -= model.mean;
      if (model.scale.size() > 0) Z = Z.array().rowwise() / model.scale.array();
      model.axes = Z.transpose() * model.coordinates;
      for (int a = 0; a < model.dimensions; ++a) {
        const double s2 = model.coordinates.col(a).squaredNorm();
        model.axes.col(a) = s2 > 0.0 ? (model.axes.col(a) / s2).eval()
                                     : Eigen::VectorXd::Zero(model.axes.rows()).eval();
      }
      break;
    }
    case Method::Mds:
    case Method::Isomap:
    case Method::LaplacianEigenmap:
    case Method::Lle:
    case Method::Umap: {
      require(input.points && input.points->rows() == n,
              "make_model needs the points (the rows D is computed from)");
      model.metric = input.metric;
      if (map.method == Method::Mds || map.method == Method::Isomap) {
        require(map.landmarks.has_value(), "make_model needs the map's landmark fit");
        model.landmarks = std::move(map.landmarks);
      }
      // The rows `frames` of `all` (all of them when `frames` is empty).
      auto rows_of = [](const auto& all, const std::vector<int>& frames) {
        std::decay_t<decltype(all)> rows(Eigen::Index(frames.size()), all.cols());
        for (std::size_t r = 0; r < frames.size(); ++r) {
          rows.row(Eigen::Index(r)) = all.row(frames[r]);
        }
        return rows;
      };
      const std::vector<int>& fitted = map.fitted_frames;
      if (model.landmarks && !fitted.empty()) {
        // The model's samples are the fitted frames: landmarks and geodesic columns index them.
        for (int& f : model.landmarks->frames) {
          f = static_cast<int>(std::lower_bound(fitted.begin(), fitted.end(), f) - fitted.begin());
        }
        Eigen::MatrixXd& geodesic = model.landmarks->geodesic;
        if (geodesic.cols() == n) {
          const Eigen::Map<const Eigen::VectorXi> at(fitted.data(), Eigen::Index(fitted.size()));
          geodesic = geodesic(Eigen::all, at).eval();
        }
      }
      if (map.method == Method::Mds && map.from_points) {
        model.points_are_landmarks = true;
        model.points = rows_of(*input.points, model.landmarks->frames);
      } else if (!fitted.empty()) {
        // A sampled le or lle map, or a map of frames that repeat poses: its model is the map of
        // the sample (of the distinct poses), which placed the others.
        model.points = rows_of(*input.points, fitted);
        model.coordinates = rows_of(model.coordinates, fitted);
      } else {
        model.points = *input.points;
      }
      if (uses_graph(map.method)) model.k = map.k_used;
      if (map.method == Method::Isomap && !map.from_points) {
        require(input.distances && input.distances->rows() == n,
                "make_model needs D for a dense isomap map");
        Embedding scratch;
        Progress none;
        if (fitted.empty()) {
          model.graph =
              build_neighbor_graph(*input.distances, options, scratch, none, 0.0, 1.0).graph;
        } else {
          // The distinct poses' graph, with the k the fit used (at most their number − 1).
          EmbedOptions fit_options = options;
          fit_options.k = map.k_used;
          const Eigen::Map<const Eigen::VectorXi> at(fitted.data(), Eigen::Index(fitted.size()));
          const Eigen::MatrixXd D = (*input.distances)(at, at);
          model.graph = build_neighbor_graph(D, fit_options, scratch, none, 0.0, 1.0).graph;
        }
      }
      if (map.method == Method::LaplacianEigenmap) {
        model.heat = map.heat_used;
        model.eigenvalues = map.eigenvalues;
      }
      if (map.method == Method::Lle) {
        require(input.features && input.features->rows() == n, "make_model needs the features X");
        model.features = fitted.empty() ? RowMatrix(*input.features)
                                        : RowMatrix(rows_of(*input.features, fitted));
        model.reg = options.reg;
      }
      break;
    }
  }
  return model;
}

std::shared_ptr<const GplvmMap> gplvm_map(const MapModel& model, const Eigen::MatrixXd& coords) {
  if (model.method != Method::Gplvm || model.dimensions != 2 || coords.cols() != 2 ||
      model.coordinates.rows() != coords.rows()) {
    return nullptr;
  }
  const Eigen::MatrixXd Y = Eigen::MatrixXd(model.features).rowwise() - model.mean;
  return std::make_shared<const GplvmMap>(model.gplvm, coords, &Y);
}

namespace {

bool searches(const MapModel& model) {
  return model.method != Method::Pca && model.method != Method::Svd &&
         model.method != Method::Gplvm && !model.points_are_landmarks;
}

// gplvm: each frame's latent point from the latent points of its kGplvmPlaceStarts nearest
// training frames (Euclidean, in X), in parallel.
Eigen::MatrixXd place_gplvm(const MapModel& model, const Eigen::MatrixXd& features,
                            const Control& control) {
  const Eigen::Index frames = features.rows(), n = model.features.rows();
  const int starts = static_cast<int>(std::min<Eigen::Index>(kGplvmPlaceStarts, n));
  Eigen::MatrixXd out(frames, model.dimensions);
  const Eigen::VectorXd train_norms = model.features.rowwise().squaredNorm();
  const int chunks = static_cast<int>((frames + kFramesPerChunk - 1) / kFramesPerChunk);
  parallel_chunks(
      chunks,
      [&](int c, int) {
        const Eigen::Index begin = Eigen::Index(c) * kFramesPerChunk;
        const Eigen::Index end = std::min<Eigen::Index>(frames, begin + kFramesPerChunk);
        std::vector<std::pair<double, int>> order(static_cast<std::size_t>(n));
        for (Eigen::Index f = begin; f < end; ++f) {
          control.check();
          const Eigen::VectorXd y = features.row(f).transpose();
          const Eigen::VectorXd d2 =
              (train_norms - 2.0 * (model.features * y)).array() + y.squaredNorm();
          for (Eigen::Index i = 0; i < n; ++i) order[std::size_t(i)] = {d2[i], int(i)};
          std::partial_sort(order.begin(), order.begin() + starts, order.end());
          Eigen::MatrixXd from(starts, model.dimensions);
          for (int a = 0; a < starts; ++a) {
            from.row(a) = model.coordinates.row(order[std::size_t(a)].second);
          }
          const Eigen::VectorXd centred = y - model.mean.transpose();
          out.row(f) = gplvm_place(model.gplvm, centred, from).transpose();
        }
      },
      [&](int done) { control.update(double(done) / chunks); });
  return out;
}

}  // namespace

std::unique_ptr<SampleSearch> make_search(const MapModel& model, const Control& control) {
  if (!searches(model)) return nullptr;
  return std::make_unique<SampleSearch>(PointSet{&model.points, model.metric}, control);
}

Eigen::MatrixXd place(const MapModel& model, const PlaceInput& input, const Control& control,
                      const SampleSearch* search) {
  const Method method = model.method;
  const int dims = model.dimensions;
  const bool projection = method == Method::Pca || method == Method::Svd;
  const bool gplvm = method == Method::Gplvm;
  const bool needs_features = projection || method == Method::Lle || gplvm;
  const bool needs_points = !projection && !gplvm;
  if (needs_features && !input.features) {
    throw ParameterError(who(method) + "this map places frames by their features X; none given");
  }
  if (needs_points && !input.points) {
    throw ParameterError(who(method) + "this map places frames by their points; none given");
  }
  Eigen::Index frames = needs_points ? input.points->rows() : input.features->rows();
  if (needs_features) {
    check_rows(*input.features, projection ? model.axes.rows() : model.features.cols(), "features",
               method);
  }
  if (needs_points) check_rows(*input.points, model.points.cols(), "points", method);
  if (needs_features && needs_points && input.features->rows() != frames) {
    throw ParameterError(who(method) + "the new frames have " +
                         std::to_string(input.features->rows()) + " rows of features but " +
                         std::to_string(frames) + " of points");
  }

  if (gplvm) return place_gplvm(model, *input.features, control);
  Eigen::MatrixXd out(frames, dims);
  if (frames == 0) return out;
  // The nearest samples of every frame (the k-d tree search the fit's k-NN uses, exact): every
  // method with points but a landmark mds map (which keeps only its landmarks, and places a
  // sample exactly by the triangulation anyway).
  const bool landmark_mds = model.points_are_landmarks;
  const int k = method == Method::Mds ? 1 : std::max(model.k, 1);
  const bool searching = searches(model);
  if (search && (!searching || search->samples().rows != &model.points ||
                 search->samples().metric != model.metric)) {
    throw ParameterError(who(method) + "the search given is not one over this map's samples");
  }
  NeighborLists nearest;
  if (searching) {
    std::vector<int> all(static_cast<std::size_t>(frames));
    for (int f = 0; f < static_cast<int>(frames); ++f) all[std::size_t(f)] = f;
    const PointSet queries{input.points, model.metric};
    if (search) {
      nearest = search->nearest(queries, all, k, control.part(0.0, 0.5));
    } else {
      nearest = knn_to_samples(PointSet{&model.points, model.metric}, queries, all, k,
                               control.part(0.0, 0.5));
    }
  }
  const Control placing = searching ? control.part(0.5, 1.0) : control;
  static const RowMatrix no_points;
  const RowMatrix& points = needs_points ? *input.points : no_points;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> features =
      needs_features ? *input.features : Eigen::MatrixXd();

  // mds: a frame's distances to the landmarks, as the fit computed them (so a map's own frames
  // land on their coordinates): EuclideanToLandmarks for Euclidean points.
  std::optional<EuclideanToLandmarks> to_landmarks;
  if (method == Method::Mds && model.metric == Metric::Euclidean) {
    if (landmark_mds) {
      to_landmarks.emplace(model.points);
    } else {
      RowMatrix rows(Eigen::Index(model.landmarks->frames.size()), model.points.cols());
      for (std::size_t l = 0; l < model.landmarks->frames.size(); ++l) {
        rows.row(Eigen::Index(l)) = model.points.row(model.landmarks->frames[l]);
      }
      to_landmarks.emplace(rows);
    }
  }
  auto landmark_distances = [&](Eigen::Index f, double* delta) {
    const LandmarkFit& fit = *model.landmarks;
    const Eigen::Index L = Eigen::Index(fit.frames.size());
    if (to_landmarks) {
      to_landmarks->compute(points, f, 1, Eigen::Map<Eigen::MatrixXd>(delta, L, 1));
      return;
    }
    for (Eigen::Index l = 0; l < L; ++l) {
      const Eigen::Index row = landmark_mds ? l : fit.frames[std::size_t(l)];
      delta[l] = pose_distance(model.points.row(row), points.row(f), model.metric);
    }
  };

  // `block`: the frame's distances to the landmarks when they were computed for its chunk.
  auto place_one = [&](Eigen::Index f, std::vector<double>& scratch, const double* block) {
    double value[3] = {0.0, 0.0, 0.0};
    if (projection) {
      for (int a = 0; a < dims; ++a) {
        double sum = 0.0;
        for (Eigen::Index c = 0; c < model.axes.rows(); ++c) {
          double v = features(f, c);
          if (model.mean.size() > 0) v -= model.mean[c];
          if (model.scale.size() > 0) v /= model.scale[c];
          sum += v * model.axes(c, a);
        }
        value[a] = sum;
      }
    } else if (landmark_mds) {
      const LandmarkFit& fit = *model.landmarks;
      if (!block) {
        scratch.resize(fit.frames.size());
        landmark_distances(f, scratch.data());
      }
      triangulate_one(fit, block ? block : scratch.data(), value);
    } else {
      const PoseRow p = points.row(f);
      const std::span<const int> nb = nearest.of(static_cast<int>(f));
      const std::span<const double> nd = nearest.distances_of(static_cast<int>(f));
      if (nd[0] == 0.0) {
        // A sample's own pose lands on that sample.
        for (int a = 0; a < dims; ++a) value[a] = model.coordinates(nb[0], a);
      } else if (method == Method::Mds) {
        const LandmarkFit& fit = *model.landmarks;
        scratch.resize(fit.frames.size());
        landmark_distances(f, scratch.data());
        triangulate_one(fit, scratch.data(), value);
      } else if (method == Method::Isomap) {
        const LandmarkFit& fit = *model.landmarks;
        const std::size_t L = fit.frames.size();
        scratch.assign(L, std::numeric_limits<double>::infinity());
        if (fit.geodesic.size() > 0) {
          for (std::size_t a = 0; a < nb.size(); ++a) {
            const double* g = fit.geodesic.col(nb[a]).data();
            for (std::size_t l = 0; l < L; ++l) scratch[l] = std::min(scratch[l], nd[a] + g[l]);
          }
        } else {
          std::vector<double> dist;
          geodesics_from(model.graph, nb, nd, dist);
          for (std::size_t l = 0; l < L; ++l) scratch[l] = dist[fit.frames[l]];
        }
        triangulate_one(fit, scratch.data(), value);
      } else if (method == Method::LaplacianEigenmap) {
        // Normalised heat-kernel weights, shifted by the nearest distance (exact for the ratio,
        // and no underflow far from the samples).
        double total = 0.0;
        for (std::size_t a = 0; a < nb.size(); ++a) {
          const double w =
              model.heat > 0.0 ? std::exp(-(nd[a] * nd[a] - nd[0] * nd[0]) / model.heat) : 1.0;
          total += w;
          for (int c = 0; c < dims; ++c) value[c] += w * model.coordinates(nb[a], c);
        }
        for (int c = 0; c < dims; ++c) value[c] /= total * (1.0 - model.eigenvalues[c]);
      } else if (method == Method::Umap) {
        // umap-learn's transform start: memberships exp(−d/sigma) of the k nearest samples
        // (rho = 0, sigma by the fit's bisection to log2(k), at least 1e-3 of their mean
        // distance), normalised to sum 1.
        const int m = static_cast<int>(nb.size());
        double mean = 0.0;
        for (double v : nd) mean += v;
        mean /= m;
        const double sigma =
            std::max(umap_sigma(nd.data(), m, 0.0, std::log2(double(m))), 1e-3 * mean);
        double total = 0.0;
        for (int s = 0; s < m; ++s) {
          // Shifted by the nearest distance: the same ratios, no underflow far from the map.
          const double w = std::exp(-(nd[std::size_t(s)] - nd[0]) / sigma);
          total += w;
          for (int c = 0; c < dims; ++c) value[c] += w * model.coordinates(nb[std::size_t(s)], c);
        }
        for (int c = 0; c < dims; ++c) value[c] /= total;
      } else {  // LLE: the barycentric weights of the k nearest samples, as the fit solved them
        const Eigen::Index m = static_cast<Eigen::Index>(nb.size());
        Eigen::MatrixXd Z(m, model.features.cols());
        for (Eigen::Index a = 0; a < m; ++a) {
          Z.row(a) = model.features.row(nb[a]) - features.row(f);
        }
        Eigen::MatrixXd C = Eigen::MatrixXd::Zero(m, m);
        C.selfadjointView<Eigen::Lower>().rankUpdate(Z);
        const double trace = C.trace();
        C.diagonal().array() += trace > 0.0 ? model.reg * trace : model.reg;
        Eigen::VectorXd w = C.llt().solve(Eigen::VectorXd::Ones(m));
        w /= w.sum();
        for (Eigen::Index a = 0; a < m; ++a) {
          for (int c = 0; c < dims; ++c) value[c] += w[a] * model.coordinates(nb[a], c);
        }
      }
    }
    for (int a = 0; a < dims; ++a) out(f, a) = value[a];
  };

  const int chunks = static_cast<int>((frames + kFramesPerChunk - 1) / kFramesPerChunk);
  parallel_chunks(
      chunks,
      [&](int c, int) {
        std::vector<double> scratch;
        const Eigen::Index begin = Eigen::Index(c) * kFramesPerChunk;
        const Eigen::Index end = std::min<Eigen::Index>(frames, begin + kFramesPerChunk);
        // A landmark mds map: the chunk's distances together (EuclideanToLandmarks is faster
        // on several frames; each frame's are the same bits).
        Eigen::MatrixXd block;
        if (landmark_mds && to_landmarks) {
          block.resize(to_landmarks->landmarks(), end - begin);
          to_landmarks->compute(points, begin, end - begin, block);
        }
        for (Eigen::Index f = begin; f < end; ++f) {
          place_one(f, scratch, block.size() > 0 ? block.col(f - begin).data() : nullptr);
        }
      },
      [&](int done) { placing.update(double(done) / chunks); });
  return out;
}

}  // namespace motionmap::embed
