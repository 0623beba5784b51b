#include "motionmap/pipeline/clip_map.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <random>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/memory.h"
#include "motionmap/core/names.h"
#include "motionmap/embed/points.h"
#include "motionmap/embed/umap.h"

namespace motionmap::pipeline {

using embed::Embedding;
using embed::EmbedInput;
using embed::jump_score;
using embed::Method;
using embed::neighborhood_quality;
using motionmap::Metric;

std::string_view map_path_name(MapPath path) {
  return enum_name(kMapPathNames, path);
}

std::optional<MapPath> parse_map_path(std::string_view name) {
  return parse_enum(kMapPathNames, name);
}

namespace {
std::string fmt(double v, const char* format = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

namespace {

Metric metric_of(features::DistanceKind kind) {
  return kind == features::DistanceKind::Geodesic ? Metric::QuaternionAngles : Metric::Euclidean;
}

EmbedInput embed_input(const features::FeatureSet& set, bool dense) {
  EmbedInput input{&set.X};
  if (dense && set.has_distances()) input.distances = &set.D;
  input.points = &set.distance_input;
  input.metric = metric_of(set.distance);
  return input;
}

// Refuses a map whose estimated memory exceeds what the machine has available.
void check_memory(const ClipMapOptions& options, int frames, int values, int columns, bool dense) {
  const std::optional<std::int64_t> available = available_memory();
  if (!available) return;
  const double bytes = estimate_map_bytes(options.embed.method, frames, values, columns, dense,
                                          options.embed, options.metrics);
  if (bytes <= double(*available)) return;
  std::string message = std::string(embed::method_name(options.embed.method)) + " on " +
                        format_count(frames) + " frames needs ~" + format_bytes(bytes) +
                        (dense ? " dense" : "") + "; available " +
                        format_bytes(double(*available)) + "; ";
  if ((options.embed.method == Method::Pca || options.embed.method == Method::Svd) &&
      !options.metrics) {
    // X itself does not fit: stream_map() never holds it.
    message += "read the clips a clip at a time (--stream, pipeline::stream_map)";
  } else if (dense) {
    message +=
        "use --landmarks (the default above " + std::to_string(options.dense_limit) + " frames)";
  } else {
    message +=
        "use fewer landmarks (--landmarks), a smaller k, or --stride to use every n-th frame";
  }
  throw ParameterError(message);
}

// min(count, n) distinct frames drawn with a fixed seed, in increasing order.
std::vector<int> random_sample(int n, int count) {
  std::vector<int> all(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) all[i] = i;
  if (count >= n) return all;
  std::mt19937_64 random(20061127);
  for (int i = 0; i < count; ++i) {
    std::uniform_int_distribution<int> pick(i, n - 1);
    std::swap(all[i], all[pick(random)]);
  }
  all.resize(static_cast<std::size_t>(count));
  std::sort(all.begin(), all.end());
  return all;
}

}  // namespace

double estimate_map_bytes(Method method, int frames, int values, int columns, bool dense,
                          const embed::EmbedOptions& options, bool metrics) {
  double bytes = embed::estimate_bytes(method, frames, values, columns, dense, options);
  // The metrics' neighbourhood quality reads D on the dense path.
  if (dense && metrics && !embed::reads_distances(method)) bytes += 8.0 * frames * double(frames);
  return bytes;
}

namespace {

double features_share(const ClipMapOptions& options) {
  return embed::reads_distances(options.embed.method) || options.metrics ? 0.3 : 0.05;
}

// The map of `set`, whose D `with_distances` adds when the dense path needs it.
ClipMap map_set(std::shared_ptr<const features::FeatureSet> set,
                const std::function<std::shared_ptr<const features::FeatureSet>(const Control&)>&
                    with_distances,
                const ClipMapOptions& options, const Control& control) {
  const bool reads_d = embed::reads_distances(options.embed.method);
  const double before = features_share(options);
  const double embed_share = options.metrics ? 1.0 - before - 0.2 : 1.0 - before;

  ClipMap result;
  result.features = std::move(set);
  const int frames = result.features->num_samples();
  result.dense = options.path == MapPath::Dense ||
                 (options.path == MapPath::Auto && frames <= options.dense_limit);
  const int values = static_cast<int>(result.features->distance_input.cols());
  // X counts only while its rows are held (map_features drops them for mds, isomap and le).
  const int columns =
      result.features->X.rows() > 0 ? static_cast<int>(result.features->X.cols()) : 0;
  check_memory(options, frames, values, columns, result.dense);
  if (result.dense && (reads_d || options.metrics) && !result.features->has_distances()) {
    result.features = with_distances(control.stage("pose distances", 0.05, before));
  }
  const features::FeatureSet& features = *result.features;
  const EmbedInput input = embed_input(features, result.dense);
  result.embedding = embed::embed(input, options.embed, control.part(before, before + embed_share));

  if (options.metrics) {
    result.metrics = map_metrics(features, result.embedding, options.metrics_k,
                                 control.stage("metrics", before + embed_share, 1.0),
                                 result.dense ? 0 : options.metrics_sample);
  }
  control.finish();
  return result;
}

}  // namespace

ClipMap map_clips(std::span<const Clip> clips, const ClipMapOptions& options,
                  const Control& control, FeatureCache* cache) {
  if (!cache) return map_features(clip_features(clips, options, control), options, control);
  auto set = cache->get(clips, options.features, false, control.stage("features", 0.0, 0.05));
  return map_set(
      std::move(set),
      [&](const Control& c) { return cache->get(clips, options.features, true, c); }, options,
      control);
}

std::shared_ptr<features::FeatureSet> clip_features(std::span<const Clip> clips,
                                                    const ClipMapOptions& options,
                                                    const Control& control) {
  return std::make_shared<features::FeatureSet>(features::build_features(
      clips, options.features, control.stage("features", 0.0, 0.05), features::Distances::Later));
}

ClipMap map_features(std::shared_ptr<features::FeatureSet> features, const ClipMapOptions& options,
                     const Control& control) {
  if (!embed::reads_features(options.embed.method)) {
    // X's rows go (0.96 GB at 10⁶ frames, for a map that reads only the points or D); its
    // column count stays, which a map file records.
    features->X.resize(0, features->X.cols());
    release_freed_memory();
  }
  return map_set(
      features,
      [&](const Control& c) {
        features::add_distances(*features, c);
        return features;
      },
      options, control);
}

embed::MapModel map_model(ClipMap map, const ClipMapOptions& options) {
  if (map.model) return std::move(*map.model);
  return embed::make_model(embed_input(*map.features, map.dense), options.embed,
                           std::move(map.embedding));
}

std::shared_ptr<const embed::GplvmMap> map_gplvm(const ClipMap& map) {
  const Embedding& e = map.embedding;
  if (map.model) return embed::gplvm_map(*map.model, e.coordinates);
  if (e.gplvm_kernel.size() != 4 ||  // only a gplvm map has its kernel
      e.coordinates.cols() != 2 || !map.features ||
      map.features->X.rows() != e.coordinates.rows()) {
    return nullptr;
  }
  const Eigen::MatrixXd& X = map.features->X;
  const Eigen::MatrixXd Y = X.rowwise() - X.colwise().mean();
  const embed::GplvmKernel kernel{e.gplvm_kernel[0], e.gplvm_kernel[1], e.gplvm_kernel[2],
                                  e.gplvm_kernel[3]};
  return std::make_shared<const embed::GplvmMap>(
      embed::gplvm_predictive(Y, e.coordinates, e.gplvm_inducing, kernel), e.coordinates, &Y);
}

MapMetrics map_metrics(const features::FeatureSet& features, const Embedding& embedding, int k,
                       const Control& control, int sample) {
  MapMetrics m;
  if (sample <= 0 && features.has_distances()) {
    m.neighborhood = neighborhood_quality(features.D, embedding.coordinates, k, control);
  } else {
    if (features.distance_input.rows() != features.num_samples()) {
      throw ParameterError(
          "metrics: the feature set has neither the distance matrix D nor the points it is "
          "computed from");
    }
    const std::vector<int> frames =
        random_sample(features.num_samples(), sample > 0 ? sample : features.num_samples());
    RowMatrix points(static_cast<Eigen::Index>(frames.size()), features.distance_input.cols());
    Eigen::MatrixXd Y(points.rows(), embedding.coordinates.cols());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      points.row(Eigen::Index(i)) = features.distance_input.row(frames[i]);
      Y.row(Eigen::Index(i)) = embedding.coordinates.row(frames[i]);
    }
    const Control distances_control = control.part(0.0, 0.5);
    const Eigen::MatrixXd D = features.distance == features::DistanceKind::Geodesic
                                  ? features::geodesic_distances(points, distances_control)
                                  : features::pairwise_distances(points, distances_control);
    m.neighborhood = neighborhood_quality(D, Y, k, control.part(0.5, 1.0));
    m.sample = frames.size() < std::size_t(features.num_samples()) ? int(frames.size()) : 0;
  }
  m.stress = embedding.stress;
  m.jump = jump_score(embedding.coordinates);
  m.degenerate = degeneracy(embedding);
  return m;
}

std::string degeneracy(const Embedding& embedding) {
  if (embedding.connecting_edges > 0) {
    return "the k-NN graph fell into " + std::to_string(embedding.graph_components) +
           " components joined by " + std::to_string(embedding.connecting_edges) +
           " bridges; raise k";
  }
  // Spread of each axis around its mean: a map whose last axis holds < 0.1 % of the first's has
  // collapsed onto fewer axes.
  const Eigen::MatrixXd& Y = embedding.coordinates;
  if (Y.rows() < 2 || Y.cols() < 2) return {};
  const Eigen::RowVectorXd spread =
      (Y.rowwise() - Y.colwise().mean()).colwise().norm() / std::sqrt(double(Y.rows()));
  if (spread.maxCoeff() == 0.0) return "every frame lands on one point";
  if (spread.minCoeff() < 1e-3 * spread.maxCoeff()) {
    return "the map collapses onto " + std::to_string(Y.cols() - 1) + " axis" +
           (Y.cols() - 1 == 1 ? "" : "es");
  }
  return {};
}

std::string describe_parameters(const Embedding& e, const ClipMapOptions& options) {
  const features::FeatureOptions& f = options.features;
  std::string s = "method=" + std::string(embed::method_name(e.method)) +
                  " dims=" + std::to_string(e.coordinates.cols());
  if (embed::uses_graph(e.method)) s += " k=" + std::to_string(e.k_used);
  if (e.method == Method::LaplacianEigenmap) {
    s += " heat=" + (e.heat_used > 0 ? fmt(e.heat_used, "%.6g") : std::string("0 (weights 1)"));
    if (!options.embed.heat) s += " (auto)";
  }
  if (e.method == Method::Lle) s += " reg=" + fmt(options.embed.reg, "%g");
  if (e.method == Method::Umap) {
    // The default epochs follow the frames laid out: the distinct poses when frames repeat.
    const int laid_out =
        int(e.fitted_frames.empty() ? e.coordinates.rows() : Eigen::Index(e.fitted_frames.size()));
    s += " min_dist=" + fmt(options.embed.min_dist, "%g") + " epochs=" +
         std::to_string(options.embed.epochs > 0 ? options.embed.epochs
                                                 : embed::umap_default_epochs(laid_out)) +
         " seed=" + std::to_string(options.embed.seed);
  }
  if (e.method == Method::Pca && options.embed.standardize) s += " standardize";
  s += " features=" + std::string(features::feature_kind_name(f.features)) +
       " distance=" + std::string(features::distance_kind_name(f.distance));
  s += " up=" + std::string(axis_name(f.up));
  if (f.joints != features::JointSelection::All) {
    s += " joints=" + std::string(features::joint_selection_name(f.joints));
  }
  if (!f.exclude.empty()) s += " exclude=" + f.exclude;
  if (f.first_frame != 0 || f.end_frame >= 0) {
    s += " frames=" + std::to_string(f.first_frame) + ":" +
         (f.end_frame >= 0 ? std::to_string(f.end_frame) : "");
  }
  if (f.stride != 1) s += " stride=" + std::to_string(f.stride);
  if (f.keep_first) s += " keep-first";
  if (e.from_points && e.landmarks) {
    s += " landmarks=" + std::to_string(e.landmarks->frames.size());
  }
  if (!e.neighbor_search.empty() && e.neighbor_search != "exact") {
    s += " neighbours=" + e.neighbor_search;
  }
  if (e.connecting_edges > 0) {
    s += " components=" + std::to_string(e.graph_components) + " (joined by " +
         std::to_string(e.connecting_edges) + " edges)";
  }
  return s;
}

std::string describe_metrics(const MapMetrics& m) {
  std::string s = "trustworthiness=" + fmt(m.neighborhood.trustworthiness, "%.4f") +
                  " continuity=" + fmt(m.neighborhood.continuity, "%.4f");
  if (m.stress) s += " stress=" + fmt(*m.stress, "%.4f");
  s += " jump=" + fmt(m.jump, "%.3g");
  if (m.sample > 0) {
    s += " (trustworthiness and continuity on a random sample of " + std::to_string(m.sample) +
         " frames";
    if (m.stress) s += ", stress over the landmark pairs";
    s += ")";
  }
  if (!m.degenerate.empty()) s += " (degenerate: " + m.degenerate + "; not comparable)";
  return s;
}

}  // namespace motionmap::pipeline
