// The metrics of a degenerate map (pipeline::degeneracy): a graph that fell apart and was joined
// by bridges, or a map collapsed onto fewer axes, keeps neighbours trivially; its figures say so
// and are not offered for ranking against honest maps.
#include "motionmap/pipeline/clip_map.h"

#include <gtest/gtest.h>

#include <span>
#include <string>

#include "motionmap/io/load.h"
#include "support/test_data.h"

namespace motionmap::pipeline {
namespace {

MapMetrics metrics_of(const Clip& clip, embed::Method method, int k) {
  ClipMapOptions options;
  options.embed.method = method;
  options.embed.k = k;
  options.metrics = true;
  return *map_clips(std::span(&clip, 1), options).metrics;
}

TEST(DegenerateMaps, ABridgedGraphSaysSoNextToItsMetrics) {
  const Clip clip = io::load_clip(test::shared_file("cmu/64_08.bvh"));
  // k = 1: the graph falls into 85 components; the map strings them into a line whose
  // trustworthiness (0.999) beats every honest map's.
  const MapMetrics bridged = metrics_of(clip, embed::Method::Isomap, 1);
  EXPECT_EQ(bridged.degenerate,
            "the k-NN graph fell into 85 components joined by 84 bridges; raise k");
  EXPECT_NE(describe_metrics(bridged).find("(degenerate: the k-NN graph fell into 85 components"),
            std::string::npos);
  const MapMetrics honest = metrics_of(clip, embed::Method::Isomap, 20);
  EXPECT_EQ(honest.degenerate, "");
  EXPECT_EQ(describe_metrics(honest).find("degenerate"), std::string::npos);
}

TEST(DegenerateMaps, AMapCollapsedOntoOneAxisSaysSo) {
  embed::Embedding e;
  e.coordinates.resize(50, 2);
  for (int f = 0; f < 50; ++f) e.coordinates.row(f) << f, 1e-6 * (f % 3);
  EXPECT_EQ(degeneracy(e), "the map collapses onto 1 axis");
  e.coordinates.col(1) *= 1e5;  // 0.6 % of the first axis's spread: thin, not collapsed
  EXPECT_EQ(degeneracy(e), "");
  e.coordinates.setZero();  // a static clip's map
  EXPECT_EQ(degeneracy(e), "every frame lands on one point");
}

}  // namespace
}  // namespace motionmap::pipeline
