// View → Key poses: the strip under the views holds the key poses pipeline::clip_key_rows picks
// for the clip playing on the map shown (a real golf swing, two Bandai takes, a saved map of
// them); a click on a thumbnail plays from its frame (the 3-D view and the map's pointer follow)
// and highlights it; the menu shows and hides the strip (remembered); another clip or count
// recomputes.
#include <unistd.h>

#include <QAction>
#include <QDir>
#include <QMenu>
#include <QMenuBar>
#include <QSettings>
#include <QSpinBox>
#include <QTest>
#include <filesystem>

#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/key_poses.h"
#include "playback/key_pose_strip.h"
#include "playback/key_poses.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

namespace fs = std::filesystem;
using testing::kTimeoutMs;

const std::string kData = MOTIONMAP_SHARED_DATA;
const std::string kSwing = kData + "/cmu/64_08.bvh";  // a golf swing, 120 fps
const std::string kWalk = kData + "/bandai/dataset-1_walk_angry_001.bvh";
const std::string kRun = kData + "/bandai/dataset-1_run_angry_001.bvh";

bool showsFrame(const SkeletonView& view, const Motion& motion, int frame) {
  const Motion& pose = view.currentPose();
  if (pose.num_frames != 1 || pose.num_joints != motion.num_joints) return false;
  for (int j = 0; j < motion.num_joints; ++j) {
    if (std::abs(pose.rotation(0, j).dot(motion.rotation(frame, j))) < 1.0 - 1e-9) return false;
  }
  return true;
}

/// The file frames of clip `clip`'s key poses on the computed map shown, as the library picks
/// them.
std::vector<int> pipelineKeys(const MainWindow& w, int clip, int count) {
  const pipeline::ClipMap& map = w.currentMap()->map;
  std::vector<int> frames;
  for (const int r : pipeline::clip_key_rows(map, clip, count))
    frames.push_back(map.features->frame_of[std::size_t(r)]);
  return frames;
}

/// The same on a saved map: select_key_poses over the clip's rows of the file's coordinates.
std::vector<int> savedKeys(const mapfile::MapFile& file, int clip, int count) {
  const std::vector<int> rows = pipeline::clip_rows(file.clip_of, clip);
  Eigen::MatrixXd points(Eigen::Index(rows.size()), file.coordinates.cols());
  for (std::size_t i = 0; i < rows.size(); ++i)
    points.row(Eigen::Index(i)) = file.coordinates.row(rows[i]);
  std::vector<int> frames;
  for (const int k : pipeline::select_key_poses(points, count))
    frames.push_back(file.frame_of[std::size_t(rows[std::size_t(k)])]);
  return frames;
}

KeyPoseStrip* stripOf(MainWindow& w) {
  return w.findChild<KeyPoseStrip*>();
}

/// The View menu's entry for the strip.
QAction* viewEntry(MainWindow& w) {
  for (QAction* menu : w.menuBar()->actions()) {
    if (!menu->menu() || menu->text().remove('&') != "View") continue;
    for (QAction* a : menu->menu()->actions()) {
      if (a->text().remove('&') == "Key poses") return a;
    }
  }
  return nullptr;
}

/// Waits for the strip's key poses of clip `clip` (count of them, or all the clip has).
bool waitForKeys(KeyPoseStrip& strip, int clip) {
  return QTest::qWaitFor(
      [&] {
        const KeyPoses& k = *strip.keyPoses();
        return !k.isComputing() && k.clip() == clip && !k.frames().empty();
      },
      kTimeoutMs);
}

std::unique_ptr<MainWindow> window() {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1280, 800);
  w->show();
  w->setMethod(embed::Method::Pca);
  return w;
}

bool waitForMap(MainWindow& w) {
  return QTest::qWaitFor([&] { return w.currentMap() != nullptr && !w.isComputing(); }, kTimeoutMs);
}

TEST(StudioKeyPoses, TheStripHoldsTheLibrarysKeyPosesOfAGolfSwingAndAClickPlaysFromOne) {
  if (!fs::exists(kSwing)) GTEST_SKIP() << "no " << kSwing;
  auto w = window();
  ASSERT_TRUE(w->openFile(QString::fromStdString(kSwing))) << w->lastError().toStdString();
  ASSERT_TRUE(waitForMap(*w)) << w->lastError().toStdString();
  w->pause();
  KeyPoseStrip* strip = stripOf(*w);
  ASSERT_NE(strip, nullptr);
  QAction* entry = viewEntry(*w);
  ASSERT_NE(entry, nullptr);
  EXPECT_TRUE(entry->isCheckable());
  // Hidden at first, and nothing computed while hidden.
  EXPECT_FALSE(strip->isVisible());
  EXPECT_FALSE(entry->isChecked());
  EXPECT_TRUE(strip->keyPoses()->frames().empty());

  entry->trigger();
  EXPECT_TRUE(strip->isVisible());
  EXPECT_TRUE(entry->isChecked());
  ASSERT_TRUE(waitForKeys(*strip, 0)) << strip->keyPoses()->message().toStdString();
  const std::vector<int> keys = pipelineKeys(*w, 0, KeyPoses::kDefaultCount);
  ASSERT_EQ(keys.size(), std::size_t(KeyPoses::kDefaultCount));
  EXPECT_EQ(strip->keyPoses()->frames(), keys);
  ASSERT_EQ(strip->keyPoses()->poses().size(), keys.size());
  EXPECT_EQ(strip->keyPoses()->poses()[1].caption,
            QString("frame %1\n%2 s")
                .arg(keys[1])
                .arg(keys[1] * w->clip()->motion.frame_time, 0, 'f', 2));

  // Thumbnails in time order, side by side, none overlapping; the strip under the views.
  KeyPoseThumbnails* thumbs = strip->thumbnails();
  for (int i = 1; i < int(keys.size()); ++i) {
    EXPECT_GE(thumbs->cellRect(i).left(), thumbs->cellRect(i - 1).right()) << i;
    EXPECT_GE(thumbs->cellRect(i).width(), KeyPoseThumbnails::kMinCell);
  }
  EXPECT_GT(strip->mapTo(w.get(), QPoint(0, 0)).y(),
            w->mapView()->mapTo(w.get(), QPoint(0, w->mapView()->height() - 1)).y());
  // A click on a thumbnail plays from its frame: the 3-D view and the map's pointer follow, and
  // it is highlighted.
  for (const int i : {0, int(keys.size()) - 1, 3}) {
    QTest::mouseClick(thumbs, Qt::LeftButton, {}, thumbs->cellRect(i).center());
    EXPECT_EQ(w->currentFrame(), keys[std::size_t(i)]) << i;
    EXPECT_TRUE(showsFrame(*w->skeletonView(), w->clip()->motion, keys[std::size_t(i)])) << i;
    const auto point = w->mapView()->pointer();
    ASSERT_TRUE(point.has_value());
    const int row = w->currentMap()->rowOfFrame[0][std::size_t(keys[std::size_t(i)])];
    EXPECT_TRUE(point->isApprox(w->currentMap()->blender->sample_point(row))) << i;
    EXPECT_EQ(thumbs->highlighted(), i);
  }
  // The window with the strip, the fourth key pose highlighted (a picture to look at).
  QTest::qWait(50);
  EXPECT_TRUE(w->grab().toImage().save(QDir::current().filePath("studio-keyposes.png")));
  // Off a key pose: nothing highlighted.
  w->setFrame(keys[3] + 1);
  EXPECT_EQ(thumbs->highlighted(), -1);
  w->setFrame(keys[2]);
  EXPECT_EQ(thumbs->highlighted(), 2);

  // Another count: the library's as many.
  strip->countBox()->setValue(5);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return !strip->keyPoses()->isComputing() && strip->keyPoses()->frames().size() == 5; },
      kTimeoutMs));
  EXPECT_EQ(strip->keyPoses()->frames(), pipelineKeys(*w, 0, 5));

  // Another map (method) of the clip: recomputed for it.
  w->setMethod(embed::Method::Isomap);
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        return w->currentMap() && !w->isComputing() &&
               w->currentMap()->options.embed.method == embed::Method::Isomap &&
               !strip->keyPoses()->isComputing() && !strip->keyPoses()->frames().empty();
      },
      kTimeoutMs));
  EXPECT_EQ(strip->keyPoses()->frames(), pipelineKeys(*w, 0, 5));

  // The menu hides it; shown or not and the count are the next window's.
  entry->trigger();
  EXPECT_FALSE(strip->isVisible());
  EXPECT_FALSE(entry->isChecked());
  entry->trigger();
  EXPECT_TRUE(strip->isVisible());
  {
    MainWindow next;
    next.setInteractive(false);
    next.show();
    ASSERT_NE(stripOf(next), nullptr);
    EXPECT_TRUE(stripOf(next)->isVisible());
    EXPECT_EQ(stripOf(next)->countBox()->value(), 5);
    EXPECT_EQ(stripOf(next)->keyPoses()->count(), 5);
  }
}

TEST(StudioKeyPoses, AnotherClipOfTheMapRecomputesTheStrip) {
  if (!fs::exists(kWalk) || !fs::exists(kRun)) GTEST_SKIP() << "no Bandai takes";
  auto w = window();
  ASSERT_TRUE(w->openFile(QString::fromStdString(kWalk))) << w->lastError().toStdString();
  ASSERT_TRUE(w->addFile(QString::fromStdString(kRun))) << w->lastError().toStdString();
  ASSERT_TRUE(waitForMap(*w)) << w->lastError().toStdString();
  ASSERT_EQ(w->clipCount(), 2);
  w->pause();
  KeyPoseStrip* strip = stripOf(*w);
  viewEntry(*w)->trigger();
  ASSERT_TRUE(waitForKeys(*strip, 0)) << strip->keyPoses()->message().toStdString();
  EXPECT_EQ(strip->keyPoses()->frames(), pipelineKeys(*w, 0, KeyPoses::kDefaultCount));

  w->setCurrentClip(1, 0);
  ASSERT_TRUE(waitForKeys(*strip, 1)) << strip->keyPoses()->message().toStdString();
  const std::vector<int> run = pipelineKeys(*w, 1, KeyPoses::kDefaultCount);
  EXPECT_EQ(strip->keyPoses()->frames(), run);
  EXPECT_NE(run, pipelineKeys(*w, 0, KeyPoses::kDefaultCount));
  KeyPoseThumbnails* thumbs = strip->thumbnails();
  QTest::mouseClick(thumbs, Qt::LeftButton, {}, thumbs->cellRect(4).center());
  EXPECT_EQ(w->currentClip(), 1);
  EXPECT_EQ(w->currentFrame(), run[4]);
  EXPECT_EQ(thumbs->highlighted(), 4);
}

TEST(StudioKeyPoses, ASavedMapHasItsClipsKeyPoses) {
  if (!fs::exists(kWalk) || !fs::exists(kRun)) GTEST_SKIP() << "no Bandai takes";
  const fs::path dir =
      fs::temp_directory_path() / ("motionmap-studio-keyposes-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<Clip> clips = {io::load_clip(kWalk), io::load_clip(kRun)};
  pipeline::ClipMapOptions options;
  options.embed.method = embed::Method::Pca;
  const pipeline::ClipMap map = pipeline::map_clips(clips, options);
  const std::string file = (dir / "lib.mmap.h5").string();
  mapfile::write_map_file(file, mapfile::make_map_file(clips, map, options));
  {
    auto w = window();
    ASSERT_TRUE(w->openMapFile(QString::fromStdString(file))) << w->lastError().toStdString();
    w->pause();
    KeyPoseStrip* strip = stripOf(*w);
    viewEntry(*w)->trigger();
    ASSERT_TRUE(waitForKeys(*strip, 0)) << strip->keyPoses()->message().toStdString();
    const mapfile::MapFile& f = w->savedMap()->file();
    EXPECT_EQ(strip->keyPoses()->frames(), savedKeys(f, 0, KeyPoses::kDefaultCount));
    // The same frames as the library picks on the map it was saved from.
    std::vector<int> computed;
    for (const int r : pipeline::clip_key_rows(map, 0, KeyPoses::kDefaultCount))
      computed.push_back(map.features->frame_of[std::size_t(r)]);
    EXPECT_EQ(strip->keyPoses()->frames(), computed);

    // Another clip of the saved map (loaded on a worker) recomputes.
    w->setCurrentClip(1, 0);
    ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isLoadingClip(); }, kTimeoutMs));
    ASSERT_TRUE(waitForKeys(*strip, 1)) << strip->keyPoses()->message().toStdString();
    const std::vector<int> run = savedKeys(f, 1, KeyPoses::kDefaultCount);
    EXPECT_EQ(strip->keyPoses()->frames(), run);
    KeyPoseThumbnails* thumbs = strip->thumbnails();
    QTest::mouseClick(thumbs, Qt::LeftButton, {}, thumbs->cellRect(2).center());
    EXPECT_EQ(w->currentClip(), 1);
    EXPECT_EQ(w->currentFrame(), run[2]);
    EXPECT_EQ(thumbs->highlighted(), 2);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace motionmap::studio
