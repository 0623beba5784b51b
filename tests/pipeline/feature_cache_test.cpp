// The pipeline builds D only for the methods that read it, and the feature cache builds each
// feature set once per feature key, whichever method asks.
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

ClipMapOptions options_for(Method method) {
  ClipMapOptions options;
  options.embed.method = method;
  options.features.stride = 2;
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

TEST(FeatureCache, MetricsOfASetWithoutDAreAClearError) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  const ClipMap pca = map_clips(std::span(&clip, 1), options_for(Method::Pca));
  ASSERT_FALSE(pca.features->has_distances());
  try {
    map_metrics(*pca.features, pca.embedding);
    FAIL() << "metrics without D did not throw";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("has no distance matrix D"), std::string::npos)
        << e.what();
  }
  features::FeatureSet with_d = *pca.features;
  features::add_distances(with_d);
  EXPECT_NO_THROW(map_metrics(with_d, pca.embedding));
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
