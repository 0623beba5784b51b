// Sketching, key poses, take edits and joint dragging on a saved map (issues #23 and #24): they
// work as on a computed map, on a blender the saved map's source builds once on a worker
// (mapfile::make_blender, clips read on demand), and give what the library gives on the same map
// (`motionmap synth/inbetween/reach --map`). A clip the map needs that is gone is an error naming
// its file. Map files are made in the test's temporary folder from real clips in ../shared/data.
#include <unistd.h>

#include <QImage>
#include <QSignalSpy>
#include <QTest>
#include <cstdio>
#include <filesystem>

#include "map/joint_drag.h"
#include "map/map_gestures.h"
#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/path_edit.h"
#include "motionmap/synth/reach.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"
#include "takes/keys_controller.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {
namespace {

namespace fs = std::filesystem;

const std::string kData = MOTIONMAP_SHARED_DATA;
// Two golf swings at 120 fps, of 365 and 453 frames.
constexpr const char* kClips[] = {"64_08.bvh", "64_09.bvh"};

// A folder of its own per test with copies of two golf swings (so a test may delete one) and
// their PCA map saved as lib.mmap.h5, opened in a shown, non-interactive window.
class SavedSynthFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : kClips) {
      if (!fs::exists(kData + "/cmu/" + name)) GTEST_SKIP() << "no " << name << " in " << kData;
    }
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = fs::temp_directory_path() /
            ("motionmap-studio-saved-synth-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(m_dir);
    fs::create_directories(m_dir);
    for (const char* name : kClips) {
      fs::copy_file(kData + "/cmu/" + name, m_dir / name);
      m_clips.push_back(io::load_clip((m_dir / name).string()));
    }
    m_file = (m_dir / "lib.mmap.h5").string();
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

  /// Writes the clips' map as m_file; `blendRecord` false: without what blending needs of every
  /// clip (as an older MotionMap wrote it), so a blender reads every clip once first.
  void saveMap(bool blendRecord = true) {
    pipeline::ClipMapOptions options;
    options.embed.method = embed::Method::Pca;
    const pipeline::ClipMap map = pipeline::map_clips(m_clips, options);
    mapfile::MapFile file = mapfile::make_map_file(m_clips, map, options);
    if (!blendRecord) file.blend.reset();
    mapfile::write_map_file(m_file, file);
  }

  /// Opens m_file and waits for its blender (built on a worker as the map opens).
  void openAndWaitForTheBlender() {
    ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)))
        << m_window->lastError().toStdString();
    ASSERT_TRUE(
        QTest::qWaitFor([&] { return m_window->currentMap() != nullptr; }, testing::kTimeoutMs))
        << m_window->lastError().toStdString();
  }

  /// What the library makes of the same map: its own SavedMap and blender, with the window's
  /// blend options.
  synth::MapBlender libraryBlender() {
    m_library =
        std::make_shared<const mapfile::SavedMap>(mapfile::read_map_file(m_file, {.model = false}));
    synth::BlendOptions blend = m_window->synthParameters().blend;
    blend.up = m_library->file().options.features.up;
    return mapfile::make_blender(m_library, blend);
  }

  /// The map row of frame `frame` of clip `clip` (a frame left out of the map, the CMU clips'
  /// bind pose: a test failure).
  int rowOf(int clip, int frame) const {
    const mapfile::MapFile& file = m_window->savedMap()->file();
    const mapfile::ClipRecord& record = file.clips[std::size_t(clip)];
    for (int r = record.first_sample; r < record.first_sample + record.samples; ++r)
      if (file.frame_of[std::size_t(r)] == frame) return r;
    ADD_FAILURE() << "frame " << frame << " of clip " << clip << " is not on the map";
    return record.first_sample;
  }
  Eigen::Vector2d pointOf(int clip, int frame) const {
    const auto& xy = m_window->savedMap()->file().coordinates;
    const int row = rowOf(clip, frame);
    return {xy(row, 0), xy(row, 1)};
  }

  /// A sketch 3 s long along clip 0's frames 20…340, then clip 1's frames 60…420.
  synth::MapPath sketch() const {
    synth::MapPath path;
    for (int f = 20; f <= 340; f += 8) path.points.push_back(pointOf(0, f));
    for (int f = 60; f <= 420; f += 8) path.points.push_back(pointOf(1, f));
    for (std::size_t i = 0; i < path.points.size(); ++i)
      path.times.push_back(3.0 * double(i) / double(path.points.size() - 1));
    return path;
  }

  bool waitForSynthesis() {
    return QTest::qWaitFor([&] { return !m_window->isSynthesizing(); }, testing::kTimeoutMs);
  }

  fs::path m_dir;
  std::string m_file;
  std::vector<Clip> m_clips;
  std::unique_ptr<MainWindow> m_window;
  std::shared_ptr<const mapfile::SavedMap> m_library;
};

/// The largest difference between two motions' numbers: their rotations' quaternion coefficients
/// (q and −q the same rotation) and translations; 0 when they are the same bit for bit, infinity
/// for motions of other sizes.
double motionDifference(const Motion& a, const Motion& b) {
  if (a.num_frames != b.num_frames || a.num_joints != b.num_joints)
    return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (int f = 0; f < a.num_frames; ++f) {
    for (int j = 0; j < a.num_joints; ++j) {
      const Eigen::Vector4d p = a.rotation(f, j).coeffs(), q = b.rotation(f, j).coeffs();
      worst =
          std::max(worst, std::min((p - q).cwiseAbs().maxCoeff(), (p + q).cwiseAbs().maxCoeff()));
      worst = std::max(worst, (a.translation(f, j) - b.translation(f, j)).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}

TEST_F(SavedSynthFixture, ASketchIsTheLibrarysSynthesisOnTheSameMapAndItsControlPointsEdit) {
  saveMap();
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)))
      << m_window->lastError().toStdString();
  // Sketched at once: the blender is built on the worker if it is not ready yet.
  QSignalSpy progress(m_window.get(), &MainWindow::synthesisProgress);
  QSignalSpy finished(m_window.get(), &MainWindow::synthesisFinished);
  const synth::MapPath path = sketch();
  ASSERT_TRUE(m_window->synthesizeAlong(path)) << m_window->lastError().toStdString();
  ASSERT_TRUE(waitForSynthesis());
  ASSERT_EQ(finished.count(), 1);
  ASSERT_TRUE(finished.at(0).at(0).toBool()) << m_window->lastError().toStdString();
  EXPECT_GT(progress.count(), 0);
  ASSERT_EQ(m_window->takes()->list().count(), 1);
  const Take& take = m_window->takes()->list().at(0);
  ASSERT_NE(take.result, nullptr);
  // The take blends on the saved map's blender, the one the window now shows as its map.
  ASSERT_NE(m_window->currentMap(), nullptr);
  EXPECT_EQ(take.map.get(), m_window->currentMap());
  EXPECT_EQ(m_window->synthesized(), take.result.get());

  // The same motion as the library's on the same map and path, bit for bit.
  const synth::MapBlender blender = libraryBlender();
  synth::MapPath followed = path;
  if (!m_window->synthParameters().timedAsDrawn) followed.times.clear();
  const synth::SynthResult expected =
      synth::synthesize(blender, followed, m_window->synthParameters().motion);
  ASSERT_GT(expected.motion.num_frames, 300);  // 3 s at 120 fps
  EXPECT_EQ(motionDifference(take.result->motion, expected.motion), 0.0);
  EXPECT_EQ(take.result->clamped_frames, expected.clamped_frames);
  // It plays, with the pointer on the take's own point of the map.
  m_window->pause();
  m_window->setFrame(10);
  ASSERT_TRUE(m_window->mapView()->pointer().has_value());
  EXPECT_EQ(*m_window->mapView()->pointer(), take.result->validity[10].point);

  // Its path is drawn on the saved map, current, with its control points.
  const auto& drawn = m_window->mapView()->takePaths();
  ASSERT_EQ(drawn.size(), 1u);
  EXPECT_TRUE(drawn[0].current);
  EXPECT_EQ(drawn[0].points, path.points);
  ASSERT_GE(drawn[0].controls.size(), 3u);
  // Looked at: the window after the sketch, the density under the violet path.
  const QString shot = QString::fromStdString(
      (fs::temp_directory_path() / "motionmap-studio-saved-sketch.png").string());
  const QImage image = m_window->screenshot();
  ASSERT_FALSE(image.isNull());
  EXPECT_TRUE(image.save(shot));
  std::printf("saved %s\n", qPrintable(shot));
  int violet = 0;
  const QImage map = m_window->mapView()->grab().toImage();
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) violet += map.pixelColor(x, y) == MapView::takeColor();
  EXPECT_GT(violet, 50);

  // A control point dragged: the take is re-made as synth::edit_path makes it on the library's
  // blender, one undo step.
  const std::shared_ptr<const synth::SynthResult> before = take.result;
  const int control = 1;
  const Eigen::Vector2d to = pointOf(0, 200);
  const synth::MapPath moved = deformPath(take.path, take.controls, control, to);
  ASSERT_TRUE(m_window->moveControlPoint(control, to)) << m_window->lastError().toStdString();
  ASSERT_TRUE(waitForSynthesis());
  ASSERT_EQ(finished.count(), 2);
  ASSERT_TRUE(finished.at(1).at(0).toBool()) << m_window->lastError().toStdString();
  const Take& edited = m_window->takes()->list().at(0);
  EXPECT_EQ(edited.path.points, moved.points);
  const synth::PathEditResult expectedEdit = synth::edit_path(blender, *before, moved, {});
  EXPECT_EQ(motionDifference(edited.result->motion, expectedEdit.result.motion), 0.0);
  EXPECT_EQ(m_window->mapView()->takePaths().at(0).points, moved.points);
  m_window->takes()->undo();
  EXPECT_EQ(m_window->takes()->list().at(0).result, before);
}

TEST_F(SavedSynthFixture, AShiftDragWithTheMouseSketchesATakeAndItsControlPointIsDragged) {
  saveMap();
  openAndWaitForTheBlender();
  MapView* view = m_window->mapView();
  QSignalSpy sketches(view, &MapView::sketchFinished);
  QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier,
                    view->toWidget(pointOf(1, 40)).toPoint());
  for (int frame = 60; frame <= 400; frame += 20) {
    QTest::qWait(10);
    QTest::mouseMove(view, view->toWidget(pointOf(1, frame)).toPoint());
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::ShiftModifier,
                      view->toWidget(pointOf(1, 400)).toPoint());
  ASSERT_EQ(sketches.count(), 1);
  ASSERT_TRUE(waitForSynthesis());
  ASSERT_EQ(m_window->takes()->list().count(), 1) << m_window->lastError().toStdString();
  const Take& take = m_window->takes()->list().at(0);
  EXPECT_GT(take.result->motion.num_frames, 0);
  ASSERT_EQ(view->takePaths().size(), 1u);
  ASSERT_GE(take.controls.size(), 3u);
  // The middle control point dragged with the mouse onto frame 200 of the first clip.
  const int control = int(take.controls.size()) / 2;
  const QPoint from =
      view->toWidget(take.path.points[std::size_t(take.controls[std::size_t(control)])]).toPoint();
  const QPoint to = view->toWidget(pointOf(0, 200)).toPoint();
  const auto before = take.result;
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, from);
  QTest::mouseMove(view, (from + to) / 2);
  QTest::mouseMove(view, to);
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, to);
  ASSERT_TRUE(waitForSynthesis());
  const Take& edited = m_window->takes()->list().at(0);
  EXPECT_NE(edited.result, before) << m_window->lastError().toStdString();
  EXPECT_LT((edited.path.points[std::size_t(edited.controls[std::size_t(control)])] -
             view->toMap(QPointF(to)))
                .norm(),
            1e-9);
  EXPECT_TRUE(m_window->takes()->undoStack().canUndo());
}

TEST_F(SavedSynthFixture, ASketchCancelledAtOnceAddsNothingAndTheNextOneWorks) {
  // A map that must read every clip for its blender: cancelled while that build may still run.
  saveMap(/*blendRecord=*/false);
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)))
      << m_window->lastError().toStdString();
  QSignalSpy finished(m_window.get(), &MainWindow::synthesisFinished);
  ASSERT_TRUE(m_window->synthesizeAlong(sketch()));
  EXPECT_TRUE(m_window->isSynthesizing());
  m_window->cancelSynthesis();  // returns once the worker stopped
  EXPECT_FALSE(m_window->isSynthesizing());
  ASSERT_EQ(finished.count(), 1);
  EXPECT_FALSE(finished.at(0).at(0).toBool());
  EXPECT_TRUE(m_window->statusText().contains("cancelled")) << m_window->statusText().toStdString();
  EXPECT_EQ(m_window->takes()->list().count(), 0);
  ASSERT_TRUE(m_window->synthesizeAlong(sketch()));
  ASSERT_TRUE(waitForSynthesis());
  EXPECT_EQ(m_window->takes()->list().count(), 1) << m_window->lastError().toStdString();
  EXPECT_EQ(m_window->takes()->list().at(0).map.get(), m_window->currentMap());
}

TEST_F(SavedSynthFixture, CtrlClickedFramesOfTwoClipsMakeAnInBetweenThroughTheirPoses) {
  saveMap();
  openAndWaitForTheBlender();
  MapView* view = m_window->mapView();
  const auto click = [&](int clip, int frame) {
    QTest::mouseClick(view, Qt::LeftButton, Qt::ControlModifier,
                      view->toWidget(pointOf(clip, frame)).toPoint());
  };
  click(0, 150);
  ASSERT_EQ(m_window->keys()->pendingKeys().size(), 1u) << m_window->lastError().toStdString();
  click(1, 300);
  ASSERT_TRUE(waitForSynthesis());
  ASSERT_EQ(m_window->takes()->list().count(), 1) << m_window->lastError().toStdString();
  const Take& take = m_window->takes()->list().at(0);
  ASSERT_EQ(take.keys.keys.size(), 2u);
  ASSERT_EQ(take.controls.size(), 2u);
  EXPECT_EQ(take.map.get(), m_window->currentMap());
  // Each key is a frame of the clip clicked, drawn within a click's reach of the click, with
  // that frame's pose; the motion passes through it at its key frame.
  const Motion& motion = take.result->motion;
  const int clips[] = {0, 1};
  const int frames[] = {150, 300};
  for (int k = 0; k < 2; ++k) {
    const synth::Key& key = take.keys.keys[std::size_t(k)];
    ASSERT_TRUE(key.has_pose()) << key.label;
    const auto colon = key.label.rfind(':');
    ASSERT_NE(colon, std::string::npos) << key.label;
    EXPECT_EQ(key.label.substr(0, colon), kClips[clips[k]]);
    const int at = std::stoi(key.label.substr(colon + 1));
    EXPECT_LE(
        QLineF(view->toWidget(pointOf(clips[k], frames[k])), view->toWidget(pointOf(clips[k], at)))
            .length(),
        MapGestures::kNearPixels + 1.0)
        << key.label;
    const Motion& source = m_clips[std::size_t(clips[k])].motion;
    const int f = take.controls[std::size_t(k)];
    for (int j = 0; j < motion.num_joints; ++j) {
      EXPECT_NEAR(std::abs(key.pose.rotation(0, j).dot(source.rotation(at, j))), 1.0, 1e-12);
      EXPECT_NEAR(std::abs(motion.rotation(f, j).dot(key.pose.rotation(0, j))), 1.0, 1e-12)
          << key.label << " joint " << j;
      EXPECT_LT((motion.translation(f, j) - key.pose.translation(0, j)).norm(), 1e-9);
    }
  }
  // The library's in-between of the same keys on the same map: the same motion.
  const synth::MapBlender blender = libraryBlender();
  synth::InbetweenOptions options;
  options.frames_between = take.keys.framesBetween;
  options.clean_feet = m_window->synthParameters().motion.clean_feet;
  const synth::InbetweenResult expected =
      synth::inbetween(blender, m_library->samples(), take.keys.keys, options);
  EXPECT_EQ(motionDifference(motion, expected.motion), 0.0);
  EXPECT_EQ(take.controls, expected.key_frames);
  // Its route is drawn with its numbered keys.
  ASSERT_EQ(view->takePaths().size(), 1u);
  EXPECT_TRUE(view->takePaths()[0].keyed);
  EXPECT_EQ(view->takePaths()[0].points.size(), std::size_t(motion.num_frames));
}

TEST_F(SavedSynthFixture, AHandDraggedToWhereItIsInAFrameOfTheOtherClipIsReached) {
  saveMap();
  openAndWaitForTheBlender();
  m_window->pause();
  m_window->setFrame(100);
  SkeletonView* view = m_window->skeletonView();
  ASSERT_TRUE(view->jointDragEnabled());
  const Skeleton& skeleton = m_window->clip()->skeleton;
  int hand = -1;
  for (int j = 0; j < skeleton.num_joints() && hand < 0; ++j)
    if (skeleton.joints[std::size_t(j)].name.find("Hand") != std::string::npos) hand = j;
  ASSERT_GE(hand, 0);
  const Eigen::Vector3d from = view->worldPose().positions[std::size_t(hand)];
  // Where the hand is in clip 1's frame 300, standing where the frame shown stands (the drag's
  // placement): a pose of the data, at that frame's point of the map.
  const synth::MapBlender blender = libraryBlender();
  const Axis up = blender.options().up;
  Motion target = blender.pose_at(blender.sample_point(rowOf(1, 300)));
  synth::place_root(target, blender.motion_root(),
                    synth::root_placement(m_clips[0].motion, 100, blender.motion_root(), up), up);
  const Eigen::Vector3d to = forward_kinematics(skeleton, target, 0).positions[std::size_t(hand)];
  ASSERT_GT((to - from).norm(), 0.0);
  // The first drag starts preparing the poses to reach from (every clip read once, on a worker)
  // and says so; the body stays.
  QSignalSpy failed(m_window->jointDrag(), &JointDrag::failed);
  QSignalSpy reached(m_window->jointDrag(), &JointDrag::reached);
  emit view->jointDragStarted(hand, from);
  emit view->jointDragged(hand, to);
  ASSERT_EQ(failed.count(), 1);
  EXPECT_TRUE(failed.at(0).at(0).toString().contains("Preparing to pose"))
      << failed.at(0).at(0).toString().toStdString();
  EXPECT_EQ(reached.count(), 0);
  EXPECT_EQ((view->worldPose().positions[std::size_t(hand)] - from).norm(), 0.0);
  emit view->jointDragFinished(hand);
  auto* source = m_window->findChild<SavedMapSource*>();
  ASSERT_NE(source, nullptr);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !source->isPreparing(); }, testing::kTimeoutMs));
  QCoreApplication::processEvents();
  // Then a drag poses the body from the saved map.
  emit view->jointDragStarted(hand, from);
  for (int step = 1; step <= 5; ++step)
    emit view->jointDragged(hand, from + (to - from) * (step / 5.0));
  ASSERT_EQ(reached.count(), 5) << m_window->lastError().toStdString();
  ASSERT_TRUE(m_window->jointDrag()->last().has_value());
  const synth::ReachResult& r = *m_window->jointDrag()->last();
  const Eigen::Vector3d now = view->worldPose().positions[std::size_t(hand)];
  // Height of the skeleton: its extent along the up axis in the frame shown.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Eigen::Vector3d& p : forward_kinematics(skeleton, m_clips[0].motion, 100).positions) {
    lo = std::min(lo, p[int(up)]);
    hi = std::max(hi, p[int(up)]);
  }
  std::printf("hand moved %.3g, now %.3g from the target (%.2f %% of the height %.3g)\n",
              (to - from).norm(), (now - to).norm(), 100.0 * (now - to).norm() / (hi - lo),
              hi - lo);
  EXPECT_LT((now - to).norm(), 0.01 * (hi - lo));
  EXPECT_NEAR((now - to).norm(), r.error, 1e-9);
  // The pointer is where the pose came from.
  ASSERT_TRUE(m_window->mapView()->pointer().has_value());
  EXPECT_EQ(*m_window->mapView()->pointer(), r.point);
  emit view->jointDragFinished(hand);
}

TEST_F(SavedSynthFixture, AMissingClipIsAnErrorNamingItsFileNotACrash) {
  saveMap();
  fs::remove(m_dir / kClips[1]);  // the second clip: the map still opens on the first
  openAndWaitForTheBlender();     // what blending needs of it is in the map file
  // A sketch over its samples: the synthesis fails, naming the file; no take.
  ASSERT_TRUE(m_window->synthesizeAlong(sketch()));
  ASSERT_TRUE(waitForSynthesis());
  std::string error = m_window->lastError().toStdString();
  EXPECT_NE(error.find(kClips[1]), std::string::npos) << error;
  EXPECT_NE(error.find("is missing"), std::string::npos) << error;
  EXPECT_EQ(m_window->takes()->list().count(), 0);
  // A key on one of its frames: refused the same way, nothing kept.
  MapView* view = m_window->mapView();
  QTest::mouseClick(view, Qt::LeftButton, Qt::ControlModifier,
                    view->toWidget(pointOf(1, 300)).toPoint());
  EXPECT_TRUE(m_window->keys()->pendingKeys().empty());
  error = m_window->lastError().toStdString();
  EXPECT_NE(error.find(kClips[1]), std::string::npos) << error;
}

TEST_F(SavedSynthFixture, AMissingClipOfAMapThatMustReadEveryClipIsAnErrorNamingIt) {
  saveMap(/*blendRecord=*/false);
  fs::remove(m_dir / kClips[1]);
  ASSERT_TRUE(m_window->openMapFile(QString::fromStdString(m_file)))
      << m_window->lastError().toStdString();
  // The blender reads every clip once: it cannot be built, and a sketch says why.
  ASSERT_TRUE(m_window->synthesizeAlong(sketch()));
  ASSERT_TRUE(waitForSynthesis());
  const std::string error = m_window->lastError().toStdString();
  EXPECT_NE(error.find(kClips[1]), std::string::npos) << error;
  EXPECT_NE(error.find("is missing"), std::string::npos) << error;
  EXPECT_EQ(m_window->takes()->list().count(), 0);
  EXPECT_EQ(m_window->currentMap(), nullptr);
  // A joint drag says so too, and the body stays as it was.
  m_window->pause();
  SkeletonView* view = m_window->skeletonView();
  const Motion before = view->currentPose();
  QSignalSpy failed(m_window->jointDrag(), &JointDrag::failed);
  emit view->jointDragStarted(0, Eigen::Vector3d::Zero());
  emit view->jointDragged(0, Eigen::Vector3d(1.0, 2.0, 3.0));
  ASSERT_EQ(failed.count(), 1);
  EXPECT_FALSE(m_window->jointDrag()->last().has_value());
  EXPECT_EQ(motionDifference(view->currentPose(), before), 0.0);
  // With the clip back, the next sketch works.
  fs::copy_file(kData + "/cmu/" + kClips[1], m_dir / kClips[1]);
  QTest::qWait(50);
  ASSERT_TRUE(m_window->synthesizeAlong(sketch()));
  ASSERT_TRUE(waitForSynthesis());
  EXPECT_EQ(m_window->takes()->list().count(), 1) << m_window->lastError().toStdString();
}

}  // namespace
}  // namespace motionmap::studio
