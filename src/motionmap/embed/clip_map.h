#pragma once
// The whole mapping pipeline for clips: features (X, D) → embedding → quality metrics. What the
// CLI's `map` and `figure` and the app run; one call, one progress bar, one cancel button.
//
//   motionmap::embed::ClipMapOptions opt;
//   opt.embed.method = motionmap::embed::Method::Isomap;
//   auto result = motionmap::embed::map_clips(clips, opt);
//   // result.embedding.coordinates row i ↔ clip result.features.clip_of[i],
//   //                                   file frame result.features.frame_of[i]
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "motionmap/embed/embed.h"
#include "motionmap/embed/metrics.h"
#include "motionmap/features/features.h"

namespace motionmap::embed {

struct ClipMapOptions {
  features::FeatureOptions features;  ///< its progress/cancel are ignored: use the ones below
  EmbedOptions embed;                 ///< its progress/cancel are ignored: use the ones below
  bool metrics = false;               ///< compute MapMetrics (O(#frames²))
  int metrics_k = 10;                 ///< neighbours for trustworthiness and continuity
  /// Overall fraction done (0…1) and the current stage, from the calling thread.
  std::function<void(double fraction, std::string_view stage)> progress;
  /// Polled during long stages; true stops the work with motionmap::Cancelled.
  std::function<bool()> cancel;
};

/// Quality of a map (see metrics.h for the definitions).
struct MapMetrics {
  NeighborhoodQuality neighborhood;  ///< at ClipMapOptions::metrics_k, against D
  std::optional<double> stress;      ///< MDS and Isomap: against their target distances
  double jump = 0.0;                 ///< 95th percentile ÷ median of consecutive map steps
};

struct ClipMap {
  features::FeatureSet features;
  Embedding embedding;
  std::optional<MapMetrics> metrics;
};

/// Builds the features of `clips` and maps them. @throws as build_features() and embed(), and
/// ParameterError if metrics are asked for a clip too short for metrics_k.
ClipMap map_clips(std::span<const Clip> clips, const ClipMapOptions& options);

/// The metrics of `embedding`, a map of `features`: neighbourhood quality at k against D, the
/// embedding's stress, the jump score. @throws ParameterError if the clip is too short for k.
MapMetrics map_metrics(const features::FeatureSet& features, const Embedding& embedding, int k = 10);

/// The effective parameters of a map in one line, for CSV comments, titles and status bars:
/// "method=isomap dims=2 k=20 features=quat distance=pointcloud up=y".
std::string describe_parameters(const Embedding& embedding, const ClipMapOptions& options);

/// The metrics as one line: "trustworthiness=0.981 continuity=0.975 stress=0.12 jump=3.4".
std::string describe_metrics(const MapMetrics& metrics);

}  // namespace motionmap::embed
