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
#include "motionmap/embed/placement.h"
#include "motionmap/features/features.h"
#include "motionmap/pipeline/feature_cache.h"

namespace motionmap::pipeline {

/// Up to this many frames a map is dense (exact, from D) unless ClipMapOptions::path says
/// otherwise; above, it takes the points path (embed.h, "Two paths").
constexpr int kDenseFrameLimit = 10000;

/// Which of embed's two paths a map takes.
enum class MapPath {
  Auto,       ///< dense up to ClipMapOptions::dense_limit frames, points path above
  Dense,      ///< always from D (exact; #frames² memory)
  Landmarks,  ///< always the points path (landmarks, sparse graphs)
};

/// The paths' names, as options and map files write them.
inline constexpr EnumName<MapPath> kMapPathNames[] = {
    {MapPath::Auto, "auto"}, {MapPath::Dense, "dense"}, {MapPath::Landmarks, "landmarks"}};
/// "auto", "dense", "landmarks".
std::string_view map_path_name(MapPath path);
/// The path named `name` (map_path_name's names); nullopt for anything else.
std::optional<MapPath> parse_map_path(std::string_view name);

struct ClipMapOptions {
  features::FeatureOptions features;
  embed::EmbedOptions embed;
  bool metrics = false;  ///< compute MapMetrics (dense: O(#frames²), needs D)
  int metrics_k = 10;    ///< neighbours for trustworthiness and continuity
  MapPath path = MapPath::Auto;
  int dense_limit = kDenseFrameLimit;
  /// Points path: the metrics are measured on a random sample (seeded, so repeatable) of this
  /// many frames instead of all of them.
  int metrics_sample = 2000;
};

/// Quality of a map (see metrics.h for the definitions).
struct MapMetrics {
  embed::NeighborhoodQuality neighborhood;  ///< at ClipMapOptions::metrics_k, against D
  std::optional<double> stress;             ///< MDS and Isomap: against their target distances
  double jump = 0.0;                        ///< 95th percentile ÷ median of consecutive map steps
  /// Frames the neighbourhood quality was measured on: 0 = all of them; otherwise a random
  /// sample of that many (the points path), and the stress is over the landmark pairs.
  int sample = 0;
  /// Why these figures do not rank the map against others (empty when they do): a k-NN graph
  /// that fell apart and was joined by bridges, or a map that collapsed onto fewer axes. Such
  /// a map keeps neighbours trivially (a line of the components strung together) and its
  /// trustworthiness can beat every honest map.
  std::string degenerate;
};

struct ClipMap {
  /// The samples and their features, shared with the other maps of the same FeatureCache. D is
  /// there when the method or the metrics needed it (has_distances()).
  std::shared_ptr<const features::FeatureSet> features;
  embed::Embedding embedding;
  std::optional<MapMetrics> metrics;
  /// Whether the map was computed from D (the dense path) or from the points.
  bool dense = true;
  /// A map streamed from its clips' files (stream_map.h), whose features hold no rows: what
  /// placing new frames needs, kept as the map was made (map_model() returns it).
  std::optional<embed::MapModel> model;
};

/// Builds the features of `clips` (or takes them from `cache`) and maps them. D is built only
/// on the dense path, when the method or the metrics read it. Without a cache this is
/// map_features(clip_features(…)): the result's X then has no rows for mds, isomap and le. Before
/// anything of #frames² or #frames·L size is allocated, its memory is estimated and compared with
/// what the machine has available. `control` hears the stages "features", "pose distances", the
/// method's own stages and "metrics".
/// @throws as build_features() and embed(); ParameterError if metrics are asked for a clip too
///   short for metrics_k, or if the map would need more memory than is available (the message
///   gives the estimate, what is available and the option that would fit); Cancelled.
ClipMap map_clips(std::span<const Clip> clips, const ClipMapOptions& options,
                  const Control& control = {}, FeatureCache* cache = nullptr);

/// map_clips() without a cache, in its two steps, for a caller that frees the clips' poses in
/// between (they are most of the memory of a large library: 1.7 GB at 10⁶ frames of 31 joints).
/// First the features of `clips` (map_clips' "features" stage)…
std::shared_ptr<features::FeatureSet> clip_features(std::span<const Clip> clips,
                                                    const ClipMapOptions& options,
                                                    const Control& control = {});

/// …then the map of them, which reads `features` only: the same map as map_clips() of the clips.
/// Adds D to `features` on the dense path when the method or the metrics read it, and drops the
/// rows of X when the method does not read it (mds, isomap, le: X.cols() stays).
ClipMap map_features(std::shared_ptr<features::FeatureSet> features, const ClipMapOptions& options,
                     const Control& control = {});

/// The metrics of `embedding`, a map of `features`: neighbourhood quality at k against D, the
/// embedding's stress, the jump score. With `sample` > 0 (or when `features` has no D), the
/// neighbourhood quality is measured on a random sample of min(sample, #frames) frames, with
/// their distances computed from the features' points (MapMetrics::sample says how many).
/// @throws ParameterError if the clip (or sample) is too short for k, or `features` has neither
///   D nor its points; Cancelled.
MapMetrics map_metrics(const features::FeatureSet& features, const embed::Embedding& embedding,
                       int k = 10, const Control& control = {}, int sample = 0);

/// Why the metrics of `embedding` cannot rank it against other maps (MapMetrics::degenerate):
/// its graph needed bridges, an axis holds < 0.1 % of the largest axis's spread (RMS about the
/// mean), or every frame lands on one point. Empty otherwise.
std::string degeneracy(const embed::Embedding& embedding);

/// Estimated peak memory of mapping `frames` frames with `method` on the dense path (dense =
/// true) or the points path; `values` is the width of the points (features::FeatureSet::
/// distance_input) and `columns` of X (0 when X's rows are not held: map_features drops them for
/// the methods that do not read X). An estimate (within a factor of about 1.5), for refusing
/// requests that cannot fit before they start.
double estimate_map_bytes(embed::Method method, int frames, int values, int columns, bool dense,
                          const embed::EmbedOptions& options, bool metrics);

/// What placing new frames on `map` needs (embed/placement.h), from the map and its features, or
/// map.model, kept by a streamed map; takes the embedding's coordinates and landmark fit (pass
/// std::move(map) when done with it). @throws as embed::make_model().
embed::MapModel map_model(ClipMap map, const ClipMapOptions& options);

/// A gplvm map's GP over its coordinates (embed::gplvm_map): what its blends and its rule of
/// where it is valid use (synth::BlendOptions::gplvm). Null for other maps, maps of more than 2
/// dimensions, and a streamed map without its model. @throws as embed::GplvmMap.
std::shared_ptr<const embed::GplvmMap> map_gplvm(const ClipMap& map);

/// The effective parameters of a map in one line, for CSV comments, titles and status bars:
/// "method=isomap dims=2 k=20 features=quat distance=pointcloud up=y".
std::string describe_parameters(const embed::Embedding& embedding, const ClipMapOptions& options);

/// The metrics as one line: "trustworthiness=0.981 continuity=0.975 stress=0.12 jump=3.4".
std::string describe_metrics(const MapMetrics& metrics);

}  // namespace motionmap::pipeline
