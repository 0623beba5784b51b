// Compare two clips (View → Compare with clip…, the Compare dock): a second clip of the map plays
// in sync with the one playing (the same time from its start, at its own frame rate), its
// character in the dock's 3-D view and its trajectory on the map with a ring at its frame; on a
// map computed here of two Bandai takes and on a saved map of them.
#include <unistd.h>

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
  w.setInteractive(false);
  w.resize(1280, 720);
  w.show();
  w.setMethod(embed::Method::Pca);
  ASSERT_TRUE(w.openFile(QString::fromStdString(kWalk)));
  ASSERT_TRUE(w.addFile(QString::fromStdString(kRun)));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return w.currentMap() != nullptr && !w.isComputing() && w.clipCount() == 2; },
      testing::kTimeoutMs));
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
