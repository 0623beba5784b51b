// The map panel's correctness (issue #10, "Found when tried" 2, 3, 4, 7 and the bind-pose note of
// 8): a drag keeps the body's heading and floor position; the slider, pointer and pose agree after
// a drag and a recompute; Cancel at every stage of a map stops it at once and keeps the map and
// parameters before; a bad parameter keeps the map before; the validity shading stays inside the
// plot with one meaning at any frame rate; the plot's notes can be read whole.
#include <QDir>
#include <QElapsedTimer>
#include <QHelpEvent>
#include <QSignalSpy>
#include <QTest>
#include <QToolTip>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/render/map_plot.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio::testing {
namespace {

/// Saves `image` as `name` in $MOTIONMAP_TEST_PNG_DIR when that is set (pictures to look at by
/// hand; a test run leaves no files behind otherwise).
void savePicture(const QImage& image, const QString& name) {
  if (qEnvironmentVariableIsEmpty("MOTIONMAP_TEST_PNG_DIR")) return;
  image.save(QDir(qEnvironmentVariable("MOTIONMAP_TEST_PNG_DIR")).filePath(name));
}

const std::string kData = MOTIONMAP_SHARED_DATA;
const char* const kSwing = "/cmu/64_08.bvh";                                              // 120 fps
const char* const kWalk = "/other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh";  // 30

/// A clip of the shared data, or nothing (the test then skips, saying so).
std::optional<Clip> sharedClip(const std::string& relative) {
  const std::string path = kData + relative;
  if (!std::filesystem::exists(path)) return std::nullopt;
  return io::load_clip(path);
}

/// A shown, non-interactive window with `clip`'s map of `method` computed.
std::unique_ptr<MainWindow> windowWith(Clip clip, embed::Method method) {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1000, 600);
  w->show();
  w->setMethod(method);
  w->openClip(std::move(clip));
  EXPECT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  EXPECT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
  return w;
}

/// Waits for the computation under way to end; true when it made a map.
bool waitForMap(MainWindow& w) {
  QSignalSpy finished(&w, &MainWindow::computationFinished);
  if (!w.isComputing()) return w.currentMap() != nullptr;
  if (!QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs)) return false;
  return finished.front().front().toBool();
}

double angleBetween(double a, double b) {
  return std::abs(std::remainder(a - b, 2.0 * M_PI));
}

/// The placement of the pose the 3-D view shows.
synth::RootPlacement shownPlacement(const MainWindow& w) {
  const synth::MapBlender& blender = *w.currentMap()->blender;
  return synth::root_placement(w.skeletonView()->currentPose(), 0, blender.motion_root(),
                               blender.options().up);
}

/// The pose shown is frame `frame` of the clip, and the pointer is on that frame's map point.
void expectShowsFrame(const MainWindow& w, int frame) {
  const MapResult& map = *w.currentMap();
  const Motion& shown = w.skeletonView()->currentPose();
  const Motion& motion = w.clip()->motion;
  ASSERT_EQ(shown.num_frames, 1);
  for (int j = 0; j < motion.num_joints; ++j) {
    EXPECT_EQ(shown.rotation(0, j).coeffs(), motion.rotation(frame, j).coeffs()) << "joint " << j;
    EXPECT_EQ(shown.translation(0, j), motion.translation(frame, j)) << "joint " << j;
  }
  ASSERT_TRUE(w.mapView()->pointer().has_value());
  const Eigen::Vector2d point = map.blender->sample_point(map.rowOfFrame[0][std::size_t(frame)]);
  EXPECT_EQ(*w.mapView()->pointer(), point);
  EXPECT_EQ(w.currentFrame(), frame);
}

/// Drags from the current frame's point out across the plot's far corners (well off the
/// trajectory) and back: at every move the pose keeps the heading and floor position of the frame
/// shown before the drag. Then release, a frame shown, and a recompute.
void dragKeepsPlacement(Clip clip) {
  const std::string name = clip.path;
  auto w = windowWith(std::move(clip), embed::Method::Isomap);
  ASSERT_NE(w->currentMap(), nullptr);
  const MapResult* map = w->currentMap();
  const Motion& motion = w->clip()->motion;
  const int frame = motion.num_frames / 3;
  w->setFrame(frame);
  expectShowsFrame(*w, frame);
  const synth::RootPlacement before =
      synth::root_placement(motion, frame, map->blender->motion_root(), map->blender->options().up);
  std::printf("%s: frame %d heading %.4f rad, floor (%.3f, %.3f)\n", name.c_str(), frame,
              before.heading, before.floor.x(), before.floor.z());

  MapView* view = w->mapView();
  const QRectF plot = view->plotRect();
  const QPointF start = view->toWidget(*view->pointer());
  // Out to two opposite corners of the plot and back to the start.
  const std::vector<QPointF> legs = {start, plot.topLeft() + QPointF(6, 6),
                                     plot.bottomRight() - QPointF(6, 6), start};
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, start.toPoint());
  int moves = 0, outside = 0;
  double worstHeading = 0.0, worstFloor = 0.0, worstYawStep = 0.0;
  double lastHeading = before.heading;
  Eigen::Vector2d lastDragPoint = Eigen::Vector2d::Zero();
  QPoint last;
  for (std::size_t leg = 0; leg + 1 < legs.size(); ++leg) {
    for (int i = 1; i <= 40; ++i) {
      last = (legs[leg] + (legs[leg + 1] - legs[leg]) * (i / 40.0)).toPoint();
      QTest::mouseMove(view, last);
      if (!view->hoverText().startsWith("blend")) continue;  // the 3-pixel press slop
      ++moves;
      if (view->hoverText().contains("edge")) ++outside;
      const synth::RootPlacement now = shownPlacement(*w);
      worstHeading = std::max(worstHeading, angleBetween(now.heading, before.heading));
      worstFloor = std::max({worstFloor, std::abs(now.floor.x() - before.floor.x()),
                             std::abs(now.floor.z() - before.floor.z())});
      worstYawStep = std::max(worstYawStep, angleBetween(now.heading, lastHeading));
      lastHeading = now.heading;
      lastDragPoint = map->blender->locate(view->toMap(QPointF(last))).validity.point;
      EXPECT_EQ(*view->pointer(), lastDragPoint);
    }
  }
  std::printf(
      "  %d drag moves (%d moved to the data's edge): heading off by at most %.2e rad, "
      "floor by %.2e, largest heading step %.2e rad\n",
      moves, outside, worstHeading, worstFloor, worstYawStep);
  EXPECT_GT(moves, 100);
  EXPECT_GT(outside, 10) << "the drag never left the trajectory";
  EXPECT_LT(worstHeading, 1e-6);
  EXPECT_LT(worstFloor, 1e-6);
  EXPECT_LT(worstYawStep, 1e-6);

  // Released: the dragged pose stays, the pointer where it was blended; the slider's frame is
  // unchanged (the pose is a blend, not a frame, until a frame is shown again).
  const Motion dragged = w->skeletonView()->currentPose();
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, last);
  EXPECT_EQ(w->skeletonView()->currentPose().rotations, dragged.rotations);
  EXPECT_EQ(*view->pointer(), lastDragPoint);
  EXPECT_EQ(w->currentFrame(), frame);
  // A second drag starts where the first left the body: no jump either.
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, last);
  QTest::mouseMove(view, last + QPoint(20, 0));
  QTest::mouseMove(view, last + QPoint(40, 10));
  EXPECT_LT(angleBetween(shownPlacement(*w).heading, before.heading), 1e-6);
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, last + QPoint(40, 10));
  // Showing a frame puts pose and pointer back on it.
  w->setFrame(frame);
  expectShowsFrame(*w, frame);

  // After a recompute (another method) the pointer is on the frame's point of the new map and the
  // pose is the frame's, even when a dragged pose was shown.
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, start.toPoint());
  QTest::mouseMove(view, (start + QPointF(30, 30)).toPoint());
  QTest::mouseMove(view, (start + QPointF(60, 40)).toPoint());
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, (start + QPointF(60, 40)).toPoint());
  EXPECT_NE(w->skeletonView()->currentPose().rotations, Motion().rotations);
  w->setMethod(embed::Method::Pca);
  ASSERT_TRUE(waitForMap(*w)) << w->lastError().toStdString();
  EXPECT_EQ(w->currentMap()->map.embedding.method, embed::Method::Pca);
  expectShowsFrame(*w, frame);
}

TEST(StudioMapfix, DragKeepsTheHeadingAndFloorPositionOfTheSwing) {
  std::optional<Clip> clip = sharedClip(kSwing);
  if (!clip) GTEST_SKIP() << "no " << kData << kSwing;
  dragKeepsPlacement(std::move(*clip));
}

TEST(StudioMapfix, DragKeepsTheHeadingAndFloorPositionOfTheBandaiWalk) {
  std::optional<Clip> clip = sharedClip(kWalk);
  if (!clip) GTEST_SKIP() << "no " << kData << kWalk;
  const int root = motion_root(clip->skeleton, clip->motion);
  EXPECT_GT(root, 0) << "the static joint_Root above the hips";
  dragKeepsPlacement(std::move(*clip));
}

TEST(StudioMapfix, DragOnASavedMapKeepsTheHeadingAndFloorPosition) {
  std::optional<Clip> clip = sharedClip(kWalk);
  if (!clip) GTEST_SKIP() << "no " << kData << kWalk;
  // The walk's map, saved as `motionmap map --save` writes it, opened without refitting.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("motionmap-mapfix-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "walk.mmap.h5").string();
  pipeline::ClipMapOptions options;
  options.embed.method = embed::Method::Pca;
  std::vector<Clip> clips{*clip};
  mapfile::write_map_file(
      file, mapfile::make_map_file(clips, pipeline::map_clips(clips, options), options));
  MainWindow w;
  w.setInteractive(false);
  w.resize(1000, 600);
  w.show();
  ASSERT_TRUE(w.openMapFile(QString::fromStdString(file))) << w.lastError().toStdString();
  const Motion& motion = w.clip()->motion;
  const int frame = motion.num_frames / 2;
  w.setFrame(frame);
  const int root = motion_root(w.clip()->skeleton, motion);
  const synth::RootPlacement before = synth::root_placement(motion, frame, root);
  MapView* view = w.mapView();
  ASSERT_TRUE(view->pointer().has_value());
  const QPointF start = view->toWidget(*view->pointer());
  const QPointF corner = view->plotRect().topLeft() + QPointF(6, 6);
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, start.toPoint());
  int moves = 0;
  double worst = 0.0;
  for (int i = 1; i <= 40; ++i) {
    const QPoint at = (start + (corner - start) * (i / 40.0)).toPoint();
    QTest::mouseMove(view, at);
    if (!view->hoverText().startsWith("blend")) continue;
    ++moves;
    const synth::RootPlacement now =
        synth::root_placement(w.skeletonView()->currentPose(), 0, root);
    worst = std::max({worst, angleBetween(now.heading, before.heading),
                      std::abs(now.floor.x() - before.floor.x()),
                      std::abs(now.floor.z() - before.floor.z())});
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, corner.toPoint());
  std::printf("saved map: %d drag moves, heading and floor off by at most %.2e\n", moves, worst);
  EXPECT_GT(moves, 30);
  EXPECT_LT(worst, 1e-6);
  std::filesystem::remove_all(dir);
}

TEST(StudioMapfix, ABadParameterKeepsTheMapBefore) {
  auto w = windowWithMap(embed::Method::Isomap);
  const MapResult* before = w->currentMap();
  ASSERT_NE(before, nullptr);
  const MapParameters old = w->parameters();
  const Eigen::MatrixXd coords = w->mapView()->coordinates();
  ASSERT_EQ(coords.rows(), before->map.embedding.coordinates.rows());
  w->setFrame(30);
  MapParameters bad = old;
  bad.exclude = "Left(Arm";  // not a regular expression
  QSignalSpy finished(w.get(), &MainWindow::computationFinished);
  w->setParameters(bad);
  // While it is computed the map before stays on screen, greyed, saying so.
  EXPECT_EQ(w->mapView()->coordinates(), coords);
  EXPECT_TRUE(w->mapView()->busyText().startsWith("Computing"))
      << w->mapView()->busyText().toStdString();
  savePicture(w->mapView()->grab().toImage(), "studio-mapfix-busy.png");
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs));
  EXPECT_FALSE(finished.front().front().toBool());
  std::printf("error shown: %s\n", qPrintable(w->lastError()));
  EXPECT_TRUE(w->lastError().contains("Left(Arm")) << w->lastError().toStdString();
  EXPECT_TRUE(w->statusText().startsWith("Error: ")) << w->statusText().toStdString();
  // The map before is current and shown, with its parameters and method.
  EXPECT_EQ(w->currentMap(), before);
  EXPECT_EQ(w->parameters(), old);
  EXPECT_EQ(w->method(), embed::Method::Isomap);
  EXPECT_TRUE(w->mapView()->hasMap());
  EXPECT_EQ(w->mapView()->coordinates(), coords);
  EXPECT_TRUE(w->mapView()->busyText().isEmpty());
  expectShowsFrame(*w, 30);
  // A valid one replaces it.
  MapParameters good = old;
  good.k = 12;
  w->setParameters(good);
  ASSERT_TRUE(waitForMap(*w)) << w->lastError().toStdString();
  EXPECT_NE(w->currentMap(), before);
  EXPECT_EQ(w->parameters(), good);
}

/// One stage of a map to cancel in, and the request that reaches it.
struct StageCase {
  const char* stage;
  const char* what;                               ///< the map asked for
  std::function<void(MainWindow&, int)> request;  ///< the int makes each request a new map
};

TEST(StudioMapfix, CancelAtEveryStageKeepsTheMapAndParametersBefore) {
  // 20 s at 120 fps: 2400 frames, so every stage lasts long enough to be seen and cancelled in.
  auto w = windowWith(swing(20.0), embed::Method::Pca);
  ASSERT_NE(w->currentMap(), nullptr);
  const auto withMethod = [](embed::Method method) {
    return [method](MainWindow& window, int i) {
      MapParameters p = window.parameters();
      p.k = 30 + i;  // never a map made before
      window.setParameters(p);
      window.setMethod(method);
    };
  };
  // A new feature set (features, then the pose distances a method of distances needs).
  const auto newFeatures = [](MainWindow& window, int i) {
    MapParameters p = window.parameters();
    p.exclude = "NoSuchJoint" + std::to_string(i);
    window.setParameters(p);
    window.setMethod(embed::Method::Mds);
  };
  const auto kriging = [](MainWindow& window, int) {
    SynthParameters s = window.synthParameters();
    s.blend.mode = synth::BlendMode::Kriging;
    window.setSynthParameters(s);
  };
  const std::vector<StageCase> cases = {
      {"features", "new features", newFeatures},
      {"pose distances", "new features", newFeatures},
      {"neighbours", "isomap", withMethod(embed::Method::Isomap)},
      {"shortest paths", "isomap", withMethod(embed::Method::Isomap)},
      {"eigen", "mds", withMethod(embed::Method::Mds)},
      {"stress", "mds", withMethod(embed::Method::Mds)},
      {"weights", "lle", withMethod(embed::Method::Lle)},
      {"weights", "le", withMethod(embed::Method::LaplacianEigenmap)},
      {"metrics", "svd", withMethod(embed::Method::Svd)},
      {"kriging set-up", "pca, local blend", withMethod(embed::Method::Pca)},
      {"kriging set-up", "pca, kriging blend", kriging},
  };
  double worst = 0.0;
  int i = 0;
  for (const StageCase& c : cases) {
    ++i;
    const MapResult* before = w->currentMap();
    ASSERT_NE(before, nullptr);
    const embed::Method method = w->method();
    const MapParameters parameters = w->parameters();
    const SynthParameters synthParameters = w->synthParameters();
    const Eigen::MatrixXd coords = w->mapView()->coordinates();
    QElapsedTimer clock;
    double ms = -1.0;
    bool seen = false;
    QStringList stages;
    // Cancel (as the Cancel button does) as soon as the stage is reported, and time it until
    // cancelled() (MapController::cancel returns once the worker has stopped).
    const auto onProgress = QObject::connect(&w->maps(), &MapController::progress, w.get(),
                                             [&](double, const QString& stage) {
                                               if (stages.isEmpty() || stages.back() != stage)
                                                 stages << stage;
                                               if (seen || stage != QLatin1String(c.stage)) return;
                                               seen = true;
                                               clock.start();
                                               w->cancelComputation();
                                             });
    const auto onCancelled = QObject::connect(&w->maps(), &MapController::cancelled, w.get(),
                                              [&] { ms = double(clock.nsecsElapsed()) * 1e-6; });
    c.request(*w, i);
    ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isComputing(); }, kTimeoutMs));
    QObject::disconnect(onProgress);
    QObject::disconnect(onCancelled);
    ASSERT_TRUE(seen) << c.stage
                      << ": never reported; stages seen: " << stages.join(", ").toStdString();
    std::printf("cancel during %-15s (%s): cancelled after %.1f ms\n", c.stage, c.what, ms);
    EXPECT_GE(ms, 0.0) << c.stage << ": not cancelled";
    EXPECT_LT(ms, 1000.0) << c.stage;  // the issue asks for 200 ms; generous on a loaded CI
    worst = std::max(worst, ms);
    // The map before, its method and parameters, shown.
    EXPECT_EQ(w->currentMap(), before) << c.stage;
    EXPECT_EQ(w->method(), method) << c.stage;
    EXPECT_EQ(w->parameters(), parameters) << c.stage;
    EXPECT_EQ(MapController::cacheKey(method, parameters, w->synthParameters().blend),
              MapController::cacheKey(method, parameters, synthParameters.blend))
        << c.stage;
    EXPECT_EQ(w->mapView()->coordinates(), coords) << c.stage;
    EXPECT_TRUE(w->statusText().contains("cancelled")) << w->statusText().toStdString();
  }
  std::printf("slowest cancel: %.1f ms\n", worst);
}

/// The share of the plot that the shading covers, and the pixels it changes outside the plot.
struct ShadingCount {
  double fraction = 0.0;
  int outside = 0;
};

ShadingCount shading(MainWindow& w) {
  MapView* view = w.mapView();
  QImage off(view->size(), QImage::Format_ARGB32), on(view->size(), QImage::Format_ARGB32);
  view->setShadingVisible(false);
  view->render(&off);
  view->setShadingVisible(true);
  view->render(&on);
  view->setShadingVisible(false);
  const QRect plot = view->plotRect().toAlignedRect();
  int inPlot = 0, shaded = 0;
  ShadingCount count;
  for (int y = 0; y < off.height(); ++y) {
    for (int x = 0; x < off.width(); ++x) {
      const bool changed = on.pixel(x, y) != off.pixel(x, y);
      if (plot.contains(x, y)) {
        ++inPlot;
        shaded += changed;
      } else {
        count.outside += changed;
      }
    }
  }
  count.fraction = double(shaded) / inPlot;
  return count;
}

void shadingStaysInThePlot(Clip clip) {
  const std::string name = clip.path;
  auto w = windowWith(std::move(clip), embed::Method::Isomap);
  ASSERT_NE(w->currentMap(), nullptr);
  w->setFrame(0);
  const ShadingCount count = shading(*w);
  std::printf("%s: the shading covers %.1f %% of the plot, %d pixels outside it\n", name.c_str(),
              100.0 * count.fraction, count.outside);
  EXPECT_GT(count.fraction, 0.02);
  EXPECT_LT(count.fraction, 0.90);
  EXPECT_EQ(count.outside, 0);
  QImage image(w->mapView()->size(), QImage::Format_ARGB32);
  w->mapView()->setShadingVisible(true);
  w->mapView()->render(&image);
  w->mapView()->setShadingVisible(false);
  savePicture(image, QString::fromStdString("studio-mapfix-shading-" +
                                            std::filesystem::path(name).stem().string() + ".png"));
}

TEST(StudioMapfix, ShadingStaysInThePlotOnASwingAt120Fps) {
  std::optional<Clip> clip = sharedClip(kSwing);
  if (!clip) GTEST_SKIP() << "no " << kData << kSwing;
  shadingStaysInThePlot(std::move(*clip));
}

TEST(StudioMapfix, ShadingStaysInThePlotOnAWalkAt30Fps) {
  std::optional<Clip> clip = sharedClip(kWalk);
  if (!clip) GTEST_SKIP() << "no " << kData << kWalk;
  shadingStaysInThePlot(std::move(*clip));
}

TEST(StudioMapfix, ShadingMarksPointsNearAFrameAtAnyFrameRate) {
  // The same swing at 30 and 120 fps: the shading covers about the same share of the plot (the
  // reach is 5 % of the map's size at both: 3 steps are less; at 15 fps they are more), a
  // pixel is shaded exactly where its map point lies within the blender's reach of a sample (away
  // from the antialiased rim), and a blend there is not moved: what looks valid is valid (one
  // rule, synth::reach_radius).
  double fractions[2] = {0.0, 0.0};
  int k = 0;
  for (const double fps : {30.0, 120.0}) {
    sample::SampleOptions options;
    options.fps = fps;
    // PCA: a linear map, so both rates give the same curve (Isomap's k neighbours would span
    // 8× more time at 15 fps and bend it differently).
    auto w = windowWith(sample::make_sample_clip(sample::SampleKind::Swing, options),
                        embed::Method::Pca);
    const MapResult* map = w->currentMap();
    ASSERT_NE(map, nullptr);
    MapView* view = w->mapView();
    QImage off(view->size(), QImage::Format_ARGB32), on(view->size(), QImage::Format_ARGB32);
    view->render(&off);
    view->setShadingVisible(true);
    view->render(&on);
    view->setShadingVisible(false);
    const double radius = view->shadingRadius();  // pixels
    ASSERT_GT(radius, 1.0);
    const QRect plot = view->plotRect().toRect();
    const QPointF pointer = view->toWidget(*view->pointer());
    int inside = 0, outside = 0, disagree = 0, shaded = 0, all = 0, clampedInShade = 0;
    for (int y = plot.top() + 2; y < plot.bottom() - 2; y += 2) {
      for (int x = plot.left() + 2; x < plot.right() - 2; x += 2) {
        ++all;
        shaded += on.pixel(x, y) != off.pixel(x, y);
        if (off.pixel(x, y) != qRgb(255, 255, 255)) continue;        // the trajectory, frame
        if (QLineF(QPointF(x, y), pointer).length() < 12) continue;  // the pointer
        if (y > plot.bottom() - 40) continue;                        // the key
        // The nearest sample's distance in pixels.
        const QPointF pixel(x + 0.5, y + 0.5);
        double nearest = INFINITY;
        for (int i = 0; i < map->blender->num_samples(); ++i)
          nearest = std::min(nearest,
                             QLineF(pixel, view->toWidget(map->blender->sample_point(i))).length());
        if (std::abs(nearest - radius) < 1.5) continue;  // the disc's rim
        const bool isShaded = on.pixel(x, y) != off.pixel(x, y);
        (nearest < radius ? inside : outside) += 1;
        if (isShaded != (nearest < radius)) ++disagree;
        if (isShaded && map->blender->locate(view->toMap(pixel)).validity.clamped) ++clampedInShade;
      }
    }
    fractions[k++] = double(shaded) / all;
    std::printf(
        "%.0f fps: radius %.1f px, %d pixels near a frame, %d not, %d disagree; %.1f %% "
        "shaded\n",
        fps, radius, inside, outside, disagree, 100.0 * shaded / all);
    EXPECT_GT(inside, 500);
    EXPECT_GT(outside, 500);
    EXPECT_EQ(disagree, 0);
    EXPECT_EQ(clampedInShade, 0);
  }
  EXPECT_NEAR(fractions[0], fractions[1], 0.25 * fractions[1]);
}

TEST(StudioMapfix, TheShadingKeyExplainsIt) {
  auto w = windowWithMap(embed::Method::Isomap);
  MapView* view = w->mapView();
  const QRect plot = view->plotRect().toRect();
  // The key sits in the plot's lower-left corner: that corner differs with the shading on.
  QImage off(view->size(), QImage::Format_ARGB32), on(view->size(), QImage::Format_ARGB32);
  view->render(&off);
  view->setShadingVisible(true);
  view->render(&on);
  view->setShadingVisible(false);
  const QRect corner(plot.left() + 2, plot.bottom() - 30, 120, 28);
  int changed = 0, dark = 0;
  for (int y = corner.top(); y < corner.bottom(); ++y) {
    for (int x = corner.left(); x < corner.right(); ++x) {
      changed += on.pixel(x, y) != off.pixel(x, y);
      dark += qGray(on.pixel(x, y)) < 100;  // the key's text
    }
  }
  EXPECT_GT(changed, 400);
  EXPECT_GT(dark, 30);
}

TEST(StudioMapfix, TheBindPoseNoteCanBeReadWhole) {
  std::optional<Clip> clip = sharedClip(kSwing);
  if (!clip) GTEST_SKIP() << "no " << kData << kSwing;
  auto w = windowWith(std::move(*clip), embed::Method::Pca);
  ASSERT_NE(w->currentMap(), nullptr);
  const render::MapPlotOptions& options = w->mapView()->plotOptions();
  QString note;
  for (const QString& n : options.notes)
    if (n.contains("bind pose")) note = n;
  ASSERT_FALSE(note.isEmpty()) << "64_08 starts with a T-pose: its note is expected";
  // A narrow map panel: the note is wider than the panel, so the plot elides it.
  w->resize(700, 500);
  QTest::qWait(20);
  MapView* view = w->mapView();
  const QFontMetricsF fm(view->font());
  std::printf("map panel %d px wide; the note: %s\n", view->width(), qPrintable(note));
  const QRectF plot = view->plotRect();
  const QPoint below(view->width() / 2,
                     int(std::min<double>(view->height() - 3, plot.bottom() + 30)));
  EXPECT_TRUE(view->noteToolTip(QPointF(below)).contains(note));
  EXPECT_TRUE(view->noteToolTip(plot.center()).isEmpty());  // the plot itself: no tooltip
  // A tooltip event there shows it whole.
  QHelpEvent help(QEvent::ToolTip, below, view->mapToGlobal(below));
  QApplication::sendEvent(view, &help);
  EXPECT_TRUE(QToolTip::isVisible());
  EXPECT_TRUE(QToolTip::text().contains(note)) << QToolTip::text().toStdString();
  QToolTip::hideText();
}

}  // namespace
}  // namespace motionmap::studio::testing
