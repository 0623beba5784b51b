#include "motionmap/embed/clip_map.h"

#include <cstdio>

#include "motionmap/core/error.h"

namespace motionmap::embed {

namespace {
std::string fmt(double v, const char* format = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

bool uses_graph(Method m) {
  return m == Method::Isomap || m == Method::LaplacianEigenmap || m == Method::Lle;
}
}  // namespace

ClipMap map_clips(std::span<const Clip> clips, const ClipMapOptions& options) {
  // Stage weights of the overall progress: D is O(F²·P), the embedding varies, metrics O(F² log).
  const double d_share = 0.3, embed_share = options.metrics ? 0.5 : 0.7;
  auto report = [&](double fraction, std::string_view stage) {
    if (options.progress) options.progress(fraction, stage);
  };

  ClipMap result;
  features::FeatureOptions fopt = options.features;
  fopt.progress = [&](double f) { report(d_share * f, "pose distances"); };
  fopt.cancel = options.cancel;
  result.features = features::build_features(clips, fopt);

  EmbedOptions eopt = options.embed;
  eopt.progress = [&](double f, std::string_view stage) { report(d_share + embed_share * f, stage); };
  eopt.cancel = options.cancel;
  const EmbedInput input{&result.features.X, &result.features.D};
  result.embedding = embed(input, eopt);

  if (options.metrics) {
    if (options.cancel && options.cancel()) throw Cancelled();
    report(d_share + embed_share, "metrics");
    result.metrics = map_metrics(result.features, result.embedding, options.metrics_k);
  }
  report(1.0, "done");
  return result;
}

MapMetrics map_metrics(const features::FeatureSet& features, const Embedding& embedding, int k) {
  MapMetrics m;
  m.neighborhood = neighborhood_quality(features.D, embedding.coordinates, k);
  m.stress = embedding.stress;
  m.jump = jump_score(embedding.coordinates);
  return m;
}

std::string describe_parameters(const Embedding& e, const ClipMapOptions& options) {
  const features::FeatureOptions& f = options.features;
  std::string s = "method=" + std::string(method_name(e.method)) +
                  " dims=" + std::to_string(e.coordinates.cols());
  if (uses_graph(e.method)) s += " k=" + std::to_string(e.k_used);
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
    s += " frames=" + std::to_string(f.first_frame) + ":" + (f.end_frame >= 0 ? std::to_string(f.end_frame) : "");
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

}  // namespace motionmap::embed
