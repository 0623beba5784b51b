// embed(): names, option and input validation (every message), equivalences between methods,
// the sign convention, determinism, progress, cancellation, disconnected graphs, degenerate input.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/embed.h"
#include "support/error_message.h"

namespace motionmap::embed {
namespace {

using ::testing::HasSubstr;

using test::error_message;

EmbedOptions with(Method method, int k = 10) {
  EmbedOptions o;
  o.method = method;
  o.k = k;
  o.max_iterations = 40;  // gplvm: enough to move every point, fast
  return o;
}

struct Data {
  Eigen::MatrixXd X;
  Eigen::MatrixXd D;
};

Data trajectory(int frames = 120, int dims = 6) {
  Data d;
  d.X = test::smooth_trajectory(frames, dims);
  d.D = test::euclidean_distances(d.X);
  return d;
}

Embedding run(const Data& d, const EmbedOptions& o, const Control& control = {}) {
  return embed({.features = &d.X, .distances = &d.D}, o, control);
}

// ------------------------------------------------------------------------------------------
// Names

TEST(EmbedNames, RoundTripEveryMethod) {
  const std::vector<std::string> names = {"pca", "svd", "mds",  "isomap",
                                          "le",  "lle", "umap", "gplvm"};
  ASSERT_EQ(all_methods().size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(method_name(all_methods()[i]), names[i]);
    EXPECT_EQ(parse_method(names[i]), all_methods()[i]);
  }
  EXPECT_EQ(parse_method("PCA"), std::nullopt);
  EXPECT_EQ(parse_method("laplacian"), std::nullopt);
  EXPECT_EQ(parse_method(""), std::nullopt);
}

// ------------------------------------------------------------------------------------------
// Validation: every error names the parameter, the value and the valid range.

TEST(EmbedValidation, MissingInputs) {
  const Data d = trajectory(20);
  EXPECT_THAT(error_message<ParameterError>([&] { embed({.distances = &d.D}, with(Method::Pca)); }),
              HasSubstr("pca: this method needs the feature matrix X (#frames by #features); "
                        "none was given"));
  EXPECT_THAT(
      error_message<ParameterError>([&] { embed({.features = &d.X}, with(Method::Isomap)); }),
      HasSubstr("isomap: this method needs the distance matrix D (#frames by #frames) or the "
                "points it is computed from; neither was given"));
  EXPECT_THAT(error_message<ParameterError>([&] { embed({.features = &d.X}, with(Method::Lle)); }),
              HasSubstr("lle: this method needs the distance matrix D"));
  EXPECT_THAT(error_message<ParameterError>([&] { embed({.distances = &d.D}, with(Method::Lle)); }),
              HasSubstr("lle: this method needs the feature matrix X"));
  // A method reads only what it needs.
  EXPECT_NO_THROW(embed({.features = &d.X}, with(Method::Svd)));
  EXPECT_NO_THROW(embed({.distances = &d.D}, with(Method::LaplacianEigenmap, 5)));
}

TEST(EmbedValidation, EmptyInputs) {
  const Eigen::MatrixXd empty;
  EXPECT_THAT(
      error_message<ParameterError>([&] { embed({.features = &empty}, with(Method::Pca)); }),
      HasSubstr("pca: the feature matrix X is empty (0 by 0); expected #frames by "
                "#features with both ≥ 1"));
  EXPECT_THAT(
      error_message<ParameterError>([&] { embed({.distances = &empty}, with(Method::Mds)); }),
      HasSubstr("mds: the distance matrix D is 0 by 0; expected #frames by #frames"));
}

TEST(EmbedValidation, NonFiniteValues) {
  Data d = trajectory(20);
  d.X(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, with(Method::Pca)); }),
              HasSubstr("pca: X(3, 1) is nan; every feature must be finite"));
  d = trajectory(20);
  d.D(2, 5) = d.D(5, 2) = std::numeric_limits<double>::infinity();
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, with(Method::Mds)); }),
              HasSubstr("mds: D(5, 2) is inf; every distance must be finite"));
}

TEST(EmbedValidation, MalformedDistanceMatrix) {
  Data d = trajectory(20);
  const Eigen::MatrixXd rect = d.D.leftCols(19);
  EXPECT_THAT(
      error_message<ParameterError>([&] { embed({.distances = &rect}, with(Method::Mds)); }),
      HasSubstr("mds: the distance matrix D is 20 by 19; expected #frames by #frames"));

  Data asym = d;
  asym.D(7, 4) += 0.5;
  EXPECT_THAT(error_message<ParameterError>([&] { run(asym, with(Method::Isomap)); }),
              HasSubstr("isomap: D is not symmetric: D(7, 4) = "));
  EXPECT_THAT(error_message<ParameterError>([&] { run(asym, with(Method::Isomap)); }),
              HasSubstr(" but D(4, 7) = "));

  Data negative = d;
  negative.D(1, 6) = negative.D(6, 1) = -1.0;
  EXPECT_THAT(
      error_message<ParameterError>([&] { run(negative, with(Method::LaplacianEigenmap)); }),
      HasSubstr("le: D(6, 1) = -1 is negative; distances must be ≥ 0"));

  Data diagonal = d;
  diagonal.D(9, 9) = 0.25;
  EXPECT_THAT(error_message<ParameterError>([&] { run(diagonal, with(Method::Mds)); }),
              HasSubstr("mds: D(9, 9) = 0.25; the diagonal of a distance matrix must be 0"));

  // Rounding-level asymmetry is accepted.
  Data nearly = d;
  nearly.D(7, 4) *= 1.0 + 1e-14;
  EXPECT_NO_THROW(run(nearly, with(Method::Mds)));
}

TEST(EmbedValidation, RowCountsMustAgree) {
  const Data d = trajectory(20);
  const Eigen::MatrixXd X = d.X.topRows(18);
  EXPECT_THAT(error_message<ParameterError>(
                  [&] { embed({.features = &X, .distances = &d.D}, with(Method::Lle, 5)); }),
              HasSubstr("lle: X has 18 rows but D has 20; both need one per frame"));
}

TEST(EmbedValidation, NeighbourCount) {
  const Data d = trajectory(10);
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, with(Method::Isomap, 10)); }),
              HasSubstr("isomap: k = 10 is out of range: with 10 frames it must be in [1, 9]"));
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, with(Method::LaplacianEigenmap, 0)); }),
              HasSubstr("le: k = 0 is out of range: with 10 frames it must be in [1, 9]"));
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, with(Method::Lle, -3)); }),
              HasSubstr("lle: k = -3 is out of range"));
  // k is not used by the other methods, so the default 20 is fine on 10 frames.
  EXPECT_NO_THROW(run(d, with(Method::Pca, 20)));
  EXPECT_NO_THROW(run(d, with(Method::Mds, 20)));
}

TEST(EmbedValidation, DimensionsAndFrameCount) {
  const Data d = trajectory(10);
  EmbedOptions o = with(Method::Pca);
  o.dimensions = 4;
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, o); }),
              HasSubstr("pca: dimensions = 4 is out of range; valid values are 2 and 3"));
  o.dimensions = 1;
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, o); }), HasSubstr("dimensions = 1"));
  const Data tiny = trajectory(3);
  EXPECT_THAT(error_message<ParameterError>([&] { run(tiny, with(Method::Mds)); }),
              HasSubstr("mds: the clip has 3 frame(s); a 2-D map needs at least 4"));
  const Eigen::MatrixXd one_column = d.X.leftCols(1);
  EXPECT_THAT(
      error_message<ParameterError>([&] { embed({.features = &one_column}, with(Method::Svd)); }),
      HasSubstr("svd: X has 1 column(s); a 2-D map needs at least 2"));
}

TEST(EmbedValidation, HeatAndRegularisation) {
  const Data d = trajectory(20);
  EmbedOptions le = with(Method::LaplacianEigenmap, 5);
  le.heat = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, le); }),
              HasSubstr("le: heat = nan is not finite"));
  EmbedOptions lle = with(Method::Lle, 5);
  lle.reg = 0.0;
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, lle); }),
              HasSubstr("lle: reg = 0 is out of range; it must be a finite number > 0"));
  lle.reg = -1e-3;
  EXPECT_THAT(error_message<ParameterError>([&] { run(d, lle); }), HasSubstr("reg = -0.001"));
}

TEST(EmbedValidation, ValidateAloneChecksOptions) {
  EmbedOptions o = with(Method::Isomap, 25);
  EXPECT_THAT(error_message<ParameterError>([&] { o.validate(20); }),
              HasSubstr("k = 25 is out of range: with 20 frames it must be in [1, 19]"));
  EXPECT_NO_THROW(o.validate(26));
}

// ------------------------------------------------------------------------------------------
// Equivalences and known answers

TEST(EmbedEquivalence, MdsOfEuclideanDistancesIsPca) {
  const Data d = trajectory(150, 5);    // dense eigen path
  const Data big = trajectory(400, 7);  // Lanczos path
  for (const Data* data : {&d, &big}) {
    const Embedding pca = run(*data, with(Method::Pca));
    const Embedding mds = run(*data, with(Method::Mds));
    const double scale = pca.coordinates.cwiseAbs().maxCoeff();
    EXPECT_LE((pca.coordinates - mds.coordinates).cwiseAbs().maxCoeff(), 1e-8 * scale);
    const double frames = double(data->X.rows());
    EXPECT_NEAR(mds.eigenvalues[0], pca.eigenvalues[0] * (frames - 1), 1e-8 * mds.eigenvalues[0]);
    EXPECT_NEAR(mds.eigenvalues[1], pca.eigenvalues[1] * (frames - 1), 1e-8 * mds.eigenvalues[0]);
    // Euclidean distances: B is positive semi-definite.
    EXPECT_EQ(mds.negative.most_negative, 0.0);
    EXPECT_EQ(mds.negative.relative, 0.0);
  }
}

TEST(EmbedEquivalence, IsomapWithAllNeighboursIsMds) {
  for (int frames : {90, 260}) {
    const Data d = trajectory(frames, 5);
    const Embedding mds = run(d, with(Method::Mds));
    const Embedding iso = run(d, with(Method::Isomap, frames - 1));
    EXPECT_EQ(iso.graph_components, 1);
    EXPECT_EQ(iso.k_used, frames - 1);
    const double scale = mds.coordinates.cwiseAbs().maxCoeff();
    EXPECT_LE((mds.coordinates - iso.coordinates).cwiseAbs().maxCoeff(), 1e-9 * scale);
    EXPECT_NEAR(*iso.stress, *mds.stress, 1e-9);
  }
}

TEST(EmbedEquivalence, SvdOfCentredDataIsPca) {
  Data d = trajectory(80, 6);
  const Embedding pca = run(d, with(Method::Pca));
  d.X = d.X.rowwise() - d.X.colwise().mean();
  const Embedding svd = embed({.features = &d.X}, with(Method::Svd));
  const double scale = pca.coordinates.cwiseAbs().maxCoeff();
  EXPECT_LE((pca.coordinates - svd.coordinates).cwiseAbs().maxCoeff(), 1e-10 * scale);
}

TEST(EmbedEquivalence, CorrelationPcaIgnoresColumnScale) {
  Data d = trajectory(60, 4);
  EmbedOptions o = with(Method::Pca);
  o.standardize = true;
  const Embedding a = run(d, o);
  d.X.col(2) *= 1000.0;
  d.X.col(0) = d.X.col(0).array() + 5.0;
  const Embedding b = run(d, o);
  EXPECT_LE((a.coordinates - b.coordinates).cwiseAbs().maxCoeff(), 1e-9);
  // A constant column stays 0 (no division by zero) and is reported.
  d.X.col(3).setConstant(7.0);
  const Embedding c = run(d, o);
  EXPECT_TRUE(c.coordinates.allFinite());
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_THAT(c.warnings[0], HasSubstr("1 constant feature column(s) were left unscaled"));
}

TEST(EmbedKnownAnswer, LaplacianEigenmapOfARingIsACircle) {
  // n frames evenly on a circle, k = 2: the ring graph, all weights equal. Its Laplacian's 2nd
  // and 3rd eigenvalues are both 1 − cos(2π/n) with eigenvectors cos and sin: a circle.
  // (60 frames: dense eigen path; 300: shift-invert Lanczos.)
  for (int n : {60, 300})
    for (std::optional<double> heat : {std::optional<double>(), std::optional<double>(0.0)}) {
      Eigen::MatrixXd X(n, 2);
      for (int i = 0; i < n; ++i)
        X.row(i) << std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n);
      const Eigen::MatrixXd D = test::euclidean_distances(X);
      EmbedOptions o = with(Method::LaplacianEigenmap, 2);
      o.heat = heat;
      const Embedding le = embed({.distances = &D}, o);
      const double expected = 1.0 - std::cos(2 * M_PI / n);
      EXPECT_NEAR(le.eigenvalues[0], expected, 1e-10);
      EXPECT_NEAR(le.eigenvalues[1], expected, 1e-10);
      const Eigen::VectorXd radius = le.coordinates.rowwise().norm();
      EXPECT_LE(radius.maxCoeff() - radius.minCoeff(), 1e-8);
      // yᵀ·Deg·y = 1 with Deg = 2·w: Σ y² = 1/(2w) per axis; both axes together 1/w.
      const double w = heat ? 1.0 : std::exp(-D(0, 1) * D(0, 1) / le.heat_used);
      EXPECT_NEAR(le.coordinates.squaredNorm(), 1.0 / w, 1e-9 / w);
    }
}

// ------------------------------------------------------------------------------------------
// Sign convention and determinism

TEST(EmbedDeterminism, SignConventionAndIdenticalBits) {
  const Data d = trajectory(300, 8);
  for (Method m : all_methods()) {
    const Embedding a = run(d, with(m));
    const Embedding b = run(d, with(m));
    ASSERT_EQ(a.coordinates.size(), b.coordinates.size());
    EXPECT_EQ(std::memcmp(a.coordinates.data(), b.coordinates.data(),
                          sizeof(double) * std::size_t(a.coordinates.size())),
              0)
        << method_name(m);
    for (Eigen::Index c = 0; c < a.coordinates.cols(); ++c) {
      Eigen::Index arg;
      a.coordinates.col(c).cwiseAbs().maxCoeff(&arg);
      EXPECT_GT(a.coordinates(arg, c), 0.0) << method_name(m) << " axis " << c;
    }
    EXPECT_TRUE(a.coordinates.allFinite());
  }
}

TEST(EmbedDeterminism, ThreeDimensions) {
  const Data d = trajectory(250, 8);
  for (Method m : all_methods()) {
    EmbedOptions o = with(m);
    o.dimensions = 3;
    const Embedding e = run(d, o);
    EXPECT_EQ(e.coordinates.cols(), 3);
    EXPECT_EQ(e.eigenvalues.size(), 3);
    // The axes are ordered: descending for pca/svd/mds/isomap (and gplvm, whose eigenvalues are
    // its PCA start's), ascending for le/lle (and umap, whose are its spectral start's).
    const bool bottom = m == Method::LaplacianEigenmap || m == Method::Lle || m == Method::Umap;
    for (int a = 0; a + 1 < 3; ++a) {
      if (bottom) {
        EXPECT_LE(e.eigenvalues[a], e.eigenvalues[a + 1]) << method_name(m);
      } else {
        EXPECT_GE(e.eigenvalues[a], e.eigenvalues[a + 1]) << method_name(m);
      }
    }
  }
}

// ------------------------------------------------------------------------------------------
// Progress and cancellation

TEST(EmbedProgress, MonotonicFromZeroToOne) {
  const Data d = trajectory(300, 8);
  for (Method m : all_methods()) {
    std::vector<double> fractions;
    std::vector<std::string> stages;
    const Control control([&](double f, std::string_view stage) {
      fractions.push_back(f);
      if (stages.empty() || stages.back() != stage) stages.emplace_back(stage);
    });
    const Embedding e = run(d, with(m), control);
    ASSERT_GE(fractions.size(), 3u) << method_name(m);
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    for (std::size_t i = 1; i < fractions.size(); ++i) {
      EXPECT_GE(fractions[i], fractions[i - 1]) << method_name(m) << " report " << i;
    }
    EXPECT_EQ(stages.front(), "validate");
    EXPECT_NE(std::find(stages.begin(), stages.end(), "eigen"), stages.end());
    // Timings: one per stage, in order, non-negative.
    ASSERT_FALSE(e.timings.empty());
    EXPECT_EQ(e.timings.front().stage, "validate");
    for (const StageTime& t : e.timings) EXPECT_GE(t.seconds, 0.0);
  }
  std::vector<std::string> stages;
  const Control control([&](double, std::string_view stage) {
    if (stages.empty() || stages.back() != stage) stages.emplace_back(stage);
  });
  run(d, with(Method::Isomap), control);
  EXPECT_EQ(stages, (std::vector<std::string>{"validate", "neighbours", "shortest paths", "eigen",
                                              "stress"}));
}

TEST(EmbedCancel, EveryMethodStopsWhenAsked) {
  const Data d = trajectory(300, 8);
  for (Method m : all_methods()) {
    const Control control({}, [] { return true; });
    EXPECT_THROW(run(d, with(m), control), Cancelled) << method_name(m);
  }
}

TEST(EmbedCancel, InsideLongStages) {
  // Cancel once a given stage has started: the loops inside it (shortest paths on both
  // threads, the eigen solver's products) notice and stop.
  const Data d = trajectory(600, 8);
  for (const auto& [method, stage_] :
       std::vector<std::pair<Method, std::string>>{{Method::Isomap, "shortest paths"},
                                                   {Method::Mds, "eigen"},
                                                   {Method::Lle, "eigen"},
                                                   {Method::LaplacianEigenmap, "neighbours"}}) {
    const std::string& stage = stage_;  // a structured binding no lambda of clang 14 captures
    std::string current;
    int polls_in_stage = 0;
    const Control control([&](double, std::string_view s) { current = s; },
                          [&] { return current == stage && ++polls_in_stage >= 2; });
    EXPECT_THROW(run(d, with(method), control), Cancelled) << method_name(method);
    EXPECT_GE(polls_in_stage, 2) << method_name(method);
  }
}

// ------------------------------------------------------------------------------------------
// Disconnected neighbour graphs

TEST(EmbedDisconnected, JoinedWithAWarningByDefault) {
  Data d;
  d.X = test::two_clusters(40);
  d.D = test::euclidean_distances(d.X);
  for (Method m : {Method::Isomap, Method::LaplacianEigenmap, Method::Lle}) {
    const Embedding e = run(d, with(m, 5));
    EXPECT_EQ(e.graph_components, 2) << method_name(m);
    EXPECT_EQ(e.connecting_edges, 1) << method_name(m);
    ASSERT_EQ(e.warnings.size(), 1u) << method_name(m);
    EXPECT_THAT(e.warnings[0], HasSubstr("the k-NN graph (k = 5) has 2 connected components; "
                                         "joined them with 1 edge(s) between their closest "
                                         "frames"));
    EXPECT_TRUE(e.coordinates.allFinite()) << method_name(m);
    // The clusters stay apart on the map: the first axis separates them.
    const double a_max = e.coordinates.col(0).head(40).maxCoeff();
    const double a_min = e.coordinates.col(0).head(40).minCoeff();
    const double b_max = e.coordinates.col(0).tail(40).maxCoeff();
    const double b_min = e.coordinates.col(0).tail(40).minCoeff();
    EXPECT_TRUE(a_max < b_min || b_max < a_min) << method_name(m);
  }
  // A connected graph reports one component and no joins.
  const Embedding one = run(d, with(Method::Isomap, 45));
  EXPECT_EQ(one.graph_components, 1);
  EXPECT_EQ(one.connecting_edges, 0);
  EXPECT_TRUE(one.warnings.empty());
}

TEST(EmbedDisconnected, StrictModeThrows) {
  Data d;
  d.X = test::two_clusters(30);
  d.D = test::euclidean_distances(d.X);
  for (Method m : {Method::Isomap, Method::LaplacianEigenmap, Method::Lle}) {
    EmbedOptions o = with(m, 4);
    o.strict = true;
    EXPECT_THAT(error_message<NumericalError>([&] { run(d, o); }),
                HasSubstr(std::string(method_name(m)) +
                          ": the k-NN graph (k = 4) has 2 connected components; use a larger k"));
  }
}

// ------------------------------------------------------------------------------------------
// Laplacian eigenmap heat-kernel underflow

TEST(EmbedHeat, FrameWhoseWeightsAllUnderflow) {
  // Frames 0…19 on a line 1 apart, frame 20 far away: with heat 1 its weights exp(−d²) are 0.
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(21, 2);
  for (int i = 0; i < 20; ++i) X(i, 0) = i;
  X(20, 1) = 100.0;
  const Eigen::MatrixXd D = test::euclidean_distances(X);
  EmbedOptions o = with(Method::LaplacianEigenmap, 3);
  o.heat = 1.0;
  const std::string msg = error_message<NumericalError>([&] { embed({.distances = &D}, o); });
  EXPECT_THAT(msg, HasSubstr("le: every heat-kernel weight exp(−d²/heat) of frame 20 underflows "
                             "to 0 (nearest neighbour at distance 100, heat = 1); use heat auto"));
  EXPECT_THAT(msg, HasSubstr("a larger heat, or drop the frame"));
  // The automatic heat (the median squared k-NN distance, here 1) is no better.
  o.heat.reset();
  EXPECT_THAT(error_message<NumericalError>([&] { embed({.distances = &D}, o); }),
              HasSubstr("of frame 20 underflows to 0 (nearest neighbour at distance 100, heat "
                        "auto = 1); use a larger heat, or drop the frame"));
  o.heat = 1e4;
  EXPECT_NO_THROW(embed({.distances = &D}, o));
}

TEST(EmbedHeat, UnderflowThatSplitsTheGraph) {
  // 3 frames far from 20 others: with k = 5 each of the 3 has 3 neighbours across the gap, whose
  // weights underflow, so the weighted graph falls apart though the k-NN graph is connected.
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(23, 2);
  for (int i = 0; i < 20; ++i) X(i, 0) = 0.1 * i;
  for (int i = 0; i < 3; ++i) X(20 + i, 0) = 50.0 + 0.1 * i;
  const Eigen::MatrixXd D = test::euclidean_distances(X);
  EmbedOptions o = with(Method::LaplacianEigenmap, 5);
  o.heat = 1.0;
  EXPECT_THAT(error_message<NumericalError>([&] { embed({.distances = &D}, o); }),
              HasSubstr("le: heat-kernel weights that underflow to 0 split the k-NN graph into 2 "
                        "components (heat = 1); use heat auto"));
}

TEST(EmbedHeat, AutomaticHeatIsTheMedianSquaredNeighbourDistance) {
  // Frames on a line at positions 0, 1, 3, 6, 10, … (gaps 1, 2, 3, …); k = 1: the nearest
  // distances are 1, 1, 2, 3, …, so the squared ones' median is known.
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(7, 1);
  for (int i = 1; i < 7; ++i) X(i, 0) = X(i - 1, 0) + i;
  const Eigen::MatrixXd D = test::euclidean_distances(X);
  const Embedding e = embed({.distances = &D}, with(Method::LaplacianEigenmap, 1));
  // Nearest distances: 1 1 2 3 4 5 6 → squared 1 1 4 9 16 25 36, median 9.
  EXPECT_EQ(e.heat_used, 9.0);
  EmbedOptions unit = with(Method::LaplacianEigenmap, 1);
  unit.heat = -1.0;
  EXPECT_EQ(embed({.distances = &D}, unit).heat_used, 0.0);
}

// ------------------------------------------------------------------------------------------
// Degenerate input: duplicate frames, a static clip

TEST(EmbedDegenerate, DuplicateFramesEverywhere) {
  // Every frame twice. k = 7 (the duplicate + 3 pairs): every frame that chooses one of a pair
  // chooses both, so duplicates keep identical neighbourhoods (with an odd number of others,
  // ties by index would take one of a pair and not the other, and LE would separate them).
  const Eigen::MatrixXd base = test::smooth_trajectory(60, 5);
  Data d;
  d.X.resize(120, 5);
  for (int i = 0; i < 60; ++i) d.X.row(2 * i) = d.X.row(2 * i + 1) = base.row(i);
  d.D = test::euclidean_distances(d.X);
  for (Method m : all_methods()) {
    const Embedding e = run(d, with(m, 7));
    EXPECT_TRUE(e.coordinates.allFinite()) << method_name(m);
    // Duplicates land on the same point.
    for (int i = 0; i < 60; ++i) {
      EXPECT_LE((e.coordinates.row(2 * i) - e.coordinates.row(2 * i + 1)).norm(),
                1e-6 * e.coordinates.cwiseAbs().maxCoeff())
          << method_name(m) << " frame " << 2 * i;
    }
  }
}

TEST(EmbedDegenerate, StaticClip) {
  Data d;
  d.X = Eigen::MatrixXd::Constant(40, 6, 2.5);
  d.D = Eigen::MatrixXd::Zero(40, 40);
  for (Method m : all_methods()) {
    const Embedding e = run(d, with(m, 5));
    EXPECT_TRUE(e.coordinates.allFinite()) << method_name(m);
    if (m == Method::Pca || m == Method::Mds || m == Method::Isomap) {
      EXPECT_EQ(e.coordinates.cwiseAbs().maxCoeff(), 0.0) << method_name(m);
      EXPECT_FALSE(e.warnings.empty()) << method_name(m);
    }
  }
}

TEST(EmbedDegenerate, NonEuclideanDistancesReportNegativeEigenvalues) {
  // Geodesic-like distances on a ring of 30 frames (arc length) are not Euclidean.
  for (int n : {30, 240}) {
    Eigen::MatrixXd D(n, n);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) D(i, j) = std::min(std::abs(i - j), n - std::abs(i - j));
    }
    const Embedding e = embed({.distances = &D}, with(Method::Mds));
    // The whole spectrum of B, densely, for comparison.
    const Eigen::MatrixXd J =
        Eigen::MatrixXd::Identity(n, n) - Eigen::MatrixXd::Constant(n, n, 1.0 / n);
    const Eigen::MatrixXd B = -0.5 * J * D.array().square().matrix() * J;
    const Eigen::VectorXd all = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(B).eigenvalues();
    EXPECT_LT(e.negative.most_negative, 0.0) << n;
    // Never more negative than the truth, and close to it.
    EXPECT_GE(e.negative.most_negative, all[0] - 1e-9 * all[n - 1]) << n;
    EXPECT_LE(e.negative.most_negative, 0.9 * all[0]) << n;
    EXPECT_GT(e.negative.relative, 0.01) << n;
    EXPECT_NEAR(e.negative.relative, -e.negative.most_negative / e.eigenvalues[0], 1e-15);
    if (n <= 200) {
      ASSERT_TRUE(e.negative.count.has_value());
      EXPECT_GT(*e.negative.count, 0);
    } else {
      EXPECT_FALSE(e.negative.count.has_value());
    }
  }
}

}  // namespace
}  // namespace motionmap::embed
