// Compare two clips (View → Compare with clip…, the Compare dock): a second clip of the map plays
// in sync with the one playing (the same time from its start, at its own frame rate), its
// character in the dock's 3-D view and its trajectory on the map with a ring at its frame; on a
// map computed here of two Bandai takes and on a saved map of them. Overlaid, the compared
// character is drawn in the main 3-D view over the one playing (where its clip places it, or on
// the playing one's root), translucent in the comparison colour.
#include <unistd.h>

#include <QComboBox>
#include <QDir>
#include <QLabel>
#include <QPushButton>
#include <QTest>
#include <filesystem>

#include "explore/compare_panel.h"
#include "explore/explore_panels.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

namespace fs = std::filesystem;

const std::string kBandai = std::string(MOTIONMAP_SHARED_DATA) + "/bandai";
const std::string kWalk = kBandai + "/dataset-1_walk_angry_001.bvh";
const std::string kRun = kBandai + "/dataset-1_run_angry_001.bvh";

/// Whether the 3-D view's pose is frame `frame` of `motion` (its joints' rotations).
bool showsFrame(const SkeletonView& view, const Motion& motion, int frame) {
  const Motion& pose = view.currentPose();
  if (pose.num_frames != 1 || pose.num_joints != motion.num_joints) return false;
  for (int j = 0; j < motion.num_joints; ++j) {
    if (std::abs(pose.rotation(0, j).dot(motion.rotation(frame, j))) < 1.0 - 1e-9) return false;
  }
  return true;
}

/// The map row of frame `frame` of clip `clip` (samples in clip order, rows contiguous).
Eigen::Vector2d pointOf(const Eigen::MatrixXd& xy, const std::vector<int>& clipOf,
                        const std::vector<int>& frameOf, int clip, int frame) {
  for (std::size_t i = 0; i < clipOf.size(); ++i)
    if (clipOf[i] == clip && frameOf[i] == frame)
      return {xy(Eigen::Index(i), 0), xy(Eigen::Index(i), 1)};
  return Eigen::Vector2d::Constant(std::nan(""));
}

TEST(StudioCompare, AComputedMapsSecondClipPlaysInSyncBesideTheFirst) {
  if (!fs::exists(kWalk) || !fs::exists(kRun)) GTEST_SKIP() << "no Bandai takes in " << kBandai;
  MainWindow w;
  ASSERT_TRUE(testing::showOnPcaMap(w, {kWalk, kRun}));
  ComparePanel* compare = w.explore()->compare();
  EXPECT_FALSE(compare->isVisible());
  EXPECT_EQ(compare->comparedClip(), -1);
  // Out of range: refused, nothing compared.
  EXPECT_FALSE(compare->compareWith(2));
  EXPECT_TRUE(w.lastError().contains("no clip 3")) << w.lastError().toStdString();
  EXPECT_EQ(compare->comparedClip(), -1);

  ASSERT_TRUE(compare->compareWith(1));
  EXPECT_TRUE(compare->isVisible());
  const Clip run = io::load_clip(kRun);
  const MapResult& map = *w.currentMap();
  const auto& starts = map.map.features->segment_starts;
  const Eigen::MatrixXd& xy = map.map.embedding.coordinates;
  // The run's trajectory on the map: its rows.
  MapView* view = w.mapView();
  ASSERT_EQ(view->comparisonTrajectory().rows(), xy.rows() - starts[1]);
  EXPECT_TRUE(
      view->comparisonTrajectory().isApprox(xy.bottomRows(xy.rows() - starts[1]).leftCols(2)));
  // In sync: frame f of the walk is the run's frame at the same time from its start.
  const int frames = std::min(w.clip()->motion.num_frames, run.motion.num_frames);
  for (const int f : {0, 7, frames / 2, frames - 1}) {
    w.setFrame(f);
    const double t = f * w.clip()->motion.frame_time;
    const int expected =
        std::min(int(std::lround(t / run.motion.frame_time)), run.motion.num_frames - 1);
    EXPECT_EQ(compare->comparedFrame(), expected) << "frame " << f;
    EXPECT_TRUE(showsFrame(*compare->view3d(), run.motion, expected)) << "frame " << f;
    EXPECT_TRUE(showsFrame(*w.skeletonView(), w.clip()->motion, f));  // the walk as before
    ASSERT_TRUE(view->comparisonPoint().has_value());
    EXPECT_TRUE(view->comparisonPoint()->isApprox(
        pointOf(xy, map.map.features->clip_of, map.map.features->frame_of, 1, expected)));
    EXPECT_TRUE(compare->caption()->text().contains(
        QString("frame %1 of %2").arg(expected).arg(run.motion.num_frames)));
  }
  // Past the run's end the run holds its last frame.
  w.setFrame(w.clip()->motion.num_frames - 1);
  EXPECT_EQ(compare->comparedFrame(),
            std::min(run.motion.num_frames - 1,
                     int(std::lround((w.clip()->motion.num_frames - 1) *
                                     w.clip()->motion.frame_time / run.motion.frame_time))));
  // Playing: the compared clip follows each frame.
  w.setFrame(0);
  w.play();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentFrame() > 10; }, 5000));
  w.pause();
  EXPECT_EQ(compare->comparedFrame(), compare->syncedFrame(w.currentFrame()));
  // Another method: the comparison stays, on the new map's points.
  w.setMethod(embed::Method::Isomap);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return w.currentMap() && w.currentMap()->options.embed.method == embed::Method::Isomap;
      },
      testing::kTimeoutMs));
  EXPECT_EQ(compare->comparedClip(), 1);
  const Eigen::MatrixXd& iso = w.currentMap()->map.embedding.coordinates;
  EXPECT_TRUE(
      view->comparisonTrajectory().isApprox(iso.bottomRows(iso.rows() - starts[1]).leftCols(2)));
  // Stop comparing: the dock hides, the map's trajectory goes.
  QTest::mouseClick(compare->findChild<QPushButton*>(), Qt::LeftButton);
  EXPECT_EQ(compare->comparedClip(), -1);
  EXPECT_FALSE(compare->isVisible());
  EXPECT_EQ(view->comparisonTrajectory().rows(), 0);
  EXPECT_FALSE(view->comparisonPoint().has_value());
  const QImage picture = w.grab().toImage();
  EXPECT_FALSE(picture.isNull());
}

/// Pixels of `image` below the map's plot (its clip legend) in the comparison colour.
int tealLegendPixels(MapView& view) {
  QImage image(view.size(), QImage::Format_ARGB32);
  view.render(&image);
  const QColor teal = MapView::comparisonColor();
  int n = 0;
  for (int y = int(view.plotRect().bottom()) + 2; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QColor c = image.pixelColor(x, y);
      n += std::abs(c.red() - teal.red()) + std::abs(c.green() - teal.green()) +
               std::abs(c.blue() - teal.blue()) <
           12;
    }
  return n;
}

// The compared clip is drawn in the comparison colour, its legend swatch too (one colour rule,
// render::drawn_clip_color): not in its own palette colour under a teal trajectory.
TEST(StudioCompare, TheComparedClipsLegendSwatchIsInTheColourItIsDrawnIn) {
  if (!fs::exists(kWalk) || !fs::exists(kRun)) GTEST_SKIP() << "no Bandai takes in " << kBandai;
  MainWindow w;
  ASSERT_TRUE(testing::showOnPcaMap(w, {kWalk, kRun}));
  MapView* view = w.mapView();
  ASSERT_EQ(view->plotOptions().clip_names.size(), 2);  // a legend of the two clips
  EXPECT_NE(view->clipColor(1, 0.5), MapView::comparisonColor());
  EXPECT_EQ(tealLegendPixels(*view), 0);
  ComparePanel* compare = w.explore()->compare();
  ASSERT_TRUE(compare->compareWith(1));
  EXPECT_EQ(view->comparisonClip(), 1);
  for (const double t : {0.0, 0.5, 1.0}) {
    EXPECT_EQ(view->clipColor(1, t), MapView::comparisonColor()) << t;
    EXPECT_NE(view->clipColor(0, t), MapView::comparisonColor()) << t;
  }
  EXPECT_GT(tealLegendPixels(*view), 10);
  // A frame of the comparison keeps it; stopping gives the clip its own colour back.
  w.setFrame(5);
  EXPECT_EQ(view->clipColor(1, 0.5), MapView::comparisonColor());
  compare->stop();
  EXPECT_EQ(view->comparisonClip(), -1);
  EXPECT_NE(view->clipColor(1, 0.5), MapView::comparisonColor());
  EXPECT_EQ(tealLegendPixels(*view), 0);
}

/// Pixels of `image` close to the comparison colour laid over the 3-D view's background.
int comparisonPixels(const QImage& image) {
  const QColor teal = MapView::comparisonColor();
  int n = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QColor c = image.pixelColor(x, y);
      // Teal (shaded, translucent over the light grey): blue and green well above red.
      n += c.green() > c.red() + 40 && c.blue() > c.red() + 40 &&
           std::abs(c.green() - c.blue()) < 40 + std::abs(teal.green() - teal.blue());
    }
  return n;
}

TEST(StudioCompare, OverlaidTheComparedCharacterIsDrawnInTheMainView) {
  if (!fs::exists(kWalk) || !fs::exists(kRun)) GTEST_SKIP() << "no Bandai takes in " << kBandai;
  MainWindow w;
  ASSERT_TRUE(testing::showOnPcaMap(w, {kWalk, kRun}));
  ComparePanel* compare = w.explore()->compare();
  SkeletonView* main = w.skeletonView();
  ASSERT_TRUE(compare->compareWith(1));
  EXPECT_EQ(compare->placement(), ComparePanel::Placement::SideBySide);
  EXPECT_FALSE(main->hasOverlay());
  const Clip run = io::load_clip(kRun);
  w.setFrame(40);
  QTest::qWait(20);
  const QImage alone = main->renderImage();
  EXPECT_LT(comparisonPixels(alone), 20);  // no teal character yet

  // Overlaid, each at its own place: the run's pose of the synced frame, as its clip places it,
  // in the main view; the dock's own view hidden.
  compare->placementChoice()->setCurrentIndex(1);
  emit compare->placementChoice()->activated(1);
  ASSERT_EQ(compare->placement(), ComparePanel::Placement::Overlaid);
  EXPECT_FALSE(compare->view3d()->isVisible());
  ASSERT_TRUE(main->hasOverlay());
  EXPECT_EQ(main->overlayColor(), MapView::comparisonColor());
  const auto expectPose = [&](int frame, const Eigen::Vector3d& shift) {
    const WorldPose want = forward_kinematics(run.skeleton, run.motion, frame);
    const WorldPose& got = main->overlayPose();
    ASSERT_EQ(got.positions.size(), want.positions.size());
    for (std::size_t j = 0; j < want.positions.size(); ++j)
      ASSERT_TRUE(got.positions[j].isApprox(want.positions[j] + shift, 1e-9)) << "joint " << j;
  };
  expectPose(compare->syncedFrame(40), Eigen::Vector3d::Zero());
  EXPECT_TRUE(compare->overlayShift().isZero());
  EXPECT_TRUE(showsFrame(*main, w.clip()->motion, 40));  // the walk as before
  EXPECT_FALSE(main->overlayBones().empty());
  // In sync while the frame moves.
  w.setFrame(80);
  expectPose(compare->syncedFrame(80), Eigen::Vector3d::Zero());
  // Drawn where its clip places it: at a frame where the run is in the walk's view (the camera
  // follows the walk; the run runs away from it), its teal figure over the scene.
  const int runRoot = motion_root(run.skeleton, run.motion);
  int inView = -1;
  for (int f = 0; f < w.clip()->motion.num_frames && inView < 0; f += 5) {
    w.setFrame(f);
    const QPointF root = main->overlayJointPixels()[std::size_t(runRoot)];
    if (QRectF(main->rect()).adjusted(80, 80, -80, -80).contains(root)) inView = f;
  }
  ASSERT_GE(inView, 0) << "the run never in the walk's view";
  w.setFrame(inView);
  expectPose(compare->syncedFrame(inView), Eigen::Vector3d::Zero());
  QTest::qWait(20);
  const QImage overlaid = main->renderImage();
  EXPECT_GT(comparisonPixels(overlaid), 200);
  EXPECT_TRUE(overlaid.save(QDir::current().filePath("studio-compare-overlaid.png")));
  // The overlay's joints project where its pose is (drawn in the same camera).
  ASSERT_EQ(main->overlayJointPixels().size(), run.skeleton.joints.size());

  // Roots together: its root's floor point on the walk's, heights kept.
  compare->setPlacement(ComparePanel::Placement::Together);
  EXPECT_EQ(compare->placementChoice()->currentIndex(), 2);
  const int walkRoot = main->motionRoot();
  const Eigen::Vector3d& walkAt = main->worldPose().positions[std::size_t(walkRoot)];
  const Eigen::Vector3d& runAt = main->overlayPose().positions[std::size_t(runRoot)];
  EXPECT_NEAR(runAt.x(), walkAt.x(), 1e-9);
  EXPECT_NEAR(runAt.z(), walkAt.z(), 1e-9);
  const Eigen::Vector3d shift = compare->overlayShift();
  EXPECT_EQ(shift.y(), 0.0);
  expectPose(compare->syncedFrame(80), shift);
  // Playing, the run follows the walk's root frame by frame.
  w.setFrame(120);
  const Eigen::Vector3d& walkNow = main->worldPose().positions[std::size_t(walkRoot)];
  const Eigen::Vector3d& runNow = main->overlayPose().positions[std::size_t(runRoot)];
  EXPECT_NEAR(runNow.x(), walkNow.x(), 1e-9);
  EXPECT_NEAR(runNow.z(), walkNow.z(), 1e-9);
  QTest::qWait(20);
  const QImage together = main->renderImage();
  EXPECT_GT(comparisonPixels(together), 200);
  EXPECT_TRUE(together.save(QDir::current().filePath("studio-compare-together.png")));
  EXPECT_TRUE(w.grab().toImage().save(QDir::current().filePath("studio-compare-window.png")));

  // Side by side again: no overlay, the dock's view shows the run.
  compare->setPlacement(ComparePanel::Placement::SideBySide);
  EXPECT_FALSE(main->hasOverlay());
  EXPECT_TRUE(compare->view3d()->isVisible());
  EXPECT_TRUE(showsFrame(*compare->view3d(), run.motion, compare->syncedFrame(120)));
  w.setFrame(60);
  EXPECT_FALSE(main->hasOverlay());
  EXPECT_TRUE(showsFrame(*compare->view3d(), run.motion, compare->syncedFrame(60)));
  // Stop comparing overlaid: the overlay goes with it; the placement stays chosen.
  compare->setPlacement(ComparePanel::Placement::Overlaid);
  ASSERT_TRUE(main->hasOverlay());
  compare->stop();
  EXPECT_FALSE(main->hasOverlay());
  EXPECT_LT(comparisonPixels(main->renderImage()), 20);
  ASSERT_TRUE(compare->compareWith(1));
  EXPECT_EQ(compare->placement(), ComparePanel::Placement::Overlaid);
  EXPECT_TRUE(main->hasOverlay());
}

TEST(StudioCompare, ASavedMapsClipIsLoadedToCompare) {
  if (!fs::exists(kWalk) || !fs::exists(kRun)) GTEST_SKIP() << "no Bandai takes in " << kBandai;
  const fs::path dir =
      fs::temp_directory_path() / ("motionmap-studio-compare-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<Clip> clips = {io::load_clip(kWalk), io::load_clip(kRun)};
  pipeline::ClipMapOptions options;
  options.embed.method = embed::Method::Pca;
  const pipeline::ClipMap map = pipeline::map_clips(clips, options);
  const std::string file = (dir / "lib.mmap.h5").string();
  mapfile::write_map_file(file, mapfile::make_map_file(clips, map, options));
  {
    MainWindow w;
    w.setInteractive(false);
    w.resize(1280, 720);
    w.show();
    ASSERT_TRUE(w.openMapFile(QString::fromStdString(file))) << w.lastError().toStdString();
    ComparePanel* compare = w.explore()->compare();
    ASSERT_TRUE(compare->compareWith(1)) << w.lastError().toStdString();
    const mapfile::MapFile& f = w.savedMap()->file();
    EXPECT_EQ(w.mapView()->comparisonTrajectory().rows(), f.clips[1].samples);
    w.setFrame(20);
    const int expected = compare->syncedFrame(20);
    EXPECT_TRUE(showsFrame(*compare->view3d(), clips[1].motion, expected));
    ASSERT_TRUE(w.mapView()->comparisonPoint().has_value());
    EXPECT_TRUE(w.mapView()->comparisonPoint()->isApprox(
        pointOf(f.coordinates, f.clip_of, f.frame_of, 1, expected)));
    EXPECT_TRUE(compare->caption()->text().startsWith("clip 2: dataset-1_run_angry_001.bvh"));
    QTest::qWait(50);
    EXPECT_TRUE(w.grab().toImage().save(QDir::current().filePath("studio-compare.png")));
    // A map of other clips ends the comparison.
    w.openClip(testing::swing());
    EXPECT_EQ(compare->comparedClip(), -1);
    EXPECT_EQ(w.mapView()->comparisonTrajectory().rows(), 0);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace motionmap::studio
