// A GP-LVM map saved and read back (mapfile/, /model/gplvm): what placing frames needs comes back
// bit for bit with the fit's max_iterations and inducing, and frames placed on the file land where
// they land on the map in memory.
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/embed/placement.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "support/error_message.h"
#include "support/map_edit.h"
#include "support/test_data.h"

namespace motionmap::mapfile {
namespace {

class TempDir {
 public:
  TempDir() {
    m_path = std::filesystem::temp_directory_path() /
             ("motionmap-gplvm-mapfile-" + std::to_string(::getpid()));
    std::filesystem::remove_all(m_path);
    std::filesystem::create_directories(m_path);
  }
  ~TempDir() { std::filesystem::remove_all(m_path); }
  std::string file(const std::string& name) const { return (m_path / name).string(); }

 private:
  std::filesystem::path m_path;
};

TEST(GplvmMapFile, SavedMapsPlaceFramesAsTheMapInMemoryDoes) {
  const TempDir dir;
  const std::vector<Clip> clips{io::load_clip(test::shared_file("cmu/64_08.bvh"))};
  const std::vector<Clip> other{io::load_clip(test::shared_file("cmu/64_09.bvh"))};
  for (int inducing : {0, 20}) {  // the full model and the sparse one
    SCOPED_TRACE("inducing " + std::to_string(inducing));
    pipeline::ClipMapOptions options;
    options.embed.method = embed::Method::Gplvm;
    options.embed.max_iterations = 10;
    options.embed.inducing = inducing;
    options.embed.lengthscale = inducing > 0 ? 0.0 : 1.0;  // fitted (the default), and held
    options.features.stride = 3;
    const pipeline::ClipMap map = pipeline::map_clips(clips, options);
    const MapFile made = make_map_file(clips, map, options);
    const std::string path = dir.file("gplvm.mmap.h5");
    write_map_file(path, made);
    const MapFile read = read_map_file(path);
    const embed::GplvmPredictive &a = made.model.gplvm, &b = read.model.gplvm;
    EXPECT_EQ(a.basis.rows(), inducing > 0 ? inducing : map.embedding.coordinates.rows());
    EXPECT_EQ(a.basis, b.basis);
    EXPECT_EQ(a.alpha, b.alpha);
    EXPECT_EQ(a.C, b.C);
    EXPECT_EQ(a.rbf_variance, b.rbf_variance);
    EXPECT_EQ(a.lengthscale, b.lengthscale);
    EXPECT_EQ(a.bias_variance, b.bias_variance);
    EXPECT_EQ(a.prior_variance, b.prior_variance);
    EXPECT_EQ(made.model.mean, read.model.mean);
    EXPECT_EQ(made.model.features, read.model.features);
    // The fit's options come back too (read_map's GPLVM(max_iter=, n_inducing=, lengthscale=) in
    // Python).
    EXPECT_EQ(read.options.embed.max_iterations, 10);
    EXPECT_EQ(read.options.embed.inducing, inducing);
    EXPECT_EQ(read.options.embed.lengthscale, options.embed.lengthscale);
    // Another clip, every 20th frame: the same places from the file as from memory.
    PlaceOptions some;
    some.stride = 20;
    const Placement from_file = place_clips(other, read, some);
    const Placement from_memory = place_clips(other, made, some);
    ASSERT_GT(from_file.coordinates.rows(), 10);
    EXPECT_TRUE(from_file.coordinates.allFinite());
    EXPECT_EQ(from_file.coordinates, from_memory.coordinates);
  }
}

// A GP-LVM file edited (and resealed, as another program would write it) so that its predictive
// cannot be used: each is refused, naming what is wrong, instead of placing frames with it.
TEST(GplvmMapFile, APredictiveThatCannotBeUsedIsRefusedNamingIt) {
  const TempDir dir;
  const std::vector<Clip> clips{io::load_clip(test::shared_file("cmu/64_08.bvh"))};
  pipeline::ClipMapOptions options;
  options.embed.method = embed::Method::Gplvm;
  options.embed.max_iterations = 5;
  options.features.stride = 6;
  const pipeline::ClipMap map = pipeline::map_clips(clips, options);
  const MapFile good = make_map_file(clips, map, options);
  const auto B = static_cast<hsize_t>(good.model.gplvm.basis.rows());
  int count = 0;
  auto refused = [&](const std::function<void(test::Edit&)>& edit) {
    const std::string path = dir.file("bad" + std::to_string(count++) + ".mmap.h5");
    write_map_file(path, good);
    {
      test::Edit e(path);
      edit(e);
    }
    return test::error_message([&] { read_map_file(path); });
  };
  auto has = [](const std::string& message, const std::string& part) {
    EXPECT_NE(message.find(part), std::string::npos) << message;
  };
  has(refused([](test::Edit& e) { e.remove("/model/gplvm"); }), "/model/gplvm");
  has(refused([](test::Edit& e) { e.int_attribute("/model/gplvm", "lengthscale", -1); }),
      "/model/gplvm: the kernel's variances and lengthscale must be > 0");
  has(refused([](test::Edit& e) { e.remove_attribute("/model/gplvm", "rbf_variance"); }),
      "rbf_variance");
  has(refused([](test::Edit& e) { e.replace("/model/gplvm/basis", 0, 2, H5T_NATIVE_DOUBLE, 0.0); }),
      "/model/gplvm/basis has no rows");
  has(refused([&](test::Edit& e) {
        e.replace("/model/gplvm/C", B + 1, B + 1, H5T_NATIVE_DOUBLE, 0.0);
      }),
      "/model/gplvm/C");
  has(refused(
          [&](test::Edit& e) { e.replace("/model/gplvm/alpha", B, 3, H5T_NATIVE_DOUBLE, 0.0); }),
      "/model/gplvm/alpha");
}

// A saved gplvm map's blender takes the map's GP (read even without the placement model):
// it blends as the map in memory does in the gp mode. A file whose GP does not belong to its
// coordinates (one edited and resealed, as another program would write it) is refused when it
// is opened, naming why, instead of blending with weights that are not the GP's.
TEST(GplvmMapFile, ASavedMapBlendsWithItsGpAndOneWhoseGpDoesNotBelongIsRefused) {
  const TempDir dir;
  const std::vector<Clip> clips{io::load_clip(test::shared_file("cmu/64_08.bvh"))};
  for (int inducing : {0, 20}) {  // the full model and the sparse one
    SCOPED_TRACE("inducing " + std::to_string(inducing));
    pipeline::ClipMapOptions options;
    options.embed.method = embed::Method::Gplvm;
    options.embed.max_iterations = 5;
    options.embed.inducing = inducing;
    options.features.stride = 6;
    const pipeline::ClipMap map = pipeline::map_clips(clips, options);
    const std::string path = dir.file("gp" + std::to_string(inducing) + ".mmap.h5");
    write_map_file(path, make_map_file(clips, map, options));
    const auto saved = std::make_shared<const SavedMap>(read_map_file(path, {.model = false}));
    ASSERT_TRUE(saved->gplvm());
    synth::BlendOptions gp;
    gp.mode = synth::BlendMode::Gp;
    const synth::MapBlender from_file = make_blender(saved, gp);
    gp.gplvm = pipeline::map_gplvm(map);
    const synth::MapBlender in_memory(clips, *map.features, map.embedding.coordinates, gp);
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(map.embedding.coordinates.row(4).transpose()),
                                     Eigen::Vector2d(0.3, -0.2), Eigen::Vector2d(40.0, 40.0)}) {
      const synth::MapWeights a = from_file.locate(p), b = in_memory.locate(p);
      EXPECT_EQ(a.validity.clamped, b.validity.clamped);
      EXPECT_EQ(a.validity.point, b.validity.point);
      EXPECT_EQ(a.samples, b.samples);
      EXPECT_EQ(a.weights, b.weights);
    }
    EXPECT_TRUE(from_file.locate(Eigen::Vector2d(40.0, 40.0)).validity.clamped);

    const std::string moved = dir.file("moved" + std::to_string(inducing) + ".mmap.h5");
    write_map_file(moved, make_map_file(clips, map, options));
    {
      test::Edit e(moved);
      e.set("/coordinates", 3, 0, map.embedding.coordinates(3, 0) + 0.3);
    }
    const std::string message =
        test::error_message([&] { SavedMap(read_map_file(moved, {.model = false})); });
    EXPECT_NE(message.find(moved), std::string::npos) << message;
    EXPECT_NE(message.find(inducing ? "does not belong to these frames"
                                    : "basis is not the latent points"),
              std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace motionmap::mapfile
