// GP-LVM (embed/gplvm.h): the objective's analytic gradients against finite differences, the
// objective against an independent numpy implementation (tests/reference/gplvm), the fit reaching
// a lower objective than its start, and bad inputs.
#include "motionmap/embed/gplvm.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/embed.h"
#include "support/error_message.h"

namespace motionmap::embed {
namespace {

// A small smooth data set: N points on a curve in 2-D latent space mapped into D dimensions.
void small_problem(Eigen::MatrixXd& Y, Eigen::MatrixXd& X, GplvmKernel& k, int N = 25, int D = 6) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd W(2, D);
  for (Eigen::Index i = 0; i < W.size(); ++i) W.data()[i] = normal(random);
  X.resize(N, 2);
  for (int i = 0; i < N; ++i) {
    const double t = 3.0 * i / (N - 1);
    X.row(i) << std::cos(t) + 0.1 * normal(random), std::sin(2 * t) + 0.1 * normal(random);
  }
  Y = (X * W).array().sin().matrix();
  Y.rowwise() -= Y.colwise().mean();
  k = initial_gplvm_kernel(Y);
  k.log_lengthscale = std::log(0.8);
}

TEST(Gplvm, AnalyticGradientsMatchFiniteDifferences) {
  Eigen::MatrixXd Y, X, gX;
  GplvmKernel k;
  small_problem(Y, X, k);
  Eigen::VectorXd gk;
  gplvm_objective(Y, X, k, &gX, &gk);
  const double h = 1e-6;
  for (int i : {0, 7, 24}) {
    for (int a = 0; a < 2; ++a) {
      Eigen::MatrixXd Xp = X, Xm = X;
      Xp(i, a) += h;
      Xm(i, a) -= h;
      const double fd = (gplvm_objective(Y, Xp, k) - gplvm_objective(Y, Xm, k)) / (2 * h);
      EXPECT_NEAR(gX(i, a), fd, 1e-6 * (1 + std::abs(fd))) << i << "," << a;
    }
  }
  double GplvmKernel::*fields[] = {&GplvmKernel::log_rbf_variance, &GplvmKernel::log_lengthscale,
                                   &GplvmKernel::log_bias_variance,
                                   &GplvmKernel::log_noise_variance};
  for (int j = 0; j < 4; ++j) {
    GplvmKernel kp = k, km = k;
    kp.*fields[j] += h;
    km.*fields[j] -= h;
    const double fd = (gplvm_objective(Y, X, kp) - gplvm_objective(Y, X, km)) / (2 * h);
    EXPECT_NEAR(gk[j], fd, 1e-6 * (1 + std::abs(fd))) << "kernel parameter " << j;
  }
}

// The objective and its gradients against tests/reference/make_gplvm_fixtures.py's numpy
// implementation, at the fit's start on CMU 64_08 (every 4th frame) and at a random point.
TEST(Gplvm, ObjectiveAndGradientsMatchNumpy) {
  const test::Fixture clip = test::read_fixture(test::fixture_dir() + "/clip_cmu_64_08/X.txt");
  const Eigen::MatrixXd Y = clip.matrix.rowwise() - clip.matrix.colwise().mean();
  for (const char* name : {"start.txt", "random.txt"}) {
    const test::Fixture f =
        test::read_fixture(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/gplvm/" + name);
    const Eigen::VectorXd theta = f.numbers("theta");
    const GplvmKernel k{theta[0], theta[1], theta[2], theta[3]};
    const Eigen::MatrixXd X = f.matrix.leftCols(2);
    Eigen::MatrixXd gX;
    Eigen::VectorXd gk;
    const double value = gplvm_objective(Y, X, k, &gX, &gk);
    const double want = f.number("objective");
    EXPECT_NEAR(value, want, 1e-8 * std::abs(want)) << name;
    const Eigen::MatrixXd want_gX = f.matrix.rightCols(2);
    EXPECT_LE((gX - want_gX).cwiseAbs().maxCoeff(), 1e-8 * (1 + want_gX.cwiseAbs().maxCoeff()))
        << name;
    const Eigen::VectorXd want_gk = f.numbers("grad_theta");
    EXPECT_LE((gk - want_gk).cwiseAbs().maxCoeff(), 1e-8 * (1 + want_gk.cwiseAbs().maxCoeff()))
        << name;
  }
  // The start itself: MotionMap's gplvm starts where the fixture does.
  const test::Fixture start =
      test::read_fixture(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/gplvm/start.txt");
  const GplvmKernel k0 = initial_gplvm_kernel(Y);
  const Eigen::VectorXd theta = start.numbers("theta");
  EXPECT_NEAR(k0.log_rbf_variance, theta[0], 1e-12);
  EXPECT_NEAR(k0.log_noise_variance, theta[3], 1e-12);
}

TEST(Gplvm, TheFitLowersTheObjective) {
  Eigen::MatrixXd Y, X;
  GplvmKernel k;
  small_problem(Y, X, k);
  Eigen::MatrixXd start = X;
  start.col(1) *= 0.3;
  const double before = gplvm_objective(Y, start, k);
  const GplvmFit fit = fit_gplvm(Y, start, k, 200);
  EXPECT_LT(fit.objective, before - 1.0);
  EXPECT_GT(fit.iterations, 5);
  EXPECT_NEAR(fit.objective, gplvm_objective(Y, fit.X, fit.kernel), 1e-9 * std::abs(fit.objective));
}

TEST(Gplvm, BadInputsAreRefused) {
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(5, 3), X = Eigen::MatrixXd::Zero(4, 2);
  EXPECT_EQ(test::error_message<ParameterError>([&] { fit_gplvm(Y, X, {}, 10); }),
            "gplvm: latent points of 4 × 2 for data of 5 × 3, expected N × q for N × D, N ≥ 2");
  X = Eigen::MatrixXd::Zero(5, 2);
  EXPECT_EQ(test::error_message<ParameterError>([&] { fit_gplvm(Y, X, {}, 0); }),
            "gplvm: 0 iterations asked for, expected at least 1");
  X(2, 1) = NAN;
  EXPECT_EQ(test::error_message<ParameterError>([&] { fit_gplvm(Y, X, {}, 10); }),
            "gplvm: the data or the starting points are not finite");
  // Through embed(): the iteration bound, and more frames than the full model maps.
  EmbedOptions o;
  o.method = Method::Gplvm;
  o.max_iterations = 0;
  const Eigen::MatrixXd small = Eigen::MatrixXd::Random(20, 3);
  EXPECT_EQ(test::error_message<ParameterError>([&] { embed({.features = &small}, o); }),
            "gplvm: max_iterations = 0 is out of range; it must be in [1, 100000] (default 300)");
  o.max_iterations = 5;
  const Eigen::MatrixXd many = Eigen::MatrixXd::Random(kGplvmMaxFrames + 1, 3);
  EXPECT_EQ(test::error_message<ParameterError>([&] { embed({.features = &many}, o); }),
            "gplvm: 2001 frames; the full model maps at most 2000 (its N × N kernel is factorised "
            "at every step, and the sparse approximation is not built yet): map every k-th frame "
            "with --stride");
}

}  // namespace
}  // namespace motionmap::embed
