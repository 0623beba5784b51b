// Studio on a GP-LVM map file: its blender blends with the GP's predictive mean (the gp mode)
// and View → Shade trustworthy blends draws the GP's rule of where the map is valid
// (embed::GplvmMap::inside), from a grid of the GP's variance, as the exact rule says to a few
// pixels in a thousand along its edge, whole and zoomed onto the edge.
#include <unistd.h>

#include <QAction>
#include <QElapsedTimer>
#include <QImage>
#include <QTest>
#include <cstdio>
#include <filesystem>

#include "map/map_view.h"
#include "motionmap/embed/gplvm.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

namespace fs = std::filesystem;

// Pixels of the shading layer inside the plot (every third row and column) whose shading
// disagrees with the GP's rule at their centres, and how many were looked at and shaded.
struct Agreement {
  int looked = 0, shaded = 0, disagree = 0;
};
Agreement compare(const MapView& view, const MapGp& gp) {
  const QImage layer = view.shadingLayer();
  Agreement a;
  EXPECT_FALSE(layer.isNull());
  if (layer.isNull()) return a;
  const QRect plot = view.plotRect().toAlignedRect().adjusted(1, 1, -1, -1);
  for (int y = plot.top(); y <= plot.bottom(); y += 3) {
    for (int x = plot.left(); x <= plot.right(); x += 3) {
      const bool inside = gp.inside(view.toMap(QPointF(x + 0.5, y + 0.5)));
      const bool shaded = qAlpha(layer.pixel(x, y)) != 0;
      a.shaded += shaded;
      a.disagree += shaded != inside;
      ++a.looked;
    }
  }
  return a;
}

TEST(StudioGplvm, ShadesTheGpsRuleAndBlendsItsPredictiveMean) {
  const std::string clip_path = MOTIONMAP_SHARED_DATA "/cmu/64_08.bvh";
  if (!fs::exists(clip_path)) GTEST_SKIP() << "no " << clip_path;
  const fs::path dir =
      fs::temp_directory_path() / ("motionmap-studio-gplvm-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::vector<Clip> clips{io::load_clip(clip_path)};
  pipeline::ClipMapOptions options;
  options.embed.method = embed::Method::Gplvm;
  options.embed.max_iterations = 40;
  options.features.stride = 2;
  const pipeline::ClipMap map = pipeline::map_clips(clips, options);
  const std::string file = (dir / "gp.mmap.h5").string();
  mapfile::write_map_file(file, mapfile::make_map_file(clips, map, options));

  auto window = std::make_unique<MainWindow>();
  window->setInteractive(false);
  window->resize(1000, 600);
  window->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(window.get()));
  ASSERT_TRUE(window->openMapFile(QString::fromStdString(file)));
  const mapfile::SavedMap* saved = window->savedMap();
  ASSERT_NE(saved, nullptr);
  ASSERT_TRUE(saved->gplvm());
  const MapGp& gp = *saved->gplvm();
  // The blender the sketches and keys use: the GP's blend and rule.
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return window->currentMap() != nullptr; }, testing::kTimeoutMs));
  ASSERT_NE(window->currentMap()->blender, nullptr);
  EXPECT_EQ(window->currentMap()->blender->options().mode, synth::BlendMode::Gp);
  EXPECT_EQ(window->currentMap()->blender->options().gplvm, saved->gplvm());

  MapView* view = window->mapView();
  for (QAction* a : window->findChildren<QAction*>())
    if (a->text().contains("Shade")) a->setChecked(true);
  ASSERT_TRUE(view->shadingVisible());
  QElapsedTimer clock;
  clock.start();
  (void)view->shadingLayer();  // builds the GP's field
  const double first = double(clock.nsecsElapsed()) * 1e-6;
  clock.restart();
  (void)view->shadingLayer();
  const double again = double(clock.nsecsElapsed()) * 1e-6;
  const Agreement whole = compare(*view, gp);
  // The frames' own points are shaded.
  const Eigen::MatrixXd& xy = saved->file().coordinates;
  const QImage layer = view->shadingLayer();
  for (const int row : {0, 60, 120}) {
    const QPoint at = view->toWidget(Eigen::Vector2d(xy(row, 0), xy(row, 1))).toPoint();
    EXPECT_NE(qAlpha(layer.pixel(at)), 0) << "row " << row;
  }
  // Zoomed 6× onto the edge of the region beside frame 30: the pixels decided from the grid.
  const Eigen::Vector2d x30(xy(30, 0), xy(30, 1));
  Eigen::Vector2d edge = x30;
  while (gp.inside(edge)) edge.x() += 0.02 * gp.lengthscale();
  view->zoomAt(view->toWidget(edge), 6.0);
  clock.restart();
  (void)view->shadingLayer();
  const double zoom = double(clock.nsecsElapsed()) * 1e-6;
  const Agreement zoomed = compare(*view, gp);
  std::printf(
      "gplvm shading: whole map %d of %d pixels shaded, %d disagree with the GP's rule; zoomed "
      "6x %d of %d, %d disagree; the first layer (with the field) %.0f ms, the next %.0f ms, "
      "zoomed %.0f ms\n",
      whole.shaded, whole.looked, whole.disagree, zoomed.shaded, zoomed.looked, zoomed.disagree,
      first, again, zoom);
  EXPECT_GT(whole.shaded, whole.looked / 20);
  EXPECT_LT(whole.shaded, whole.looked);
  EXPECT_GT(zoomed.shaded, zoomed.looked / 20);
  EXPECT_LT(zoomed.shaded, zoomed.looked);
  // The field is exact at its corners and bilinear between (cells ≤ ℓ/8): pixels along the
  // edge may differ, a few in a thousand of the view.
  EXPECT_LE(whole.disagree, whole.looked / 200);
  EXPECT_LE(zoomed.disagree, zoomed.looked / 200);
  window.reset();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace motionmap::studio
