// The GP-LVM read as a map (embed::GplvmMap): its frame weights reproduce the GP's predictive
// mean, and its variance the GP's, against an independent dense numpy implementation
// (tests/reference/make_gplvm_predictive_fixtures.py); the validity rule on the fixtures' clip;
// the cutoff of k(x); predictives that do not belong to the latent points.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/gplvm.h"
#include "support/error_message.h"

namespace motionmap::embed {
namespace {

using ::testing::HasSubstr;

struct Reference {
  Eigen::MatrixXd F, Y, X;  // features (91 × 120), centred, latent points (random.txt)
  GplvmKernel kernel;
};

Reference reference() {
  Reference r;
  r.F = test::read_fixture(test::fixture_dir() + "/clip_cmu_64_08/X.txt").matrix;
  r.Y = r.F.rowwise() - r.F.colwise().mean();
  const test::Fixture f =
      test::read_fixture(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/gplvm/random.txt");
  r.X = f.matrix.leftCols(2);
  const Eigen::VectorXd t = f.numbers("theta");
  r.kernel = {t[0], t[1], t[2], t[3]};
  return r;
}

Eigen::MatrixXd inducing(const Eigen::MatrixXd& X, const Eigen::VectorXd& rows) {
  Eigen::MatrixXd Z(rows.size(), 2);
  for (Eigen::Index i = 0; i < rows.size(); ++i) Z.row(i) = X.row(Eigen::Index(rows[i]));
  return Z;
}

// Σ w'_i F_i is numpy's μ(x) + mean to 1e-9, per joint normalised too, and the variance is
// numpy's σ²(x) − s to 1e-9 of the prior, at the fixture's 7 points (on latent points, between
// them, a lengthscale off, far away), for the full model and the sparse one (12 inducing inputs).
TEST(GplvmMap, WeightsGiveNumpysPredictiveMeanAndVariance) {
  const Reference r = reference();
  for (const char* name : {"predictive.txt", "predictive_sparse.txt"}) {
    const test::Fixture f =
        test::read_fixture(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/gplvm/" + name);
    const Eigen::MatrixXd Z =
        f.has("inducing_rows") ? inducing(r.X, f.numbers("inducing_rows")) : Eigen::MatrixXd();
    const GplvmPredictive p = gplvm_predictive(r.Y, r.X, Z, r.kernel);
    const GplvmMap gp(p, r.X, &r.Y);
    const Eigen::Index D = r.F.cols();
    ASSERT_EQ(f.matrix.cols(), 3 + 2 * D) << name;
    for (Eigen::Index q = 0; q < f.matrix.rows(); ++q) {
      const Eigen::Vector2d x = f.matrix.row(q).head(2).transpose();
      EXPECT_NEAR(gp.variance(x), f.matrix(q, 2), 1e-9 * gp.prior_variance()) << name << " " << q;
      const Eigen::VectorXd w = gp.frame_weights(x);
      ASSERT_EQ(w.size(), r.F.rows());
      EXPECT_NEAR(w.sum(), 1.0, 1e-12) << name << " " << q;
      const Eigen::RowVectorXd mu = w.transpose() * r.F;
      const Eigen::RowVectorXd want = f.matrix.row(q).segment(3, D);
      EXPECT_LE((mu - want).cwiseAbs().maxCoeff(), 1e-9) << name << " " << q;
      Eigen::RowVectorXd unit = mu;
      for (Eigen::Index j = 0; j < D; j += 4) unit.segment(j, 4).normalize();
      EXPECT_LE((unit - f.matrix.row(q).segment(3 + D, D)).cwiseAbs().maxCoeff(), 1e-9)
          << name << " " << q;
    }
  }
}

// The cutoff of k(x)'s RBF part changes the variance by less than 1e-12 of the prior against
// the dense sum over every basis point, at random points over the latent points' box.
TEST(GplvmMap, TheCutoffLeavesTheVarianceAsTheDenseSum) {
  const Reference r = reference();
  // A short lengthscale, so that the cutoff leaves most basis points out.
  GplvmKernel k = r.kernel;
  k.log_lengthscale = std::log(0.05);
  const GplvmPredictive p = gplvm_predictive(r.Y, r.X, Eigen::MatrixXd(), k);
  const GplvmMap gp(p, r.X);
  std::mt19937 random(7);
  const Eigen::Vector2d lo = r.X.colwise().minCoeff(), hi = r.X.colwise().maxCoeff();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int t = 0; t < 200; ++t) {
    const Eigen::Vector2d x(lo.x() + u(random) * (hi.x() - lo.x()),
                            lo.y() + u(random) * (hi.y() - lo.y()));
    const Eigen::VectorXd kx =
        (p.rbf_variance * (-0.5 / (p.lengthscale * p.lengthscale) *
                           (p.basis.rowwise() - x.transpose()).rowwise().squaredNorm())
                              .array()
                              .exp() +
         p.bias_variance)
            .matrix();
    const double dense = p.rbf_variance + p.bias_variance - kx.dot(p.C * kx);
    EXPECT_NEAR(gp.variance(x), std::max(0.0, dense), 1e-12 * gp.prior_variance()) << t;
  }
}

// The frames' own latent points are inside the data (the full model's every one); a point 10
// lengthscales beyond the latent points' box is not.
TEST(GplvmMap, TheFramesAreInsideAndFarPointsOutside) {
  const Reference r = reference();
  for (const bool sparse : {false, true}) {
    const Eigen::MatrixXd Z =
        sparse ? inducing(r.X, Eigen::VectorXd::LinSpaced(30, 0, 90)) : Eigen::MatrixXd();
    const GplvmPredictive p = gplvm_predictive(r.Y, r.X, Z, r.kernel);
    const GplvmMap gp(p, r.X, &r.Y);
    EXPECT_DOUBLE_EQ(gp.threshold(), kGplvmValidFraction * gp.prior_variance());
    int inside = 0;
    for (Eigen::Index i = 0; i < r.X.rows(); ++i) inside += gp.inside(r.X.row(i).transpose());
    std::printf("%s model: %d of %d frames inside\n", sparse ? "sparse" : "full", inside,
                int(r.X.rows()));
    // The full model predicts every frame well; the sparse one (30 inducing inputs for 91 random
    // latent points, not fitted) leaves a few where no inducing input is near.
    EXPECT_GE(inside, sparse ? 80 : 91);
    const Eigen::Vector2d far =
        r.X.colwise().maxCoeff().transpose() + Eigen::Vector2d::Constant(10 * p.lengthscale);
    EXPECT_FALSE(gp.inside(far));
    EXPECT_GT(gp.variance(far), 0.9 * p.rbf_variance);
  }
}

// A predictive that does not belong to the latent points it is given is refused, naming why.
TEST(GplvmMap, APredictiveOfOtherLatentPointsIsRefused) {
  const Reference r = reference();
  Eigen::MatrixXd moved = r.X;
  moved(5, 0) += 0.2;
  const GplvmPredictive full = gplvm_predictive(r.Y, r.X, Eigen::MatrixXd(), r.kernel);
  EXPECT_THAT(test::error_message<ParameterError>([&] { (void)GplvmMap(full, moved); }),
              HasSubstr("basis is not the latent points"));
  const GplvmPredictive sparse =
      gplvm_predictive(r.Y, r.X, inducing(r.X, Eigen::VectorXd::LinSpaced(30, 0, 90)), r.kernel);
  EXPECT_NO_THROW((void)GplvmMap(sparse, r.X, &r.Y));
  EXPECT_THAT(test::error_message<ParameterError>([&] { (void)GplvmMap(sparse, moved, &r.Y); }),
              HasSubstr("does not belong to these frames"));
  const Eigen::MatrixXd other = r.Y.colwise().reverse();
  // A full model's predictive given one latent point fewer reads as a sparse one, whose weights
  // then do not give its alpha.
  const Eigen::MatrixXd top = r.Y.topRows(90);
  EXPECT_THAT(test::error_message<ParameterError>([&] { (void)GplvmMap(full, r.X, &other); }),
              HasSubstr("does not belong to these frames"));
  EXPECT_THAT(
      test::error_message<ParameterError>([&] { (void)GplvmMap(full, r.X.topRows(90), &top); }),
      HasSubstr("does not belong to these frames"));
  Eigen::MatrixXd three(r.X.rows(), 3);
  three << r.X, Eigen::VectorXd::Zero(r.X.rows());
  EXPECT_THAT(test::error_message<ParameterError>([&] { (void)GplvmMap(full, three); }),
              HasSubstr("2-D map"));
  GplvmPredictive no_noise = full;
  no_noise.prior_variance = full.rbf_variance + full.bias_variance;
  EXPECT_THAT(test::error_message<ParameterError>([&] { (void)GplvmMap(no_noise, r.X); }),
              HasSubstr("no noise"));
  const GplvmMap gp(full, r.X);
  EXPECT_THAT(
      test::error_message<ParameterError>([&] { gp.variance(Eigen::Vector2d(std::nan(""), 0.0)); }),
      HasSubstr("not finite"));
}

}  // namespace
}  // namespace motionmap::embed
