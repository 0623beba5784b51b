// GP-LVM (embed/gplvm.h): the objective's analytic gradients against finite differences, the
// objective against an independent numpy implementation (tests/reference/gplvm), the fit reaching
// a lower objective than its start, and bad inputs.
#include "motionmap/embed/gplvm.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/placement.h"
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

// Inducing inputs near some of the latent points (every `every`-th, nudged).
Eigen::MatrixXd near_rows(const Eigen::MatrixXd& X, int every) {
  Eigen::MatrixXd Z(0, X.cols());
  for (Eigen::Index i = 0; i < X.rows(); i += every) {
    Z.conservativeResize(Z.rows() + 1, Eigen::NoChange);
    Z.row(Z.rows() - 1) = X.row(i) + Eigen::RowVector2d(0.03, -0.02);
  }
  return Z;
}

TEST(GplvmSparse, AnalyticGradientsMatchFiniteDifferences) {
  Eigen::MatrixXd Y, X, gX, gZ;
  GplvmKernel k;
  small_problem(Y, X, k);
  const Eigen::MatrixXd Z = near_rows(X, 3);  // 9 inducing inputs
  Eigen::VectorXd gk;
  sparse_gplvm_objective(Y, X, Z, k, &gX, &gZ, &gk);
  // A step of 1e-4: at 1e-6 the differences' rounding (K_uu's conditioning amplifies it) reaches
  // 1e-6 of the gradients; numpy's complex-step gradients check them to 1e-8.
  const double h = 1e-4;
  for (int i : {0, 7, 24}) {
    for (int a = 0; a < 2; ++a) {
      Eigen::MatrixXd Xp = X, Xm = X;
      Xp(i, a) += h;
      Xm(i, a) -= h;
      const double fd =
          (sparse_gplvm_objective(Y, Xp, Z, k) - sparse_gplvm_objective(Y, Xm, Z, k)) / (2 * h);
      EXPECT_NEAR(gX(i, a), fd, 1e-6 * (1 + std::abs(fd))) << "x " << i << "," << a;
    }
  }
  for (int m : {0, 4, 8}) {
    for (int a = 0; a < 2; ++a) {
      Eigen::MatrixXd Zp = Z, Zm = Z;
      Zp(m, a) += h;
      Zm(m, a) -= h;
      const double fd =
          (sparse_gplvm_objective(Y, X, Zp, k) - sparse_gplvm_objective(Y, X, Zm, k)) / (2 * h);
      EXPECT_NEAR(gZ(m, a), fd, 1e-6 * (1 + std::abs(fd))) << "z " << m << "," << a;
    }
  }
  double GplvmKernel::*fields[] = {&GplvmKernel::log_rbf_variance, &GplvmKernel::log_lengthscale,
                                   &GplvmKernel::log_bias_variance,
                                   &GplvmKernel::log_noise_variance};
  for (int j = 0; j < 4; ++j) {
    GplvmKernel kp = k, km = k;
    kp.*fields[j] += h;
    km.*fields[j] -= h;
    const double fd =
        (sparse_gplvm_objective(Y, X, Z, kp) - sparse_gplvm_objective(Y, X, Z, km)) / (2 * h);
    EXPECT_NEAR(gk[j], fd, 1e-6 * (1 + std::abs(fd))) << "kernel parameter " << j;
  }
}

// The sparse objective and its gradients against the numpy fixtures (the dense N × N form of the
// bound, gradients by complex-step differentiation) to 1e-8 relative.
TEST(GplvmSparse, ObjectiveAndGradientsMatchNumpy) {
  const test::Fixture clip = test::read_fixture(test::fixture_dir() + "/clip_cmu_64_08/X.txt");
  const Eigen::MatrixXd Y = clip.matrix.rowwise() - clip.matrix.colwise().mean();
  for (const char* name : {"sparse_start.txt", "sparse_random.txt"}) {
    const test::Fixture f =
        test::read_fixture(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/gplvm/" + name);
    const Eigen::VectorXd theta = f.numbers("theta");
    const Eigen::VectorXd rows = f.numbers("rows");
    const Eigen::Index N = Eigen::Index(rows[0]), M = Eigen::Index(rows[1]);
    ASSERT_EQ(N, Y.rows());
    ASSERT_EQ(N + M, f.matrix.rows());
    const GplvmKernel k{theta[0], theta[1], theta[2], theta[3]};
    const Eigen::MatrixXd X = f.matrix.topLeftCorner(N, 2), Z = f.matrix.bottomLeftCorner(M, 2);
    Eigen::MatrixXd gX, gZ;
    Eigen::VectorXd gk;
    const double value = sparse_gplvm_objective(Y, X, Z, k, &gX, &gZ, &gk);
    const double want = f.number("objective");
    EXPECT_NEAR(value, want, 1e-8 * std::abs(want)) << name;
    const Eigen::MatrixXd want_gX = f.matrix.topRightCorner(N, 2);
    const Eigen::MatrixXd want_gZ = f.matrix.bottomRightCorner(M, 2);
    EXPECT_LE((gX - want_gX).cwiseAbs().maxCoeff(), 1e-8 * (1 + want_gX.cwiseAbs().maxCoeff()))
        << name;
    EXPECT_LE((gZ - want_gZ).cwiseAbs().maxCoeff(), 1e-8 * (1 + want_gZ.cwiseAbs().maxCoeff()))
        << name;
    const Eigen::VectorXd want_gk = f.numbers("grad_theta");
    EXPECT_LE((gk - want_gk).cwiseAbs().maxCoeff(), 1e-8 * (1 + want_gk.cwiseAbs().maxCoeff()))
        << name << ": " << gk.transpose() << " vs " << want_gk.transpose();
  }
}

// The sparse objective is an upper bound of the full one that tightens as inducing inputs are
// added (nested sets) and reaches it when Z = X. It differs there only by the jitter ε in K_uu:
// 0 ≤ K − Q ≤ ε I, so log|Q + sI| and the trace term each lie within N ε / s of the full
// model's (times D/2), and the quadratic term within ε |Y|² / (2 s²).
TEST(GplvmSparse, TheBoundTendsToTheFullObjectiveAsTheInducingInputsReachTheFrames) {
  Eigen::MatrixXd Y, X;
  GplvmKernel k;
  small_problem(Y, X, k, 40, 6);
  const double full = gplvm_objective(Y, X, k);
  double previous = std::numeric_limits<double>::infinity();
  for (int every : {8, 4, 2, 1}) {  // nested: rows 0, 8, …; 0, 4, …; 0, 2, …; all
    Eigen::MatrixXd Z(0, 2);
    for (Eigen::Index i = 0; i < X.rows(); i += every) {
      Z.conservativeResize(Z.rows() + 1, Eigen::NoChange);
      Z.row(Z.rows() - 1) = X.row(i);
    }
    const double sparse = sparse_gplvm_objective(Y, X, Z, k);
    EXPECT_GE(sparse, full - 1e-9 * std::abs(full)) << "M = " << Z.rows();
    EXPECT_LE(sparse, previous + 1e-9 * std::abs(full)) << "M = " << Z.rows();
    previous = sparse;
  }
  const double sf2 = std::exp(k.log_rbf_variance), eps = 1e-8 * sf2;
  const double s = std::exp(k.log_noise_variance) + eps;
  const double N = double(Y.rows()), D = double(Y.cols());
  const double bound = D * N * eps / s + eps * Y.squaredNorm() / (2 * s * s);
  EXPECT_LE(previous - full, bound + 1e-10 * std::abs(full));
  EXPECT_GT(bound, 0.0);
  // Far from it with few inducing inputs (the test above is not vacuous).
  EXPECT_GT(sparse_gplvm_objective(Y, X, X.topRows(3), k) - full, 1.0);
}

TEST(GplvmSparse, TheFitLowersTheBoundAndMovesTheInducingInputs) {
  Eigen::MatrixXd Y, X;
  GplvmKernel k;
  small_problem(Y, X, k, 60, 6);
  Eigen::MatrixXd start = X;
  start.col(1) *= 0.3;
  const Eigen::MatrixXd Z0 = gplvm_inducing_start(start, 10);
  const double before = sparse_gplvm_objective(Y, start, Z0, k);
  const GplvmFit fit = fit_gplvm(Y, start, k, 200, {}, &Z0);
  EXPECT_LT(fit.objective, before - 1.0);
  EXPECT_GT(fit.iterations, 5);
  ASSERT_EQ(fit.Z.rows(), 10);
  EXPECT_GT((fit.Z - Z0).norm(), 1e-3);
  EXPECT_NEAR(fit.objective, sparse_gplvm_objective(Y, fit.X, fit.Z, fit.kernel),
              1e-9 * std::abs(fit.objective));
}

// With ℓ held the sparse model has minima, and the fit reaches one and says so: CMU 64_08 every
// 4th frame (91 frames), 20 inducing inputs, from MotionMap's start (PCA scores scaled to unit
// variance, ℓ = 1). Before K_uf was whitened before squaring (A = L⁻¹K_uf), B lost its positive
// definiteness to rounding where inducing inputs crowd, and held-ℓ fits stalled in their first
// iterations (measured on the 1 989 warped walks: docs/methods/gplvm.md, *Sparse model*). It says
// "converged" by the 5-iteration decrease test (measured: 4 280 iterations, gradient norm 0.24).
TEST(GplvmSparse, WithTheLengthscaleHeldTheFitConverges) {
  const test::Fixture clip = test::read_fixture(test::fixture_dir() + "/clip_cmu_64_08/X.txt");
  const Eigen::MatrixXd Y = clip.matrix.rowwise() - clip.matrix.colwise().mean();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Y, Eigen::ComputeThinU);
  Eigen::MatrixXd X0 = svd.matrixU().leftCols(2) * std::sqrt(double(Y.rows() - 1));
  const Eigen::MatrixXd Z0 = gplvm_inducing_start(X0, 20);
  GplvmKernel k = initial_gplvm_kernel(Y);
  k.log_lengthscale = 0.0;
  const GplvmFit fit = fit_gplvm(Y, X0, k, 20000, {}, &Z0, /*fit_lengthscale=*/false);
  std::printf(
      "[ figures ] sparse gplvm, ℓ held, 91 frames, M = 20: %s after %d iterations (%d "
      "evaluations), bound %.6f, gradient norm %.2e\n",
      fit.stopped, fit.iterations, fit.evaluations, fit.objective, fit.gradient_norm);
  EXPECT_STREQ(fit.stopped, "converged");
  EXPECT_GT(fit.iterations, 0);
  EXPECT_LE(fit.iterations, 6000);
  EXPECT_EQ(fit.kernel.log_lengthscale, 0.0);
  // At a minimum: the gradient is small against the start's, and the point is the one kept.
  Eigen::MatrixXd gX, gZ;
  Eigen::VectorXd gk;
  sparse_gplvm_objective(Y, X0, Z0, k, &gX, &gZ, &gk);
  const double start_norm = std::sqrt(gX.squaredNorm() + gZ.squaredNorm() + gk.squaredNorm());
  EXPECT_LE(fit.gradient_norm, 1e-4 * start_norm);
  const double value = sparse_gplvm_objective(Y, fit.X, fit.Z, fit.kernel, &gX, &gZ, &gk);
  EXPECT_EQ(value, fit.objective);
  gk[1] = 0.0;  // ℓ is held
  EXPECT_NEAR(std::sqrt(gX.squaredNorm() + gZ.squaredNorm() + gk.squaredNorm()), fit.gradient_norm,
              1e-12 * start_norm);
}

TEST(GplvmSparse, InducingStartIsASeededSubsetOfTheLatentPoints) {
  Eigen::MatrixXd X(50, 2);
  for (int i = 0; i < 50; ++i) X.row(i) << i, -i;
  const Eigen::MatrixXd Z = gplvm_inducing_start(X, 7);
  ASSERT_EQ(Z.rows(), 7);
  for (int m = 0; m < 7; ++m) {
    EXPECT_EQ(Z(m, 1), -Z(m, 0));  // a row of X
    if (m > 0) {
      EXPECT_GT(Z(m, 0), Z(m - 1, 0));  // distinct, in frame order
    }
  }
  EXPECT_EQ(gplvm_inducing_start(X, 7), Z);  // seeded
  EXPECT_EQ(gplvm_inducing_start(X, 50), X);
  EXPECT_EQ(test::error_message<ParameterError>([&] { gplvm_inducing_start(X, 0); }),
            "gplvm: 0 inducing points for 50 frames; give between 1 and the number of frames");
  EXPECT_EQ(test::error_message<ParameterError>([&] { gplvm_inducing_start(X, 51); }),
            "gplvm: 51 inducing points for 50 frames; give between 1 and the number of frames");
}

// Through embed(): the sparse model when asked for, with its inducing inputs and kernel kept.
TEST(GplvmSparse, EmbedFitsTheSparseModelWhenAskedAndAboveTheThreshold) {
  Eigen::MatrixXd Y, X;
  GplvmKernel k;
  small_problem(Y, X, k, 80, 6);
  EmbedOptions o;
  o.method = Method::Gplvm;
  o.max_iterations = 30;
  o.inducing = 12;
  const Embedding map = embed({.features = &Y}, o);
  EXPECT_EQ(map.coordinates.rows(), 80);
  EXPECT_EQ(map.gplvm_inducing.rows(), 12);
  EXPECT_EQ(map.gplvm_kernel.size(), 4U);
  ASSERT_FALSE(map.notes.empty());
  EXPECT_NE(map.notes.back().find("gplvm (sparse, 12 inducing points)"), std::string::npos)
      << map.notes.back();
  o.inducing = 0;
  const Embedding full = embed({.features = &Y}, o);
  EXPECT_EQ(full.gplvm_inducing.rows(), 0);
  EXPECT_EQ(gplvm_inducing_points(1000, 0), 0);
  EXPECT_EQ(gplvm_inducing_points(1001, 0), kGplvmDefaultInducing);
  EXPECT_EQ(gplvm_inducing_points(500, 40), 40);
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

// MotionMap's fit and scipy's L-BFGS-B (tests/reference/make_gplvm_fixtures.py, optimum.txt),
// from the same start on CMU 64_08 every 8th frame, the lengthscale held (with it free the
// objective has no minimum: gplvm.h), reach the same optimum: the same latent points up to a
// rotation of the plane (the objective's symmetry) and the same objective.
TEST(Gplvm, ReachesScipysOptimumFromTheSameStart) {
  const test::Fixture clip = test::read_fixture(test::fixture_dir() + "/clip_cmu_64_08/X.txt");
  Eigen::MatrixXd Y(clip.matrix.rows() / 2 + clip.matrix.rows() % 2, clip.matrix.cols());
  for (Eigen::Index i = 0; i < Y.rows(); ++i) Y.row(i) = clip.matrix.row(2 * i);
  Y = Y.rowwise() - Y.colwise().mean();
  const test::Fixture f =
      test::read_fixture(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/gplvm/optimum.txt");
  ASSERT_EQ(f.matrix.rows(), Y.rows());
  const Eigen::VectorXd t0 = f.numbers("theta_start");
  const Eigen::MatrixXd X0 = f.matrix.leftCols(2), want = f.matrix.rightCols(2);
  // The fixture starts where MotionMap's gplvm does.
  const GplvmKernel k0 = initial_gplvm_kernel(Y);
  ASSERT_NEAR(k0.log_rbf_variance, t0[0], 1e-12);
  ASSERT_NEAR(k0.log_noise_variance, t0[3], 1e-12);
  const GplvmFit fit = fit_gplvm(Y, X0, k0, 100000, {}, nullptr, /*fit_lengthscale=*/false);
  EXPECT_STREQ(fit.stopped, "converged");
  const double disparity = test::procrustes_disparity(fit.X, want);
  const double objective = f.number("objective");
  std::printf(
      "[ figures ] gplvm optimum, 46 frames: MotionMap %d iterations, objective %.10f; scipy "
      "%d iterations, %.10f; Procrustes disparity %.2e\n",
      fit.iterations, fit.objective, int(f.number("iterations")), objective, disparity);
  EXPECT_LE(disparity, 1e-4);
  // σ_b² drifts towards 0 at the optimum (scipy: log σ_b² = −18.7), a direction so flat that
  // the two stopping rules leave the objectives 1.5e-6 apart (relative).
  EXPECT_NEAR(fit.objective, objective, 1e-5 * std::abs(objective));
  EXPECT_EQ(fit.kernel.log_lengthscale, 0.0);  // ℓ is kept
  const Eigen::VectorXd theta = f.numbers("theta");
  EXPECT_NEAR(fit.kernel.log_noise_variance, theta[3], 1e-3 * std::abs(theta[3]));
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
  o.inducing = 21;
  EXPECT_EQ(test::error_message<ParameterError>([&] { embed({.features = &small}, o); }),
            "gplvm: inducing = 21 is out of range; it must be in [1, 20] (the number of frames), "
            "or 0 for the default (the full model up to 1000 frames, 100 inducing points above)");
  o.inducing = -1;
  EXPECT_EQ(test::error_message<ParameterError>([&] { embed({.features = &small}, o); }),
            "gplvm: inducing = -1 is out of range; it must be in [1, 20] (the number of frames), "
            "or 0 for the default (the full model up to 1000 frames, 100 inducing points above)");
  o.inducing = 4;
  Eigen::MatrixXd bad = small;
  bad(3, 1) = INFINITY;
  EXPECT_THAT(test::error_message<ParameterError>([&] { embed({.features = &bad}, o); }),
              testing::HasSubstr("finite"));
}

}  // namespace
}  // namespace motionmap::embed

namespace motionmap::embed {
namespace {

// The placement objective's gradient against central differences, for both models' predictive.
TEST(GplvmPlace, ObjectiveGradientMatchesFiniteDifferences) {
  Eigen::MatrixXd Y, X;
  GplvmKernel k;
  small_problem(Y, X, k, 30, 6);
  for (bool sparse : {false, true}) {
    const GplvmPredictive p =
        gplvm_predictive(Y, X, sparse ? near_rows(X, 4) : Eigen::MatrixXd(), k);
    const Eigen::VectorXd y = Y.row(5).transpose() * 0.9;
    for (const Eigen::Vector2d& x : {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-1.0, 0.7)}) {
      Eigen::VectorXd g;
      gplvm_place_objective(p, y, x, &g);
      for (int a = 0; a < 2; ++a) {
        Eigen::VectorXd xp = x, xm = x;
        xp[a] += 1e-6;
        xm[a] -= 1e-6;
        const double fd =
            (gplvm_place_objective(p, y, xp) - gplvm_place_objective(p, y, xm)) / 2e-6;
        EXPECT_NEAR(g[a], fd, 1e-6 * (1 + std::abs(fd))) << (sparse ? "sparse " : "full ") << a;
      }
    }
  }
}

// The sparse predictive with Z = X is the full one (up to the jitter).
TEST(GplvmPlace, SparsePredictiveWithEveryFrameInducingIsTheFullOne) {
  Eigen::MatrixXd Y, X;
  GplvmKernel k;
  small_problem(Y, X, k, 30, 6);
  const GplvmPredictive full = gplvm_predictive(Y, X, Eigen::MatrixXd(), k);
  const GplvmPredictive sparse = gplvm_predictive(Y, X, X, k);
  const Eigen::VectorXd y = Y.row(11).transpose();
  for (const Eigen::Vector2d& x : {Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(-1.0, 0.7)}) {
    EXPECT_NEAR(gplvm_place_objective(sparse, y, x), gplvm_place_objective(full, y, x), 1e-5);
  }
}

// CMU 64_08 every 4th frame (the fixtures' clip), fitted, both models.
struct FittedClip {
  Eigen::MatrixXd X;  // features
  Embedding map;
};

FittedClip fit_clip(const Eigen::MatrixXd& features, int inducing) {
  EmbedOptions o;
  o.method = Method::Gplvm;
  o.max_iterations = 100;
  o.inducing = inducing;
  return {features, embed({.features = &features}, o)};
}

Eigen::MatrixXd clip_features() {
  return test::read_fixture(test::fixture_dir() + "/clip_cmu_64_08/X.txt").matrix;
}

// A map's own frames land near their latent points (which have unit variance per axis; the
// clip's path spans about 4): the full model's within 0.1 for 90% of them, the sparse one's (30
// inducing points for 91 frames, a smoother mean) within 0.3 (measured: median 0.11, 90% 0.23);
// every frame within 0.5.
TEST(GplvmPlace, TheMapsOwnFramesLandNearTheirLatentPoints) {
  const Eigen::MatrixXd features = clip_features();
  for (int inducing : {0, 30}) {
    FittedClip c = fit_clip(features, inducing);
    const Eigen::MatrixXd latent = c.map.coordinates;
    EmbedOptions o;
    o.method = Method::Gplvm;
    const MapModel model = make_model({.features = &c.X}, o, std::move(c.map));
    const Eigen::MatrixXd placed = place(model, {.features = &c.X});
    ASSERT_EQ(placed.rows(), latent.rows());
    const Eigen::VectorXd error = (placed - latent).rowwise().norm();
    std::vector<double> sorted(error.data(), error.data() + error.size());
    std::sort(sorted.begin(), sorted.end());
    EXPECT_LE(sorted[sorted.size() * 9 / 10], inducing > 0 ? 0.3 : 0.1)
        << "inducing " << inducing << ": median " << sorted[sorted.size() / 2] << ", 90% "
        << sorted[sorted.size() * 9 / 10] << ", largest " << sorted.back();
    EXPECT_LE(sorted.back(), 0.5) << "inducing " << inducing;
    // Each frame on its own: the same point as with the others.
    const Eigen::MatrixXd one = c.X.row(17);
    EXPECT_EQ(place(model, {.features = &one}).row(0), placed.row(17));
  }
}

// A frame the map was not fitted on lands near its neighbours in time: fitted on the clip less
// every 6th frame (CMU 64_08, a golf swing, every 4th frame: 30 frames a second), the kept frame
// whose latent point is nearest where a held-out frame lands is within 10 frames (1/3 s) of it for
// every held-out frame (by chance: about 1 in 4 each), and for the full model within 2 frames
// for 13 of the 15 (measured: 14 within 1). The swing's still address pose, frames 0–20, is one
// blurred region: a frame held out of it may land by any frame of it (the sparse model's, 30
// inducing points; with ℓ held at 1, the full model's too: 15 → 0).
TEST(GplvmPlace, AHeldOutFrameLandsNearItsNeighboursInTime) {
  const Eigen::MatrixXd all = clip_features();
  std::vector<int> kept, held;
  for (int f = 0; f < all.rows(); ++f) (f % 6 == 3 ? held : kept).push_back(f);
  Eigen::MatrixXd train(Eigen::Index(kept.size()), all.cols());
  Eigen::MatrixXd test_rows(Eigen::Index(held.size()), all.cols());
  for (std::size_t i = 0; i < kept.size(); ++i) train.row(Eigen::Index(i)) = all.row(kept[i]);
  for (std::size_t i = 0; i < held.size(); ++i) test_rows.row(Eigen::Index(i)) = all.row(held[i]);
  for (int inducing : {0, 30}) {
    FittedClip c = fit_clip(train, inducing);
    const Eigen::MatrixXd latent = c.map.coordinates;
    EmbedOptions o;
    o.method = Method::Gplvm;
    const MapModel model = make_model({.features = &c.X}, o, std::move(c.map));
    const Eigen::MatrixXd placed = place(model, {.features = &test_rows});
    int within_2 = 0, within_10 = 0;
    std::string report;
    for (std::size_t i = 0; i < held.size(); ++i) {
      Eigen::Index nearest = 0;
      (latent.rowwise() - placed.row(Eigen::Index(i))).rowwise().squaredNorm().minCoeff(&nearest);
      const int apart = std::abs(kept[std::size_t(nearest)] - held[i]);
      within_2 += apart <= 2;
      within_10 += apart <= 10 || (held[i] <= 20 && kept[std::size_t(nearest)] <= 20);
      report += " " + std::to_string(held[i]) + "→" + std::to_string(kept[std::size_t(nearest)]);
    }
    EXPECT_EQ(within_10, int(held.size())) << "inducing " << inducing << ":" << report;
    if (inducing == 0) {
      EXPECT_GE(within_2, 13) << report;
    }
    EXPECT_TRUE(placed.allFinite());
  }
}

}  // namespace
}  // namespace motionmap::embed
