// Studio on a saved map (File → Open map, `motionmap-studio lib.mmap.h5`): the map file opens
// without refitting and is drawn as a density image with the current clip's trajectory; hovering
// names the clip and frame under the mouse, a click loads the clicked clip on demand and jumps to
// the frame, a drag blends the nearest samples (mapfile::SavedMap::pose_at), and a clip changed
// since the map was made is refused with the library's message. Map files are made in the test's
// temporary folder from the real clips in ../shared/data.
#include <unistd.h>

#include <QAction>
#include <QDir>
#include <QImage>
#include <QLabel>
#include <QTest>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "common/parameters.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

namespace fs = std::filesystem;

const std::string kData = MOTIONMAP_SHARED_DATA;

// A folder of its own per test with copies of 64_08 and 64_09 (so a test may change one) and
// their mds map saved as lib.mmap.h5.
class SavedMapFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"64_08.bvh", "64_09.bvh"}) {
      if (!fs::exists(kData + "/cmu/" + name)) GTEST_SKIP() << "no " << name << " in " << kData;
    }
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = fs::temp_directory_path() /
            ("motionmap-studio-saved-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
    std::vector<Clip> clips;
    for (const char* name : {"64_08.bvh", "64_09.bvh"}) {
      fs::copy_file(kData + "/cmu/" + name, m_dir / name);
      clips.push_back(io::load_clip((m_dir / name).string()));
    }
    pipeline::ClipMapOptions options;
    options.embed.method = embed::Method::Mds;
    const pipeline::ClipMap map = pipeline::map_clips(clips, options);
    m_file = (m_dir / "lib.mmap.h5").string();
    mapfile::write_map_file(m_file, mapfile::make_map_file(clips, map, options));
    m_coords = map.embedding.coordinates;
    m_clips = std::move(clips);
    m_window = std::make_unique<MainWindow>();
    m_window->setInteractive(false);
    m_window->resize(1000, 600);
    m_window->show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(m_window.get()));
  }
  void TearDown() override {
    m_window.reset();
    if (!m_dir.empty()) fs::remove_all(m_dir);
  }

  /// The widget pixel of map row `row`.
  QPoint pixelOf(int row) const {
    const auto& xy = m_window->savedMap()->file().coordinates;
    return m_window->mapView()->toWidget(Eigen::Vector2d(xy(row, 0), xy(row, 1))).toPoint();
  }

  fs::path m_dir;
  std::string m_file;
  std::vector<Clip> m_clips;
  Eigen::MatrixXd m_coords;  ///< the saved map's coordinates
  std::unique_ptr<MainWindow> m_window;
};

bool sameRotations(const Motion& a, const Motion& b, int frameOfB = 0) {
  if (a.num_joints != b.num_joints || a.num_frames < 1 || b.num_frames <= frameOfB) return false;
  for (int j = 0; j < a.num_joints; ++j) {
    if (std::abs(a.rotation(0, j).dot(b.rotation(frameOfB, j))) < 1.0 - 1e-12) return false;
  }
  return true;
}

TEST_F(SavedMapFixture, OpensWithoutRefittingAsADensityImageWithTheFirstClipOnTop) {
  ASSERT_TRUE(m_window->openFile(QString::fromStdString(m_file)))
      << m_window->lastError().toStdString();
  const mapfile::SavedMap* saved = m_window->savedMap();
  ASSERT_NE(saved, nullptr);
  EXPECT_FALSE(m_window->isComputing());  // nothing is mapped again
  EXPECT_EQ(m_window->clipCount(), 2);
  EXPECT_EQ(m_window->currentClip(), 0);
  ASSERT_NE(m_window->clip(), nullptr);
  EXPECT_EQ(m_window->clip()->motion.num_frames, m_clips[0].motion.num_frames);
  EXPECT_TRUE(saved->is_loaded(0));
  EXPECT_FALSE(saved->is_loaded(1));  // loaded when needed
  EXPECT_TRUE(m_window->statusText().contains("map file")) << m_window->statusText().toStdString();
  EXPECT_TRUE(m_window->statusText().contains("method=mds"));
  // The density image holds every point: as many inked pixels as distinct pixels under samples.
  MapView* view = m_window->mapView();
  ASSERT_TRUE(view->hasDensity());
  const QImage& density = view->densityImage();
  ASSERT_FALSE(density.isNull());
  std::set<std::pair<int, int>> under;
  const qreal dpr = density.devicePixelRatio();
  for (int r = 0; r < saved->file().num_samples(); ++r) {
    const auto& xy = saved->file().coordinates;
    const QPointF p = view->toWidget(Eigen::Vector2d(xy(r, 0), xy(r, 1))) * dpr;
    under.insert({int(p.x()), int(p.y())});
  }
  int inked = 0;
  for (int y = 0; y < density.height(); ++y)
    for (int x = 0; x < density.width(); ++x) inked += qAlpha(density.pixel(x, y)) > 0;
  EXPECT_EQ(inked, int(under.size()));
  // The pointer is on the current frame's sample.
  ASSERT_TRUE(view->pointer().has_value());
  const int row0 = saved->file().clips[0].first_sample;
  m_window->setFrame(saved->file().frame_of[std::size_t(row0) + 5]);
  EXPECT_EQ(*view->pointer(), Eigen::Vector2d(saved->file().coordinates(row0 + 5, 0),
                                              saved->file().coordinates(row0 + 5, 1)));
  // The screenshot shows the density and the red → blue trajectory.
  const QImage shot = m_window->screenshot();
  EXPECT_FALSE(shot.isNull());
  // Meanwhile its blender (for sketches, keys and joint drags) is built on a worker, over the
  // map's own points: the map as takes blend on it.
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs));
  EXPECT_EQ(m_window->currentMap()->map.embedding.coordinates, saved->file().coordinates);
  EXPECT_EQ(m_window->currentMap()->blender->num_samples(), saved->file().num_samples());
}

TEST_F(SavedMapFixture, HoverNamesTheClipAndFrameUnderTheMouse) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  const mapfile::MapFile& file = m_window->savedMap()->file();
  MapView* view = m_window->mapView();
  const int row = file.clips[1].first_sample + file.clips[1].samples / 2;  // a frame of clip 2
  QTest::mouseMove(view, pixelOf(row));
  const QString text = view->hoverText();
  ASSERT_TRUE(text.startsWith("clip ")) << text.toStdString();
  // The sample named lies under the mouse (within 2 px: the pixel rounding of two samples).
  const int clip = text.section(' ', 1, 1).toInt() - 1;
  const int frame = text.section("frame ", 1).toInt();
  int named = -1;
  for (int r = file.clips[std::size_t(clip)].first_sample;
       r < file.clips[std::size_t(clip)].first_sample + file.clips[std::size_t(clip)].samples; ++r)
    if (file.frame_of[std::size_t(r)] == frame) named = r;
  ASSERT_GE(named, 0) << text.toStdString();
  EXPECT_LE((QPointF(pixelOf(named)) - QPointF(pixelOf(row))).manhattanLength(), 2.0);
  EXPECT_TRUE(text.contains(".bvh"));
  QTest::mouseMove(view, QPoint(2, 2));
  EXPECT_TRUE(view->hoverText().isEmpty());
}

TEST_F(SavedMapFixture, ClickLoadsTheClickedClipAndJumpsToItsFrame) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  const mapfile::SavedMap* saved = m_window->savedMap();
  const mapfile::MapFile& file = saved->file();
  const int row = file.clips[1].first_sample + 40;
  ASSERT_FALSE(saved->is_loaded(1));
  QTest::mouseClick(m_window->mapView(), Qt::LeftButton, Qt::NoModifier, pixelOf(row));
  // The click returns at once; the clip loads on the loader's thread, then the jump happens.
  EXPECT_TRUE(m_window->isLoadingClip());
  EXPECT_TRUE(m_window->statusText().startsWith("Loading clip 2 of 2"))
      << m_window->statusText().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !m_window->isLoadingClip(); }, testing::kTimeoutMs));
  ASSERT_EQ(m_window->currentClip(), 1) << m_window->lastError().toStdString();
  EXPECT_TRUE(saved->is_loaded(1));
  const int frame = m_window->currentFrame();
  // The frame jumped to is a sample of clip 2 drawn within 2 px of the click.
  int jumped = -1;
  for (int r = file.clips[1].first_sample; r < file.clips[1].first_sample + file.clips[1].samples;
       ++r)
    if (file.frame_of[std::size_t(r)] == frame) jumped = r;
  ASSERT_GE(jumped, 0);
  EXPECT_LE((QPointF(pixelOf(jumped)) - QPointF(pixelOf(row))).manhattanLength(), 2.0);
  EXPECT_EQ(m_window->clip()->motion.num_frames, m_clips[1].motion.num_frames);
  EXPECT_TRUE(sameRotations(m_window->skeletonView()->currentPose(), m_clips[1].motion, frame));
  EXPECT_TRUE(m_window->statusText().contains("clip 2 of 2"));
  // Far from every sample nothing happens.
  QTest::mouseClick(m_window->mapView(), Qt::LeftButton, Qt::NoModifier, QPoint(2, 2));
  EXPECT_EQ(m_window->currentClip(), 1);
  EXPECT_EQ(m_window->currentFrame(), frame);
}

TEST_F(SavedMapFixture, DragBlendsTheNearestSamples) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  m_window->pause();
  const mapfile::SavedMap* saved = m_window->savedMap();
  const mapfile::MapFile& file = saved->file();
  MapView* view = m_window->mapView();
  const QPoint a = pixelOf(file.clips[0].first_sample + 20);
  const QPoint b = pixelOf(file.clips[1].first_sample + 60);
  const QPoint mid = (a + b) / 2 + QPoint(3, 2);
  // The blends stand where the frame shown before the drag stood (its heading and floor position).
  const Motion& motion = m_window->clip()->motion;
  const int root = motion_root(m_window->clip()->skeleton, motion);
  const synth::RootPlacement placement =
      synth::root_placement(motion, m_window->currentFrame(), root);
  const auto placedAt = [&](const QPoint& pixel) {
    mapfile::SavedPose pose = saved->pose_at(view->toMap(QPointF(pixel)), 12);
    synth::place_root(pose.pose, root, placement);
    return pose;
  };
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, a);
  QTest::mouseMove(view, mid);
  // Clips not loaded yet are loaded on the worker; the drag's point is blended when they arrive.
  ASSERT_TRUE(QTest::qWaitFor([&] { return !m_window->isLoadingClip(); }, testing::kTimeoutMs));
  QCoreApplication::processEvents();
  const mapfile::SavedPose expected = placedAt(mid);
  EXPECT_TRUE(sameRotations(m_window->skeletonView()->currentPose(), expected.pose));
  EXPECT_TRUE(view->hoverText().startsWith("blend of 12 samples"))
      << view->hoverText().toStdString();
  EXPECT_EQ(view->hoverText().contains("outside"), expected.outside);
  QTest::mouseMove(view, b);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !m_window->isLoadingClip(); }, testing::kTimeoutMs));
  QCoreApplication::processEvents();
  const mapfile::SavedPose atB = placedAt(b);
  EXPECT_TRUE(sameRotations(m_window->skeletonView()->currentPose(), atB.pose));
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, b);
  EXPECT_TRUE(saved->is_loaded(1));  // its clip was loaded to blend it
}

TEST_F(SavedMapFixture, AClipChangedSinceTheMapWasMadeIsRefusedClearly) {
  { std::ofstream(m_dir / "64_09.bvh", std::ios::app) << "\n"; }
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));  // clip 1 is intact
  const mapfile::MapFile& file = m_window->savedMap()->file();
  const int frame = m_window->currentFrame();
  QTest::mouseClick(m_window->mapView(), Qt::LeftButton, Qt::NoModifier,
                    pixelOf(file.clips[1].first_sample + 40));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !m_window->isLoadingClip(); }, testing::kTimeoutMs));
  EXPECT_EQ(m_window->currentClip(), 0);  // the clip before stays
  EXPECT_EQ(m_window->currentFrame(), frame);
  const std::string error = m_window->lastError().toStdString();
  EXPECT_NE(error.find("64_09.bvh"), std::string::npos) << error;
  EXPECT_NE(error.find("has changed since the map was made"), std::string::npos) << error;
  EXPECT_NE(error.find(file.clips[1].sha256), std::string::npos) << error;
  // Asked again (a click, a drag over its samples): the same refusal at once, no new load.
  QTest::mouseClick(m_window->mapView(), Qt::LeftButton, Qt::NoModifier,
                    pixelOf(file.clips[1].first_sample + 40));
  EXPECT_FALSE(m_window->isLoadingClip());
  EXPECT_EQ(m_window->currentClip(), 0);
  const QPoint on = pixelOf(file.clips[1].first_sample + 80);
  QTest::mousePress(m_window->mapView(), Qt::LeftButton, Qt::NoModifier, on + QPoint(-6, 0));
  QTest::mouseMove(m_window->mapView(), on);
  QTest::mouseMove(m_window->mapView(), on + QPoint(1, 0));
  EXPECT_FALSE(m_window->isLoadingClip());
  EXPECT_FALSE(m_window->mapView()->hoverText().startsWith("blend"));
  EXPECT_NE(m_window->lastError().toStdString().find("has changed since the map was made"),
            std::string::npos);
  QTest::mouseRelease(m_window->mapView(), Qt::LeftButton, Qt::NoModifier, on + QPoint(1, 0));
  // The first clip missing: the map does not open, and says why.
  fs::remove(m_dir / "64_08.bvh");
  MainWindow other;
  other.setInteractive(false);
  EXPECT_FALSE(other.openMapFile(QString::fromStdString(m_file)));
  EXPECT_NE(other.lastError().toStdString().find("is missing"), std::string::npos);
  EXPECT_EQ(other.savedMap(), nullptr);
  // Not a map file at all.
  { std::ofstream(m_dir / "junk.h5") << "not hdf5"; }
  EXPECT_FALSE(other.openFile(QString::fromStdString((m_dir / "junk.h5").string())));
  EXPECT_NE(other.lastError().toStdString().find("junk.h5"), std::string::npos);
}

TEST_F(SavedMapFixture, ADamagedMapFileIsRefusedAndTheOpenClipMapAndTakesStay) {
  // A clip with its map and an unexported take.
  m_window->openClip(m_clips[0]);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs));
  const MapResult* map = m_window->currentMap();
  ASSERT_TRUE(m_window->synthesizeAlong(testing::pathAlong(*map, 10, 90, 1.0)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !m_window->isSynthesizing(); }, testing::kTimeoutMs));
  ASSERT_EQ(m_window->takes()->list().count(), 1);
  const int frames = m_window->clip()->motion.num_frames;
  // Damaged copies: cut in half, and bytes changed in the map's coordinates, which opening reads
  // (its checksum catches the change; a dataset only placing new clips reads is checked then).
  std::string bytes;
  {
    std::ifstream in(m_file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 1000u);
  const fs::path cut = m_dir / "cut.mmap.h5", changed = m_dir / "changed.mmap.h5";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::string damaged = bytes;
  char value[sizeof(double)];
  std::memcpy(value, &m_coords(5, 0), sizeof(double));
  const std::size_t at = damaged.find(std::string(value, sizeof(double)));
  ASSERT_NE(at, std::string::npos) << "the coordinates are not stored as doubles";
  for (std::size_t i = at; i < at + 16; ++i) damaged[i] ^= 0x5a;
  std::ofstream(changed, std::ios::binary) << damaged;
  for (const fs::path& bad : {cut, changed}) {
    EXPECT_FALSE(m_window->openMapFile(QString::fromStdString(bad.string()))) << bad;
    const std::string error = m_window->lastError().toStdString();
    EXPECT_NE(error.find(bad.filename().string()), std::string::npos) << error;
    // What was open stays: the clip, its computed map, the take (not lost, still unexported).
    EXPECT_EQ(m_window->savedMap(), nullptr);
    EXPECT_EQ(m_window->currentMap(), map);
    EXPECT_EQ(m_window->clip()->motion.num_frames, frames);
    EXPECT_EQ(m_window->takes()->list().count(), 1);
    EXPECT_TRUE(m_window->hasUnsavedMotion());
  }
}

TEST_F(SavedMapFixture, OpeningAClipLeavesTheSavedMap) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  m_window->openClip(testing::swing());
  EXPECT_EQ(m_window->savedMap(), nullptr);
  EXPECT_FALSE(m_window->mapView()->hasDensity());
  EXPECT_TRUE(
      QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs));
}

// The Motion menu checks the saved map's own method (MDS here), whatever the last computed map's
// was; choosing another method offers "Recompute from clips…" (non-interactive: the refusal is
// shown), and recomputing maps the saved map's clips here with the method chosen.
TEST_F(SavedMapFixture, TheMotionMenuShowsTheSavedMethodAndOffersToRecomputeFromClips) {
  m_window->setMethod(embed::Method::Pca);
  m_window->openClip(testing::swing());
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs));
  auto checked = [&] {
    for (QAction* a : m_window->findChildren<QAction*>())
      if (a->isCheckable() && a->isChecked() && a->actionGroup() && a->data().isValid() &&
          a->text() == methodLabel(embed::Method(a->data().toInt())))
        return embed::Method(a->data().toInt());
    return embed::Method::Isomap;
  };
  EXPECT_EQ(checked(), embed::Method::Pca);
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  EXPECT_EQ(checked(), embed::Method::Mds);
  m_window->setMethod(embed::Method::LaplacianEigenmap);
  EXPECT_EQ(checked(), embed::Method::Mds);  // refused: the saved map stays as it was made
  EXPECT_TRUE(m_window->lastError().contains("shown as it was made"))
      << m_window->lastError().toStdString();
  // Recompute from clips: both clips mapped here with PCA.
  ASSERT_TRUE(m_window->recomputeFromClips(embed::Method::Pca))
      << m_window->lastError().toStdString();
  EXPECT_EQ(m_window->savedMap(), nullptr);
  EXPECT_EQ(m_window->clipCount(), 2);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs));
  EXPECT_EQ(m_window->currentMap()->map.features->num_samples(), int(m_coords.rows()));
  EXPECT_EQ(checked(), embed::Method::Pca);
  EXPECT_EQ(m_window->currentMap()->options.embed.method, embed::Method::Pca);
}

TEST_F(SavedMapFixture, RecomputingRefusesAClipChangedSinceTheMapWasMade) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  {
    std::ofstream append(m_dir / "64_09.bvh", std::ios::app);
    append << "\n";
  }
  EXPECT_FALSE(m_window->recomputeFromClips(embed::Method::Pca));
  EXPECT_TRUE(m_window->lastError().contains("64_09")) << m_window->lastError().toStdString();
  EXPECT_NE(m_window->savedMap(), nullptr);  // the saved map stays
}

// The map coordinates under the mouse are in the status bar, with the digits the zoom needs.
TEST_F(SavedMapFixture, TheStatusBarShowsTheMapCoordinatesUnderTheMouse) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  MapView* view = m_window->mapView();
  QLabel* label = nullptr;
  for (QLabel* l : m_window->findChildren<QLabel*>())
    if (l->toolTip().contains("map coordinates under the mouse")) label = l;
  ASSERT_NE(label, nullptr);
  const QPoint at = pixelOf(40);
  QTest::mouseMove(view, at);
  const Eigen::Vector2d p = view->toMap(QPointF(at));
  const QStringList parts = label->text().split(' ', Qt::SkipEmptyParts);
  ASSERT_EQ(parts.size(), 5) << label->text().toStdString();  // map x X y Y
  const double pixel = view->viewExtent().width() / view->plotRect().width();
  EXPECT_NEAR(parts[2].toDouble(), p.x(), pixel);
  EXPECT_NEAR(parts[4].toDouble(), p.y(), pixel);
  const int digits = int(parts[2].size() - parts[2].indexOf('.') - 1);
  view->zoomAt(QPointF(at), 100.0);
  QTest::mouseMove(view, at + QPoint(1, 0));
  const QStringList zoomed = label->text().split(' ', Qt::SkipEmptyParts);
  ASSERT_EQ(zoomed.size(), 5);
  EXPECT_EQ(int(zoomed[2].size() - zoomed[2].indexOf('.') - 1), digits + 2);
}

/// Pixels of the view's shading layer (device pixels) that disagree with the disc rule at their
/// centres — the map point toMap(centre) within the reach of some sample, by brute force over
/// every sample — and how many are shaded and how many were looked at.
struct DiscRule {
  int shaded = 0, looked = 0, disagree = 0;
};
DiscRule compareWithDiscRule(const MapView& view, const Eigen::MatrixXd& xy, double reach) {
  const QImage layer = view.shadingLayer();
  DiscRule count;
  EXPECT_FALSE(layer.isNull());
  if (layer.isNull()) return count;
  EXPECT_EQ(layer.devicePixelRatio(), 1.0);  // offscreen: device pixels are widget pixels
  const QRect plot = view.plotRect().toAlignedRect().adjusted(1, 1, -1, -1);
  for (int y = plot.top(); y <= plot.bottom(); ++y) {
    for (int x = plot.left(); x <= plot.right(); ++x) {
      const Eigen::Vector2d p = view.toMap(QPointF(x + 0.5, y + 0.5));
      bool within = false;
      for (Eigen::Index i = 0; i < xy.rows() && !within; ++i)
        within = (Eigen::Vector2d(xy(i, 0), xy(i, 1)) - p).norm() <= reach;
      const bool shaded = qAlpha(layer.pixel(x, y)) != 0;
      count.shaded += shaded;
      count.disagree += shaded != within;
      ++count.looked;
    }
  }
  return count;
}

// View → Shade trustworthy blends on a saved map: the same rule as on a computed map — green
// where a map point lies within the blender's reach of a sample (SavedMap::reach_distance, the
// blender's reach_distance) — drawn exactly at every pixel's centre, whole and zoomed, and under
// the magnifier; only inside the plot.
TEST_F(SavedMapFixture, ShadesTrustworthyBlendsWithinTheBlendersReachOfASample) {
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)));
  const mapfile::SavedMap* saved = m_window->savedMap();
  ASSERT_NE(saved, nullptr);
  MapView* view = m_window->mapView();
  ASSERT_TRUE(view->hasDensity());
  EXPECT_TRUE(view->shadingAvailable());
  const double reach = saved->reach_distance();
  EXPECT_GT(reach, 0.0);
  EXPECT_EQ(view->shadingReach(), reach);
  // The blender built over the same samples for sketches has the same reach.
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs));
  ASSERT_NE(m_window->currentMap()->blender, nullptr);
  EXPECT_DOUBLE_EQ(m_window->currentMap()->blender->reach_distance(), reach);
  EXPECT_DOUBLE_EQ(m_window->currentMap()->blender->median_step(), saved->median_step());

  // Off until asked for (View → Shade trustworthy blends); the menu turns it on.
  EXPECT_FALSE(view->shadingVisible());
  QAction* shade = nullptr;
  for (QAction* a : m_window->findChildren<QAction*>())
    if (a->text().contains("Shade")) shade = a;
  ASSERT_NE(shade, nullptr);
  QImage off(view->size(), QImage::Format_ARGB32), on(view->size(), QImage::Format_ARGB32);
  view->render(&off);
  shade->setChecked(true);
  EXPECT_TRUE(view->shadingVisible());
  view->render(&on);
  const QRect plot = view->plotRect().toAlignedRect();
  int changedInside = 0, changedOutside = 0;
  for (int y = 0; y < on.height(); ++y)
    for (int x = 0; x < on.width(); ++x)
      (plot.contains(x, y) ? changedInside : changedOutside) += on.pixel(x, y) != off.pixel(x, y);
  EXPECT_GT(changedInside, 1000);
  EXPECT_EQ(changedOutside, 0);

  const Eigen::MatrixXd& xy = saved->file().coordinates;
  const QImage layer = view->shadingLayer();
  ASSERT_EQ(layer.size(), view->size());
  // The pixel under a sample is shaded.
  const QPointF sample = view->toWidget(Eigen::Vector2d(xy(40, 0), xy(40, 1)));
  ASSERT_TRUE(view->plotRect().contains(sample));
  EXPECT_NE(qAlpha(layer.pixel(sample.toPoint())), 0);
  // A pixel of the plot farther than the reach from every sample is not: the plot's pixel
  // farthest from the samples (the map's frame leaves room around them).
  QPoint far;
  double farthest = 0.0;
  for (int y = plot.top() + 1; y < plot.bottom(); y += 3) {
    for (int x = plot.left() + 1; x < plot.right(); x += 3) {
      const double d = saved->index().nearest(view->toMap(QPointF(x + 0.5, y + 0.5))).distance;
      if (d > farthest) {
        farthest = d;
        far = QPoint(x, y);
      }
    }
  }
  ASSERT_GT(farthest, reach);
  EXPECT_EQ(qAlpha(layer.pixel(far)), 0);
  // Every pixel as the disc rule says, the whole map and zoomed in 6× near the data's edge.
  const DiscRule whole = compareWithDiscRule(*view, xy, reach);
  std::printf("whole map: %d of %d plot pixels shaded (reach %.1f px), %d disagree\n", whole.shaded,
              whole.looked, view->shadingRadius(), whole.disagree);
  EXPECT_GT(whole.shaded, whole.looked / 20);
  EXPECT_LT(whole.shaded, whole.looked * 19 / 20);
  EXPECT_EQ(whole.disagree, 0);
  view->zoomAt(QPointF(sample) + QPointF(view->shadingRadius(), 0.0), 6.0);
  const DiscRule zoomed = compareWithDiscRule(*view, xy, reach);
  std::printf("zoomed 6x: %d of %d plot pixels shaded (reach %.1f px), %d disagree\n",
              zoomed.shaded, zoomed.looked, view->shadingRadius(), zoomed.disagree);
  EXPECT_GT(zoomed.shaded, 0);
  EXPECT_LT(zoomed.shaded, zoomed.looked);
  EXPECT_EQ(zoomed.disagree, 0);
  view->resetView();

  // Under the magnifier the shading follows the lens: a pixel inside the lens is shaded where the
  // map point it shows is within reach (the lens spreads the shaded disc around a sample).
  view->setLensEnabled(true);
  view->setLensCenter(sample);
  QImage lensOff(view->size(), QImage::Format_ARGB32), lensOn(view->size(), QImage::Format_ARGB32);
  shade->setChecked(false);
  view->render(&lensOff);
  shade->setChecked(true);
  view->render(&lensOn);
  int lensShaded = 0, lensDisagree = 0;
  ASSERT_TRUE(view->pointer().has_value());
  const QPointF pointer = view->toWidget(*view->pointer());
  const double R = view->lensRadius();
  for (int y = int(sample.y() - R) + 2; y < int(sample.y() + R) - 2; y += 2) {
    for (int x = int(sample.x() - R) + 2; x < int(sample.x() + R) - 2; x += 2) {
      const QPointF centre(x + 0.5, y + 0.5);
      if (QLineF(centre, sample).length() > R - 3 || !view->plotRect().contains(centre)) continue;
      if (lensOff.pixel(x, y) != qRgb(255, 255, 255)) continue;  // density, trajectory
      if (QLineF(centre, pointer).length() < 12) continue;       // the pointer (white)
      const double d = saved->index().nearest(view->toMap(centre)).distance;
      if (std::abs(d - reach) < 1e-3 * reach) continue;  // the rim
      const bool shaded = lensOn.pixel(x, y) != lensOff.pixel(x, y);
      lensShaded += shaded;
      lensDisagree += shaded != (d <= reach);
    }
  }
  std::printf("under the lens: %d background pixels shaded, %d disagree\n", lensShaded,
              lensDisagree);
  EXPECT_GT(lensShaded, 20);
  EXPECT_EQ(lensDisagree, 0);
  view->setLensEnabled(false);
  if (!qEnvironmentVariableIsEmpty("MOTIONMAP_TEST_PNG_DIR"))
    m_window->screenshot().save(
        QDir(qEnvironmentVariable("MOTIONMAP_TEST_PNG_DIR")).filePath("studio-saved-shading.png"));
  shade->setChecked(false);
}

}  // namespace
}  // namespace motionmap::studio
