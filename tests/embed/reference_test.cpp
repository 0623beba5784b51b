// Every method against the independent numpy/scipy/scikit-learn references of
// tests/reference/make_fixtures.py, case by case.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "embed/embed_test_util.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/metrics.h"

namespace motionmap::embed {
namespace {

using test::Fixture;

struct RunFile {
  std::string case_name;
  std::string run;
};

std::vector<RunFile> all_runs() {
  std::vector<RunFile> out;
  for (const auto& dir : std::filesystem::directory_iterator(test::fixture_dir())) {
    if (!dir.is_directory()) continue;
    for (const auto& file : std::filesystem::directory_iterator(dir.path())) {
      const std::string stem = file.path().stem().string();
      if (file.path().extension() != ".txt" || stem == "X" || stem == "D") continue;
      out.push_back({dir.path().filename().string(), stem});
    }
  }
  std::sort(out.begin(), out.end(), [](const RunFile& a, const RunFile& b) {
    return a.case_name + "/" + a.run < b.case_name + "/" + b.run;
  });
  return out;
}

// Accuracy targets (Procrustes disparity): tight for the methods with well separated
// eigenvalues, 1e-6 for the two bottom-of-the-spectrum methods (see docs/methods/le.md, lle.md).
double disparity_target(Method m) {
  return (m == Method::LaplacianEigenmap || m == Method::Lle) ? 1e-6 : 1e-8;
}

class Reference : public ::testing::TestWithParam<RunFile> {};

TEST_P(Reference, MatchesIndependentImplementation) {
  const RunFile& rf = GetParam();
  const std::string folder = test::fixture_dir() + "/" + rf.case_name;
  const Eigen::MatrixXd X = test::read_fixture(folder + "/X.txt").matrix;
  const Eigen::MatrixXd D = std::filesystem::exists(folder + "/D.txt")
                                ? test::read_fixture(folder + "/D.txt").matrix
                                : test::euclidean_distances(X);
  const Fixture expected = test::read_fixture(folder + "/" + rf.run + ".txt");

  EmbedOptions options;
  options.method = *parse_method(expected.header.at("method"));
  options.dimensions = static_cast<int>(expected.number("dims"));
  options.k = static_cast<int>(expected.number("k"));
  if (expected.has("standardize")) options.standardize = expected.number("standardize") != 0;
  if (expected.has("reg")) options.reg = expected.number("reg");
  if (expected.has("heat") && expected.header.at("heat") != "auto") {
    options.heat = expected.number("heat");
  }
  const Embedding map = embed({.features = &X, .distances = &D}, options);

  const Eigen::MatrixXd& want = expected.matrix;
  ASSERT_EQ(map.coordinates.rows(), want.rows());
  ASSERT_EQ(map.coordinates.cols(), want.cols());
  const double disparity = test::procrustes_disparity(want, map.coordinates);
  EXPECT_LE(disparity, disparity_target(options.method)) << rf.case_name << "/" << rf.run;
  RecordProperty("disparity", std::to_string(disparity));
  std::printf("[ disparity ] %s/%s: %.3g\n", rf.case_name.c_str(), rf.run.c_str(), disparity);

  // Same signs and scale as the reference, not only the same shape: the sign convention and
  // the normalisations (covariance 1/(F−1), U·√λ, yᵀ·Deg·y = 1, unit LLE vectors) agree.
  const double scale = want.cwiseAbs().maxCoeff();
  EXPECT_LE((map.coordinates - want).cwiseAbs().maxCoeff(), 1e-3 * scale);

  const Eigen::VectorXd values = expected.numbers("eigenvalues");
  for (Eigen::Index a = 0; a < values.size(); ++a) {
    EXPECT_NEAR(map.eigenvalues[a], values[a], 1e-7 * std::abs(values[0]) + 1e-14) << "axis " << a;
  }
  if (expected.has("heat_used")) {
    EXPECT_DOUBLE_EQ(map.heat_used, expected.number("heat_used"));
  }
  if (expected.has("stress")) {
    ASSERT_TRUE(map.stress.has_value());
    EXPECT_NEAR(*map.stress, expected.number("stress"), 1e-6);
  }
  // The metrics, on the reference map itself, equal the Python values.
  const NeighborhoodQuality q = neighborhood_quality(D, want);
  EXPECT_NEAR(q.trustworthiness, expected.number("trustworthiness"), 1e-12);
  EXPECT_NEAR(q.continuity, expected.number("continuity"), 1e-12);
  const double jump = expected.number("jump");
  if (std::isinf(jump)) {
    EXPECT_TRUE(std::isinf(jump_score(want)));
  } else {
    EXPECT_NEAR(jump_score(want), jump, 1e-12 * jump);
  }
}

INSTANTIATE_TEST_SUITE_P(Fixtures, Reference, ::testing::ValuesIn(all_runs()),
                         [](const ::testing::TestParamInfo<RunFile>& info) {
                           return info.param.case_name + "_" + info.param.run;
                         });

TEST(EmbedReference, FixturesArePresent) {
  EXPECT_GE(all_runs().size(), 25u);
}

}  // namespace
}  // namespace motionmap::embed
