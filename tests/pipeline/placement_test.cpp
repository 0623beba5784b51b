// Placing frames on a map that was already made (embed/placement.h, pipeline::map_model), for
// every method on both paths, on real clips: the map's own frames land on their coordinates, a
// frame lands on the same bits however many are placed with it, new clips land among the map's
// samples, and bad input is a clear error.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/embed/placement.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/sample/sample_clip.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::pipeline {
namespace {

using embed::Method;
using ::testing::HasSubstr;

struct Case {
  Method method;
  MapPath path;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(embed::method_name(info.param.method)) +
         (info.param.path == MapPath::Dense ? "_dense" : "_points");
}

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (Method m : embed::all_methods()) {
    // gplvm places a frame at the latent point that best explains it, near but not on its own:
    // GplvmMapsPlaceFrames here, tests/embed/gplvm_test.cpp.
    if (m == Method::Gplvm) continue;
    out.push_back({m, MapPath::Dense});
    if (embed::reads_distances(m)) out.push_back({m, MapPath::Landmarks});
  }
  return out;
}

ClipMapOptions options_for(const Case& c) {
  ClipMapOptions o;
  o.embed.method = c.method;
  o.embed.k = 12;
  o.path = c.path;
  o.embed.landmarks = 64;  // fewer than the frames, so the landmark maps are not the dense ones
  return o;
}

const Clip& clip_64_08() {
  static const Clip clip = io::load_clip(test::shared_file("cmu/64_08.bvh"));
  return clip;
}
const Clip& clip_64_09() {
  static const Clip clip = io::load_clip(test::shared_file("cmu/64_09.bvh"));
  return clip;
}

class Placement : public ::testing::TestWithParam<Case> {};

TEST_P(Placement, OwnFramesLandOnTheirCoordinates) {
  const ClipMapOptions options = options_for(GetParam());
  const ClipMap map = map_clips(std::span(&clip_64_08(), 1), options);
  const embed::MapModel model = map_model(map, options);
  const features::FeatureSet& set = *map.features;
  const Eigen::MatrixXd placed = embed::place(model, {&set.X, &set.distance_input});
  ASSERT_EQ(placed.rows(), map.embedding.coordinates.rows());
  if (GetParam().method == Method::Pca || GetParam().method == Method::Svd) {
    // The projection recomputed from the axes: equal to rounding.
    const double scale = map.embedding.coordinates.cwiseAbs().maxCoeff();
    EXPECT_LE((placed - map.embedding.coordinates).cwiseAbs().maxCoeff(), 1e-10 * scale);
  } else {
    EXPECT_EQ(placed, map.embedding.coordinates);
  }
}

TEST_P(Placement, AFrameLandsTheSameHoweverManyArePlacedWithIt) {
  const ClipMapOptions options = options_for(GetParam());
  const ClipMap map = map_clips(std::span(&clip_64_08(), 1), options);
  const embed::MapModel model = map_model(map, options);
  const features::FeatureSet other = features::build_features(
      std::span(&clip_64_09(), 1), options.features, {}, features::Distances::Later);
  const Eigen::MatrixXd all = embed::place(model, {&other.X, &other.distance_input});
  for (Eigen::Index f : {Eigen::Index(0), other.X.rows() / 2, other.X.rows() - 1}) {
    const Eigen::MatrixXd x = other.X.row(f);
    const RowMatrix p = other.distance_input.row(f);
    const Eigen::MatrixXd one = embed::place(model, {&x, &p});
    ASSERT_EQ(one.rows(), 1);
    EXPECT_EQ(one.row(0), all.row(f)) << "frame " << f;
  }
  // A second golf swing of the same subject lands among the first one's samples: inside their
  // bounding box grown on every side by a quarter of its longest side.
  const Eigen::RowVectorXd lo = map.embedding.coordinates.colwise().minCoeff();
  const Eigen::RowVectorXd hi = map.embedding.coordinates.colwise().maxCoeff();
  const Eigen::RowVectorXd margin =
      Eigen::RowVectorXd::Constant(lo.size(), 0.25 * (hi - lo).maxCoeff());
  EXPECT_TRUE(all.allFinite());
  EXPECT_TRUE(((all.rowwise() - (lo - margin)).array() >= 0.0).all());
  EXPECT_TRUE((((hi + margin) - all.colwise().maxCoeff()).array() >= 0.0).all())
      << "map " << lo << " … " << hi << ", placed " << all.colwise().minCoeff() << " … "
      << all.colwise().maxCoeff();
}

TEST_P(Placement, AKeptSearchPlacesAsAFreshOne) {
  const ClipMapOptions options = options_for(GetParam());
  const ClipMap map = map_clips(std::span(&clip_64_08(), 1), options);
  const embed::MapModel model = map_model(map, options);
  const std::unique_ptr<embed::SampleSearch> search = embed::make_search(model);
  // Only the methods that look up nearest samples have one: pca, svd and landmark mds do not.
  const bool searches = embed::reads_distances(options.embed.method) &&
                        !(options.embed.method == Method::Mds && map.embedding.from_points);
  ASSERT_EQ(search != nullptr, searches);
  const features::FeatureSet other = features::build_features(
      std::span(&clip_64_09(), 1), options.features, {}, features::Distances::Later);
  const embed::PlaceInput input{&other.X, &other.distance_input};
  const Eigen::MatrixXd fresh = embed::place(model, input);
  EXPECT_EQ(embed::place(model, input, {}, search.get()), fresh);
  // Twice with the same search: nothing of one call stays in it.
  EXPECT_EQ(embed::place(model, input, {}, search.get()), fresh);
  if (search) {
    // A search over other samples (a copy of the model holds its own points) is refused.
    const embed::MapModel copy = model;
    EXPECT_THAT(
        test::error_message<ParameterError>([&] { embed::place(copy, input, {}, search.get()); }),
        HasSubstr("the search given is not one over this map's samples"));
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethodAndPath, Placement, ::testing::ValuesIn(all_cases()),
                         case_name);

TEST(Placement, GplvmMapsPlaceFrames) {
  ClipMapOptions options;
  options.embed.method = Method::Gplvm;
  options.embed.max_iterations = 5;
  options.features.stride = 3;
  const ClipMap map = map_clips(std::span(&clip_64_08(), 1), options);
  const Eigen::MatrixXd own = map.embedding.coordinates;
  const embed::MapModel model = map_model(map, options);
  const Eigen::MatrixXd X = map.features->X;
  const Eigen::MatrixXd placed = embed::place(model, {.features = &X});
  ASSERT_EQ(placed.rows(), own.rows());
  EXPECT_TRUE(placed.allFinite());
  // Within the map's extent (its latent points have unit variance per axis).
  EXPECT_LE(placed.cwiseAbs().maxCoeff(), own.cwiseAbs().maxCoeff() + 1.0);
  EXPECT_THAT(test::error_message<ParameterError>([&] { embed::place(model, {}); }),
              HasSubstr("this map places frames by their features X; none given"));
}

TEST(Placement, BadInputIsAClearError) {
  ClipMapOptions options;
  options.embed.method = Method::Isomap;
  const ClipMap map = map_clips(std::span(&clip_64_08(), 1), options);
  const embed::MapModel model = map_model(map, options);
  const features::FeatureSet& set = *map.features;
  EXPECT_THAT(test::error_message<ParameterError>([&] {
                embed::place(model, {&set.X, nullptr});
              }),
              HasSubstr("place (isomap): this map places frames by their points; none given"));
  const RowMatrix narrow = set.distance_input.leftCols(6);
  EXPECT_THAT(test::error_message<ParameterError>([&] {
                embed::place(model, {nullptr, &narrow});
              }),
              HasSubstr("the new frames' points have 6 values per frame; the map's have"));
  RowMatrix bad = set.distance_input.topRows(3);
  bad(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(test::error_message<ParameterError>([&] {
                embed::place(model, {nullptr, &bad});
              }),
              HasSubstr("frame 1's points are not all finite"));
}

}  // namespace
}  // namespace motionmap::pipeline

namespace motionmap::pipeline {
namespace {

TEST(MapPaths, DenseUpToTheLimitThenPointsUnlessForced) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  ClipMapOptions options;
  options.embed.method = embed::Method::Mds;
  EXPECT_TRUE(map_clips(std::span(&clip, 1), options).dense);
  options.dense_limit = 100;
  const ClipMap above = map_clips(std::span(&clip, 1), options);
  EXPECT_FALSE(above.dense);
  EXPECT_TRUE(above.embedding.from_points);
  EXPECT_FALSE(above.features->has_distances());  // no #frames² matrix was made
  EXPECT_THAT(describe_parameters(above.embedding, options), HasSubstr(" landmarks=256"));
  options.path = MapPath::Dense;
  EXPECT_TRUE(map_clips(std::span(&clip, 1), options).dense);
  options.path = MapPath::Landmarks;
  options.dense_limit = kDenseFrameLimit;
  EXPECT_FALSE(map_clips(std::span(&clip, 1), options).dense);
}

TEST(MapPaths, AMapThatCannotFitIsRefusedBeforeItIsAllocated) {
  // 60 000 frames: the dense isomap would need two 60 000² matrices (~58 GB).
  const Clip clip =
      sample::make_sample_clip(sample::SampleKind::Walk, {.fps = 120, .seconds = 500});
  ClipMapOptions options;
  options.embed.method = embed::Method::Isomap;
  options.path = MapPath::Dense;
  EXPECT_THAT(test::error_message<ParameterError>([&] { map_clips(std::span(&clip, 1), options); }),
              HasSubstr("isomap on 60 000 frames needs ~58 GB dense; available "));
  EXPECT_THAT(test::error_message<ParameterError>([&] { map_clips(std::span(&clip, 1), options); }),
              HasSubstr("; use --landmarks (the default above 10000 frames)"));
  EXPECT_NEAR(
      estimate_map_bytes(embed::Method::Isomap, 60000, 100, 120, true, options.embed, false),
      57.6e9, 0.2e9);
  EXPECT_LT(estimate_map_bytes(embed::Method::Isomap, 60000, 100, 120, false, options.embed, false),
            1e9);
}

}  // namespace
}  // namespace motionmap::pipeline
