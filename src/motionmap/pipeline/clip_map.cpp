#include "motionmap/pipeline/clip_map.h"

#include <cstdio>

#include "motionmap/core/error.h"

namespace motionmap::pipeline {

using embed::Embedding;
using embed::EmbedInput;
using embed::jump_score;
using embed::Method;
using embed::neighborhood_quality;

namespace {
std::string fmt(double v, const char* format = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

bool needs_distances(Method method) {
  return method != Method::Pca && method != Method::Svd;
}

ClipMap map_clips(std::span<const Clip> clips, const ClipMapOptions& options,
                  const Control& control, FeatureCache* cache) {
  const bool need_d = embed::reads_distances(options.embed.method) || options.metrics;
  // Shares of the overall progress: D is O(F²·P); without it the features are quick.
  const double features_share = need_d ? 0.3 : 0.05;
  const double embed_share = options.metrics ? 1.0 - features_share - 0.2 : 1.0 - features_share;
  const Control features_control =
      control.stage(need_d ? "pose distances" : "features", 0.0, features_share);

  ClipMap result;
  if (cache) {
    result.features = cache->get(clips, options.features, need_d, features_control);
  } else {
    result.features = std::make_shared<const features::FeatureSet>(
        features::build_features(clips, options.features, features_control,
                                 need_d ? features::Distances::Now : features::Distances::Later));
  }
  const features::FeatureSet& set = *result.features;
  const EmbedInput input{&set.X, set.has_distances() ? &set.D : nullptr};
  result.embedding = embed::embed(input, options.embed,
                                  control.part(features_share, features_share + embed_share));

  if (options.metrics) {
    result.metrics = map_metrics(set, result.embedding, options.metrics_k,
                                 control.stage("metrics", features_share + embed_share, 1.0));
  }
  control.finish();
  return result;
}

MapMetrics map_metrics(const features::FeatureSet& features, const Embedding& embedding, int k,
                       const Control& control) {
  if (!features.has_distances()) {
    throw ParameterError(
        "metrics: the feature set has no distance matrix D (built with "
        "Distances::Later); add_distances() first");
  }
  MapMetrics m;
  m.neighborhood = neighborhood_quality(features.D, embedding.coordinates, k, control);
  m.stress = embedding.stress;
  m.jump = jump_score(embedding.coordinates);
  return m;
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
  if (e.method == Method::Pca && options.embed.standardize) s += " standardize";
  s += " features=" + std::string(features::feature_kind_name(f.features)) +
       " distance=" + std::string(features::distance_kind_name(f.distance));
  s += " up=" + std::string(f.up == Axis::Z ? "z" : "y");
  if (!f.exclude.empty()) s += " exclude=" + f.exclude;
  if (f.first_frame != 0 || f.end_frame >= 0) {
    s += " frames=" + std::to_string(f.first_frame) + ":" +
         (f.end_frame >= 0 ? std::to_string(f.end_frame) : "");
  }
  if (f.stride != 1) s += " stride=" + std::to_string(f.stride);
  if (f.keep_first) s += " keep-first";
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
  return s;
}

}  // namespace motionmap::pipeline
