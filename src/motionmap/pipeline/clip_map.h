#pragma once
// The whole mapping pipeline for clips: features (X, and D when the method or the metrics read
// it) → embedding → quality metrics. What the CLI's `map` and `figure` and the app run; one
// call, one progress bar, one cancel button (the Control).
//
//   motionmap::pipeline::ClipMapOptions opt;
//   opt.embed.method = motionmap::embed::Method::Isomap;
//   auto result = motionmap::pipeline::map_clips(clips, opt, control);
//   // result.embedding.coordinates row i ↔ clip result.features->clip_of[i],
//   //                                   file frame result.features->frame_of[i]
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/metrics.h"
#include "motionmap/features/features.h"
#include "motionmap/pipeline/feature_cache.h"

namespace motionmap::pipeline {

struct ClipMapOptions {
  features::FeatureOptions features;
  embed::EmbedOptions embed;
  bool metrics = false;  ///< compute MapMetrics (O(#frames²), needs D)
  int metrics_k = 10;    ///< neighbours for trustworthiness and continuity
};

/// Quality of a map (see metrics.h for the definitions).
struct MapMetrics {
  embed::NeighborhoodQuality neighborhood;  ///< at ClipMapOptions::metrics_k, against D
  std::optional<double> stress;             ///< MDS and Isomap: against their target distances
  double jump = 0.0;                        ///< 95th percentile ÷ median of consecutive map steps
};

struct ClipMap {
  /// The samples and their features, shared with the other maps of the same FeatureCache. D is
  /// there when the method or the metrics needed it (has_distances()).
  std::shared_ptr<const features::FeatureSet> features;
  embed::Embedding embedding;
  std::optional<MapMetrics> metrics;
};

/// Builds the features of `clips` (or takes them from `cache`) and maps them. D is built only
/// when the method or the metrics read it. `control` hears the stages "features", "pose
/// distances", the method's own stages and "metrics".
/// @throws as build_features() and embed(), and ParameterError if metrics are asked for a clip
///   too short for metrics_k; Cancelled.
ClipMap map_clips(std::span<const Clip> clips, const ClipMapOptions& options,
                  const Control& control = {}, FeatureCache* cache = nullptr);

/// The metrics of `embedding`, a map of `features` (which must hold D): neighbourhood quality
/// at k against D, the embedding's stress, the jump score.
/// @throws ParameterError if the clip is too short for k or `features` has no D; Cancelled.
MapMetrics map_metrics(const features::FeatureSet& features, const embed::Embedding& embedding,
                       int k = 10, const Control& control = {});

/// The effective parameters of a map in one line, for CSV comments, titles and status bars:
/// "method=isomap dims=2 k=20 features=quat distance=pointcloud up=y".
std::string describe_parameters(const embed::Embedding& embedding, const ClipMapOptions& options);

/// The metrics as one line: "trustworthiness=0.981 continuity=0.975 stress=0.12 jump=3.4".
std::string describe_metrics(const MapMetrics& metrics);

}  // namespace motionmap::pipeline
