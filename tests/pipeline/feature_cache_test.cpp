// The pipeline builds D only for the methods that read it, and the feature cache builds each
// feature set once per feature key, whichever method asks.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <span>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/feature_cache.h"
#include "motionmap/sample/sample_clip.h"

namespace motionmap::pipeline {
namespace {

using embed::Method;
using ::testing::HasSubstr;

ClipMapOptions options_for(Method method) {
  ClipMapOptions options;
  options.embed.method = method;
  options.features.stride = 2;
  options.embed.max_iterations = 20;  // gplvm: a few steps are enough to compare two runs
  return options;
}

TEST(FeatureCache, PcaAndSvdBuildNoDistanceMatrix) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  for (Method m : {Method::Pca, Method::Svd}) {
    const ClipMap map = map_clips(std::span(&clip, 1), options_for(m));
    EXPECT_FALSE(map.features->has_distances()) << embed::method_name(m);
    EXPECT_EQ(map.features->D.size(), 0);
  }
  ClipMapOptions with_metrics = options_for(Method::Pca);
  with_metrics.metrics = true;  // the metrics read D
  EXPECT_TRUE(map_clips(std::span(&clip, 1), with_metrics).features->has_distances());
  EXPECT_TRUE(map_clips(std::span(&clip, 1), options_for(Method::Mds)).features->has_distances());
}

TEST(FeatureCache, OneSetPerFeatureKeyWithDAddedOnce) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  const std::span<const Clip> clips(&clip, 1);
  FeatureCache cache;
  const ClipMap pca = map_clips(clips, options_for(Method::Pca), {}, &cache);
  EXPECT_EQ(cache.size(), 1);
  EXPECT_FALSE(pca.features->has_distances());

  const ClipMap isomap = map_clips(clips, options_for(Method::Isomap), {}, &cache);
  EXPECT_EQ(cache.size(), 1);  // the same key: D added to a copy, the PCA map's set unchanged
  EXPECT_TRUE(isomap.features->has_distances());
  EXPECT_FALSE(pca.features->has_distances());
  EXPECT_EQ(isomap.features->X, pca.features->X);

  // Every later request of the key gets that set, D and all, and no new one is built.
  const ClipMap svd = map_clips(clips, options_for(Method::Svd), {}, &cache);
  const ClipMap lle = map_clips(clips, options_for(Method::Lle), {}, &cache);
  EXPECT_EQ(svd.features, isomap.features);
  EXPECT_EQ(lle.features, isomap.features);
  EXPECT_EQ(cache.size(), 1);

  // Other features are another key.
  ClipMapOptions positions = options_for(Method::Pca);
  positions.features.features = features::FeatureKind::Positions;
  map_clips(clips, positions, {}, &cache);
  EXPECT_EQ(cache.size(), 2);
  cache.clear();
  EXPECT_EQ(cache.size(), 0);
  EXPECT_TRUE(isomap.features->has_distances());  // sets handed out stay valid
}

TEST(FeatureCache, MapsFromTheCacheEqualMapsWithout) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Walk);
  const std::span<const Clip> clips(&clip, 1);
  FeatureCache cache;
  for (Method m : embed::all_methods()) {
    const ClipMap cached = map_clips(clips, options_for(m), {}, &cache);
    const ClipMap fresh = map_clips(clips, options_for(m));
    EXPECT_EQ(cached.embedding.coordinates, fresh.embedding.coordinates) << embed::method_name(m);
    EXPECT_EQ(cached.features->notes, fresh.features->notes) << embed::method_name(m);
  }
}

TEST(FeatureCache, MetricsOfASetWithoutDAreMeasuredOnItsPoints) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  const ClipMap pca = map_clips(std::span(&clip, 1), options_for(Method::Pca));
  ASSERT_FALSE(pca.features->has_distances());
  // Without D, every frame's distances come from the points: the same numbers as from D.
  const MapMetrics from_points = map_metrics(*pca.features, pca.embedding);
  features::FeatureSet with_d = *pca.features;
  features::add_distances(with_d);
  const MapMetrics from_d = map_metrics(with_d, pca.embedding);
  EXPECT_EQ(from_points.neighborhood.trustworthiness, from_d.neighborhood.trustworthiness);
  EXPECT_EQ(from_points.neighborhood.continuity, from_d.neighborhood.continuity);
  EXPECT_EQ(from_points.sample, 0);
  // A sample says how many frames it measured.
  const MapMetrics sampled = map_metrics(with_d, pca.embedding, 10, {}, 200);
  EXPECT_EQ(sampled.sample, 200);
  EXPECT_GT(sampled.neighborhood.trustworthiness, 0.9);
  EXPECT_THAT(describe_metrics(sampled), HasSubstr("on a random sample of 200 frames"));
  // Neither D nor points: a clear error.
  features::FeatureSet bare = *pca.features;
  bare.distance_input = RowMatrix();
  try {
    map_metrics(bare, pca.embedding);
    FAIL() << "metrics without D or points did not throw";
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("neither the distance matrix D nor the points"));
  }
}

TEST(FeatureKey, DiffersExactlyWhenTheSamplesOrMatricesDo) {
  features::FeatureOptions a;
  features::FeatureOptions b = a;
  EXPECT_EQ(feature_key(a), feature_key(b));
  b.stride = 2;
  EXPECT_NE(feature_key(a), feature_key(b));
  b = a;
  b.distance = features::DistanceKind::Geodesic;
  EXPECT_NE(feature_key(a), feature_key(b));
  b = a;
  b.joints = features::JointSelection::Common;  // other joints, other X and D
  EXPECT_NE(feature_key(a), feature_key(b));
  b = a;
  b.exclude = "x|1";  // a pattern holding the key's separator is still its own key
  features::FeatureOptions c = a;
  c.exclude = "x";
  c.keep_first = true;
  EXPECT_NE(feature_key(b), feature_key(c));
}

}  // namespace
}  // namespace motionmap::pipeline
