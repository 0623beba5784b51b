// Landmark MDS and the Nyström extension of the Laplacian eigenmap against independent numpy /
// scipy implementations (tests/reference/make_placement_fixtures.py): the fit on a case's first
// rows, then the placement of the rest.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "embed/embed_test_util.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/placement.h"

namespace motionmap::embed {
namespace {

std::string folder(const std::string& name) {
  return std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/placement/" + name;
}

// ‖a − b‖∞ relative to ‖b‖∞.
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

class PlacementReference : public ::testing::TestWithParam<std::string> {};

TEST_P(PlacementReference, LandmarkMdsFitAndPlacement) {
  const test::Fixture x = test::read_fixture(folder(GetParam()) + "/X.txt");
  const test::Fixture expected = test::read_fixture(folder(GetParam()) + "/lmds.txt");
  const int fit = static_cast<int>(expected.number("fit"));
  const RowMatrix train = x.matrix.topRows(fit);
  const RowMatrix rest = x.matrix.bottomRows(x.matrix.rows() - fit);
  EmbedOptions options;
  options.method = Method::Mds;
  options.landmarks = static_cast<int>(expected.number("count"));
  const Embedding map = embed({.points = &train}, options);
  const Eigen::VectorXd landmarks = expected.numbers("landmarks");
  ASSERT_EQ(map.landmarks->frames.size(), std::size_t(landmarks.size()));
  for (Eigen::Index l = 0; l < landmarks.size(); ++l) {
    EXPECT_EQ(map.landmarks->frames[l], int(landmarks[l]));
  }
  EXPECT_LE(relative_error(map.coordinates, expected.matrix.topRows(fit)), 1e-9);
  const MapModel model = make_model({.points = &train}, options, map);
  const Eigen::MatrixXd placed = place(model, {.points = &rest});
  EXPECT_LE(relative_error(placed, expected.matrix.bottomRows(rest.rows())), 1e-9);
}

TEST_P(PlacementReference, LaplacianEigenmapNystromExtension) {
  const test::Fixture x = test::read_fixture(folder(GetParam()) + "/X.txt");
  const test::Fixture expected = test::read_fixture(folder(GetParam()) + "/le_nystrom.txt");
  const int fit = static_cast<int>(expected.number("fit"));
  const Eigen::MatrixXd train_x = x.matrix.topRows(fit);
  const RowMatrix train = train_x;
  const RowMatrix rest = x.matrix.bottomRows(x.matrix.rows() - fit);
  const Eigen::MatrixXd D = test::euclidean_distances(train_x);
  EmbedOptions options;
  options.method = Method::LaplacianEigenmap;
  options.k = static_cast<int>(expected.number("k"));
  const Embedding map = embed({.distances = &D}, options);
  EXPECT_NEAR(map.heat_used, expected.number("heat"), 1e-12 * expected.number("heat"));
  // The fit to the eigen solvers' agreement (docs/methods/le.md), the extension to the same.
  EXPECT_LE(relative_error(map.coordinates, expected.matrix.topRows(fit)), 1e-6);
  const MapModel model = make_model({.distances = &D, .points = &train}, options, map);
  const Eigen::MatrixXd placed = place(model, {.points = &rest});
  EXPECT_LE(relative_error(placed, expected.matrix.bottomRows(rest.rows())), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Cases, PlacementReference, ::testing::Values("swiss_roll", "closed_loop"));

}  // namespace
}  // namespace motionmap::embed
