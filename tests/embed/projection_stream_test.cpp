// PCA and SVD accumulated a block of rows at a time (embed/projection_stream.h) against embed()
// on the whole X: the same map within 1e-10 (Procrustes disparity and every coordinate, relative
// to the map's extent), each axis with the same sign, the same eigenvalues, warnings and
// placement model; on real clips and on a synthetic X with a far-off and a constant column.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <span>
#include <string>
#include <vector>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/placement.h"
#include "motionmap/embed/projection_stream.h"
#include "motionmap/features/features.h"
#include "motionmap/io/load.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::embed {
namespace {

using ::testing::HasSubstr;

constexpr double kTolerance = 1e-10;

struct Streamed {
  Embedding map;
  MapModel model;
};

// X given to a ProjectionStream in blocks of the given sizes (cycled), twice.
Streamed stream_blocks(const Eigen::MatrixXd& X, const EmbedOptions& options,
                       const std::vector<Eigen::Index>& sizes) {
  ProjectionStream stream(options);
  auto each_block = [&](const auto& visit) {
    Eigen::Index at = 0;
    for (std::size_t b = 0; at < X.rows(); ++b) {
      const Eigen::Index rows = std::min(sizes[b % sizes.size()], X.rows() - at);
      visit(at, rows);
      at += rows;
    }
  };
  each_block(
      [&](Eigen::Index at, Eigen::Index rows) { stream.accumulate(X.middleRows(at, rows)); });
  stream.fit();
  Eigen::MatrixXd Y(stream.rows(), options.dimensions);
  each_block([&](Eigen::Index at, Eigen::Index rows) {
    Y.middleRows(at, rows) = stream.project(X.middleRows(at, rows));
  });
  Streamed out;
  out.map = stream.finish(std::move(Y), &out.model);
  return out;
}

// The streamed map is embed()'s within kTolerance, same signs, same eigenvalues, warnings and
// model (which places X's rows on the same points).
void expect_same_map(const Eigen::MatrixXd& X, const EmbedOptions& options,
                     const std::vector<Eigen::Index>& sizes) {
  SCOPED_TRACE(std::string(method_name(options.method)) + (options.standardize ? " std" : "") +
               " dims " + std::to_string(options.dimensions) + " blocks of " +
               std::to_string(sizes.front()));
  EmbedInput input{&X};
  const Embedding whole = embed(input, options);
  const Streamed streamed = stream_blocks(X, options, sizes);
  const Eigen::MatrixXd& A = whole.coordinates;
  const Eigen::MatrixXd& B = streamed.map.coordinates;
  ASSERT_EQ(B.rows(), A.rows());
  ASSERT_EQ(B.cols(), A.cols());
  EXPECT_LE(test::procrustes_disparity(A, B), kTolerance);
  const double extent = A.cwiseAbs().maxCoeff();
  EXPECT_LE((A - B).cwiseAbs().maxCoeff(), kTolerance * extent);
  for (Eigen::Index a = 0; a < A.cols(); ++a) {
    // (An axis without variance holds rounding noise of either sign.)
    if (A.col(a).cwiseAbs().maxCoeff() < 1e-9 * extent) continue;
    EXPECT_GT(A.col(a).dot(B.col(a)), 0.0) << "axis " << a << " flipped";
  }
  for (Eigen::Index a = 0; a < A.cols(); ++a) {
    EXPECT_NEAR(streamed.map.eigenvalues[a], whole.eigenvalues[a],
                kTolerance * whole.eigenvalues[0]);
  }
  EXPECT_EQ(streamed.map.warnings, whole.warnings);
  EXPECT_EQ(streamed.map.method, options.method);

  const MapModel model = make_model(input, options, whole);
  EXPECT_EQ(streamed.model.mean.size(), model.mean.size());
  EXPECT_EQ(streamed.model.scale.size(), model.scale.size());
  PlaceInput place_input;
  place_input.features = &X;
  // The model places the map's own frames on the map. (make_model's axes, Zᵀ·Y ÷ σ², lose
  // digits on an ill-conditioned X, so the in-memory map's coordinates are the reference.)
  const Eigen::MatrixXd placed = place(streamed.model, place_input);
  EXPECT_LE((placed - A).cwiseAbs().maxCoeff(), kTolerance * extent);
}

Eigen::MatrixXd clip_features(const std::vector<std::string>& files,
                              features::FeatureKind kind = features::FeatureKind::Quaternions) {
  std::vector<Clip> clips;
  for (const std::string& f : files) clips.push_back(io::load_clip(test::shared_file(f)));
  features::FeatureOptions options;
  options.features = kind;
  return features::build_features(clips, options, {}, features::Distances::Later).X;
}

TEST(ProjectionStream, MatchesEmbedOnRealClips) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/64_09.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/02_03.bvh");
  const Eigen::MatrixXd X = clip_features({"cmu/64_08.bvh", "cmu/02_03.bvh", "cmu/64_09.bvh"});
  for (const Method method : {Method::Pca, Method::Svd}) {
    for (const int dims : {2, 3}) {
      EmbedOptions options;
      options.method = method;
      options.dimensions = dims;
      expect_same_map(X, options, {X.rows()});  // one block
      expect_same_map(X, options, {1});         // a row at a time
      expect_same_map(X, options, {173, 7, 400});
    }
  }
  EmbedOptions standardized;
  standardized.standardize = true;  // CMU's constant thumb columns: the warning, too
  expect_same_map(X, standardized, {97, 300});
  const Eigen::MatrixXd positions =
      clip_features({"cmu/64_08.bvh", "cmu/64_09.bvh"}, features::FeatureKind::Positions);
  expect_same_map(positions, standardized, {250});
  expect_same_map(positions, EmbedOptions{}, {250});
}

TEST(ProjectionStream, MatchesEmbedOnFarOffAndConstantColumns) {
  // A column far from 0 with a small spread (a sum of squares minus a squared sum would lose 8
  // of its digits) and a constant column (standardising leaves it unscaled, with a warning).
  Eigen::MatrixXd X = test::smooth_trajectory(2000, 6);
  X.col(1).array() += 1e4;
  X.col(4) = Eigen::VectorXd::Constant(X.rows(), 3.25);
  for (const Method method : {Method::Pca, Method::Svd}) {
    EmbedOptions options;
    options.method = method;
    expect_same_map(X, options, {128, 333});
  }
  EmbedOptions standardized;
  standardized.standardize = true;
  expect_same_map(X, standardized, {128, 333});
}

TEST(ProjectionStream, FlatAxisIsZeroWithEmbedsWarning) {
  // Rank 1: the second axis has no variance.
  Eigen::MatrixXd X(50, 4);
  for (int r = 0; r < 50; ++r) X.row(r) << r, 2.0 * r, -r, 0.5 * r;
  expect_same_map(X, EmbedOptions{}, {9});
  const Streamed s = stream_blocks(X, EmbedOptions{}, {9});
  EXPECT_THAT(s.map.warnings, ::testing::Contains(HasSubstr("axis 2 has no variance")));
}

TEST(ProjectionStream, BadInputIsAClearError) {
  EmbedOptions isomap;
  isomap.method = Method::Isomap;
  EXPECT_THAT(test::error_message([&] { ProjectionStream s(isomap); }),
              HasSubstr("only pca and svd"));

  ProjectionStream stream(EmbedOptions{});
  stream.accumulate(Eigen::MatrixXd::Ones(3, 4));
  Eigen::MatrixXd bad = Eigen::MatrixXd::Ones(2, 4);
  bad(1, 2) = std::nan("");
  EXPECT_THAT(test::error_message([&] { stream.accumulate(bad); }),
              HasSubstr("X(4, 2) is nan; every feature must be finite"));
  EXPECT_THAT(test::error_message([&] { stream.accumulate(Eigen::MatrixXd::Ones(2, 5)); }),
              HasSubstr("a block of X has 5 columns; the rows before it have 4"));
  EXPECT_THAT(test::error_message([&] { stream.project(Eigen::MatrixXd::Ones(2, 4)); }),
              HasSubstr("project() before fit()"));
  // Three rows are too few for a 2-D map, as embed() says.
  EXPECT_THAT(test::error_message([&] { stream.fit(); }), HasSubstr("needs at least 4"));

  ProjectionStream empty(EmbedOptions{});
  EXPECT_THAT(test::error_message([&] { empty.fit(); }), HasSubstr("X is empty"));
}

}  // namespace
}  // namespace motionmap::embed
