// The whole pipeline — clip → X, D → the six maps — against tests/reference/make_fixtures.py,
// whose X and D come from an independent NumPy/SciPy reading of the same BVH
// (tests/reference/mocap.py). Fixture folders whose X.txt names a `source` are clip cases.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "embed/embed_test_util.h"
#include "motionmap/embed/embed.h"
#include "motionmap/features/features.h"
#include "motionmap/io/bvh.h"
#include "motionmap/sample/sample_clip.h"
#include "support/test_data.h"

namespace motionmap {
namespace {

std::vector<std::string> clip_cases() {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& dir : std::filesystem::directory_iterator(test::fixture_dir(), ec)) {
    const auto x = dir.path() / "X.txt";
    if (std::filesystem::exists(x) && test::read_fixture(x.string()).has("source")) {
      out.push_back(dir.path().filename().string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

class ClipReference : public ::testing::TestWithParam<std::string> {};

TEST_P(ClipReference, FeaturesAndMapsMatchIndependentImplementation) {
  const std::string folder = test::fixture_dir() + "/" + GetParam();
  const test::Fixture x_ref = test::read_fixture(folder + "/X.txt");
  const test::Fixture d_ref = test::read_fixture(folder + "/D.txt");
  const std::string source = x_ref.header.at("source");

  Clip clip;
  if (source.rfind("sample:", 0) == 0) {
    // The fixture was made from `motionmap sample --kind <kind>` written to BVH; reading the
    // written file back gives exactly the values Python read.
    const auto kind = sample::parse_sample_kind(source.substr(7));
    ASSERT_TRUE(kind.has_value()) << source;
    const Clip generated = sample::make_sample_clip(*kind);
    std::ostringstream text;
    io::write_bvh(io::from_motion(generated.skeleton, generated.motion), text);
    const io::BvhDocument doc = io::parse_bvh(text.str(), source);
    clip.path = source;
    clip.skeleton = doc.skeleton;
    clip.motion = io::to_motion(doc);
  } else {
    MOTIONMAP_REQUIRE_SHARED(source);
    clip = io::load_bvh(test::shared_file(source));
  }

  features::FeatureOptions options;
  options.stride = static_cast<int>(x_ref.number("stride"));
  const features::FeatureSet set =
      features::build_features(std::span<const Clip>(&clip, 1), options);
  const Eigen::VectorXd frames = x_ref.numbers("frames");
  ASSERT_EQ(set.num_samples(), frames.size());
  for (int i = 0; i < set.num_samples(); ++i) EXPECT_EQ(set.frame_of[i], frames[i]) << i;

  // X: quaternions, sign-consistent; D: heading-local point-cloud distances.
  ASSERT_EQ(set.X.rows(), x_ref.matrix.rows());
  ASSERT_EQ(set.X.cols(), x_ref.matrix.cols());
  EXPECT_LE((set.X - x_ref.matrix).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LE((set.D - d_ref.matrix).cwiseAbs().maxCoeff(), 1e-9 * d_ref.matrix.maxCoeff());

  for (embed::Method method : embed::all_methods()) {
    // umap is stochastic: checked against umap-learn by its quality (tests/embed/umap_test.cpp);
    // gplvm is an optimisation: its objective is checked against numpy
    // (tests/embed/gplvm_test.cpp).
    if (method == embed::Method::Umap || method == embed::Method::Gplvm) continue;
    const std::string name(embed::method_name(method));
    const test::Fixture want = test::read_fixture(folder + "/" + name + ".txt");
    embed::EmbedOptions eopt;
    eopt.method = method;
    eopt.k = static_cast<int>(want.number("k"));
    const embed::Embedding map = embed::embed({&set.X, &set.D}, eopt);
    const double target =
        (method == embed::Method::LaplacianEigenmap || method == embed::Method::Lle) ? 1e-6 : 1e-8;
    const double disparity = test::procrustes_disparity(want.matrix, map.coordinates);
    EXPECT_LE(disparity, target) << GetParam() << "/" << name;
    std::printf("[ disparity ] %s/%s (from the clip): %.3g\n", GetParam().c_str(), name.c_str(),
                disparity);
  }
}

INSTANTIATE_TEST_SUITE_P(Fixtures, ClipReference, ::testing::ValuesIn(clip_cases()),
                         [](const auto& info) { return info.param; });
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ClipReference);

}  // namespace
}  // namespace motionmap
