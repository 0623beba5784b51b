// Key poses in Studio (takes/keys_controller.h): Ctrl-clicked frames become an in-between take
// through their poses; keys added, removed, moved and retimed, each an undo step; what the
// in-betweening says (keys too far apart for their time) in the status line.
#include <QSignalSpy>
#include <QTest>
#include <algorithm>
#include <filesystem>

#include "map/map_gestures.h"
#include "map/map_view.h"
#include "studio_test_util.h"
#include "takes/keys_controller.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::windowWithMap;

Eigen::Vector2d pointOfFrame(const MapResult& map, int frame) {
  return map.blender->sample_point(map.rowOfFrame[0][std::size_t(frame)]);
}

// Places a key with a Ctrl-click where frame `frame` of clip `clip` is drawn.
void ctrlClickFrame(MainWindow& w, int frame, int clip = 0) {
  const MapResult& map = *w.currentMap();
  const QPointF pixel = w.mapView()->toWidget(
      map.blender->sample_point(map.rowOfFrame[std::size_t(clip)][std::size_t(frame)]));
  QTest::mouseClick(w.mapView(), Qt::LeftButton, Qt::ControlModifier, pixel.toPoint());
}

// The key's own pose (a frame of the clip, standing where it stood) at frame `at` of `motion`.
void expectKeyPose(const Motion& motion, int at, const synth::Key& key) {
  ASSERT_TRUE(key.has_pose()) << key.label;
  for (int j = 0; j < motion.num_joints; ++j) {
    EXPECT_NEAR(std::abs(motion.rotation(at, j).dot(key.pose.rotation(0, j))), 1.0, 1e-12)
        << key.label << " joint " << j;
    EXPECT_LT((motion.translation(at, j) - key.pose.translation(0, j)).norm(), 1e-9)
        << key.label << " joint " << j;
  }
}

// The key clicked at frame `frame`'s point is a frame of the clip drawn within a click's reach of
// it (the frame nearest the pixel: neighbouring frames of the 120 fps swing overlap at the map's
// scale, and its trajectory passes near itself), with that frame's pose.
void expectKeyNearFrame(MainWindow& w, const synth::Key& key, const Clip& clip, int frame) {
  const auto colon = key.label.rfind(':');
  ASSERT_NE(colon, std::string::npos) << key.label;
  const int at = std::stoi(key.label.substr(colon + 1));
  const QPointF clicked = w.mapView()->toWidget(pointOfFrame(*w.currentMap(), frame));
  const QPointF drawn = w.mapView()->toWidget(pointOfFrame(*w.currentMap(), at));
  EXPECT_LE(QLineF(clicked, drawn).length(), MapGestures::kNearPixels + 1.0) << key.label;
  ASSERT_LT(at, clip.motion.num_frames);
  for (int j = 0; j < clip.motion.num_joints; ++j) {
    EXPECT_NEAR(std::abs(key.pose.rotation(0, j).dot(clip.motion.rotation(at, j))), 1.0, 1e-12);
    EXPECT_LT((key.pose.translation(0, j) - clip.motion.translation(at, j)).norm(), 1e-9);
  }
}

bool waitForSynthesis(MainWindow& w) {
  return QTest::qWaitFor([&] { return !w.isSynthesizing(); }, kTimeoutMs);
}

TEST(StudioKeys, TwoCtrlClickedFramesMakeAnInBetweenTakeThroughTheirPoses) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  const Clip& clip = *w->clip();
  ctrlClickFrame(*w, 20);
  ASSERT_EQ(w->keys()->pendingKeys().size(), 1u) << w->lastError().toStdString();
  EXPECT_EQ(w->mapView()->pendingKeys().size(), 1u);
  EXPECT_EQ(w->takes()->list().count(), 0);
  ctrlClickFrame(*w, 150);
  ASSERT_TRUE(waitForSynthesis(*w));
  ASSERT_EQ(w->takes()->list().count(), 1) << w->lastError().toStdString();
  EXPECT_TRUE(w->keys()->pendingKeys().empty());
  const Take& take = w->takes()->list().at(0);
  ASSERT_EQ(take.keys.keys.size(), 2u);
  ASSERT_EQ(take.controls.size(), 2u);
  // The keys are the frames clicked; the motion passes through their poses, root included.
  const Motion& motion = take.result->motion;
  expectKeyNearFrame(*w, take.keys.keys[0], clip, 20);
  expectKeyNearFrame(*w, take.keys.keys[1], clip, 150);
  expectKeyPose(motion, take.controls[0], take.keys.keys[0]);
  expectKeyPose(motion, take.controls[1], take.keys.keys[1]);
  // Its route is drawn with numbered keys, inside the data.
  const auto paths = w->takes()->pathsOn(map);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_TRUE(paths[0].keyed);
  EXPECT_EQ(paths[0].points.size(), std::size_t(motion.num_frames));
  for (const auto& v : take.result->validity) EXPECT_FALSE(v.clamped);
  // Undo takes it away, redo brings it back.
  w->takes()->undo();
  EXPECT_EQ(w->takes()->list().count(), 0);
  w->takes()->redo();
  EXPECT_EQ(w->takes()->list().count(), 1);
}

TEST(StudioKeys, KeysAreAddedRemovedMovedAndRetimedAsUndoSteps) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  const Clip& clip = *w->clip();
  ctrlClickFrame(*w, 20);
  ctrlClickFrame(*w, 100);
  ASSERT_TRUE(waitForSynthesis(*w));
  ASSERT_EQ(w->takes()->list().count(), 1) << w->lastError().toStdString();
  w->takes()->list().setCurrent(0);
  // A third key: appended.
  ctrlClickFrame(*w, 200);
  ASSERT_TRUE(waitForSynthesis(*w));
  const Take* take = w->keys()->keyedTake();
  ASSERT_NE(take, nullptr);
  ASSERT_EQ(take->keys.keys.size(), 3u) << w->lastError().toStdString();
  expectKeyNearFrame(*w, take->keys.keys[2], clip, 200);
  expectKeyPose(take->result->motion, take->controls[2], take->keys.keys[2]);
  // Ctrl-click on key 2 (frame 100's): removed.
  const QPointF second =
      w->mapView()->toWidget(take->result->validity[std::size_t(take->controls[1])].point);
  ASSERT_TRUE(w->placeKey(w->mapView()->toMap(second), second));
  ASSERT_TRUE(waitForSynthesis(*w));
  take = w->keys()->keyedTake();
  ASSERT_EQ(take->keys.keys.size(), 2u);
  expectKeyNearFrame(*w, take->keys.keys[1], clip, 200);
  expectKeyPose(take->result->motion, take->controls[1], take->keys.keys[1]);
  // Moved: key 2 onto frame 60.
  ASSERT_TRUE(w->keys()->moveKey(1, pointOfFrame(*map, 60),
                                 w->mapView()->toWidget(pointOfFrame(*map, 60))));
  ASSERT_TRUE(waitForSynthesis(*w));
  take = w->keys()->keyedTake();
  expectKeyNearFrame(*w, take->keys.keys[1], clip, 60);
  expectKeyPose(take->result->motion, take->controls[1], take->keys.keys[1]);
  // Retimed: the second key two seconds after the first.
  ASSERT_TRUE(w->keys()->retime({0.0, 2.0}));
  ASSERT_TRUE(waitForSynthesis(*w));
  take = w->keys()->keyedTake();
  const double dt = take->result->motion.frame_time;
  EXPECT_EQ(take->controls[1] - take->controls[0], int(std::lround(2.0 / dt)));
  // Each change was one step: undo the retime, the move, the removal, the addition.
  for (const std::size_t keys : {2u, 2u, 3u, 2u}) {
    w->takes()->undo();
    ASSERT_NE(w->keys()->keyedTake(), nullptr);
    EXPECT_EQ(w->keys()->keyedTake()->keys.keys.size(), keys);
  }
  // Two keys cannot lose one.
  const Take* two = w->keys()->keyedTake();
  const QPointF first =
      w->mapView()->toWidget(two->result->validity[std::size_t(two->controls[0])].point);
  EXPECT_FALSE(w->placeKey(w->mapView()->toMap(first), first));
  EXPECT_TRUE(w->lastError().contains("two keys")) << w->lastError().toStdString();
  // Times for another number of keys: refused, nothing started.
  EXPECT_FALSE(w->keys()->retime({0.0, 1.0, 2.0}));
  EXPECT_FALSE(w->isSynthesizing());
  EXPECT_TRUE(w->lastError().contains("3 times for 2 keys")) << w->lastError().toStdString();
}

// An in-between's notes reach the status line: keys of two takes captured 2.8 m apart, retimed
// to 0.3 s, make the root glide (synth::inbetween says so, with the time the clips would take).
TEST(StudioKeys, AnInBetweenTakesNotesAreInTheStatusLine) {
  const std::string bandai = std::string(MOTIONMAP_SHARED_DATA) + "/bandai/dataset-1_";
  const std::string walk = bandai + "walk_angry_001.bvh", bow = bandai + "bow_normal_001.bvh";
  if (!std::filesystem::exists(walk) || !std::filesystem::exists(bow))
    GTEST_SKIP() << "no Bandai takes in " << MOTIONMAP_SHARED_DATA;
  MainWindow w;
  ASSERT_TRUE(testing::showOnPcaMap(w, {walk, bow}));
  ctrlClickFrame(w, 20, 0);
  ctrlClickFrame(w, 40, 1);
  ASSERT_TRUE(waitForSynthesis(w));
  ASSERT_EQ(w.takes()->list().count(), 1) << w.lastError().toStdString();
  // The window's width with nothing running (measured before the first synthesis, it could
  // include what shows the work in progress: 728 px against 705 after, on a fresh build).
  const int width = w.minimumSizeHint().width();
  ASSERT_TRUE(w.keys()->retime({0.0, 0.3}));
  ASSERT_TRUE(waitForSynthesis(w));
  const Take& take = w.takes()->list().at(w.takes()->list().count() - 1);
  ASSERT_TRUE(take.result);
  const auto glide = std::find_if(take.result->notes.begin(), take.result->notes.end(),
                                  [](const std::string& n) { return n.find("apart") != n.npos; });
  ASSERT_NE(glide, take.result->notes.end())
      << take.keys.keys[0].label << " to " << take.keys.keys[1].label;
  std::printf("[ figures  ] %s\n", glide->c_str());
  // It names the keys as the map numbers them, from 1.
  EXPECT_EQ(
      glide->rfind(
          "key 1 (" + take.keys.keys[0].label + ") to key 2 (" + take.keys.keys[1].label + ")", 0),
      0u)
      << *glide;
  // The take plays when its motion arrives; the status line says what its synthesis said.
  EXPECT_TRUE(w.statusText().contains(QString::fromStdString(*glide)))
      << w.statusText().toStdString();
  EXPECT_TRUE(w.statusToolTip().contains(QString::fromStdString(*glide)));
  // A long status line does not widen the window.
  EXPECT_EQ(w.minimumSizeHint().width(), width);
}

// Keys of two takes captured in different places, untimed: the walk's key to the bow's. Each
// key's root standing where it stood in its take, the root glides to the bow's and a note says
// so. With free roots (Motion → Synthesis…, "In-between roots: free after the first key"), the
// bow's pose is still hit, but its root stands where the clips carry it: no glide.
TEST(StudioKeys, AnInBetweensLaterRootsCanStandWhereTheClipsCarryThem) {
  const std::string bandai = std::string(MOTIONMAP_SHARED_DATA) + "/bandai/dataset-1_";
  const std::string walk = bandai + "walk_angry_001.bvh", bow = bandai + "bow_normal_001.bvh";
  if (!std::filesystem::exists(walk) || !std::filesystem::exists(bow))
    GTEST_SKIP() << "no Bandai takes in " << MOTIONMAP_SHARED_DATA;
  for (const bool free : {false, true}) {
    MainWindow w;
    ASSERT_TRUE(testing::showOnPcaMap(w, {walk, bow}));
    SynthParameters parameters = w.synthParameters();
    parameters.freeRoots = free;
    ASSERT_TRUE(w.setSynthParameters(parameters));
    ctrlClickFrame(w, 20, 0);
    ctrlClickFrame(w, 40, 1);
    ASSERT_TRUE(waitForSynthesis(w));
    ASSERT_EQ(w.takes()->list().count(), 1) << w.lastError().toStdString();
    const Take& take = w.takes()->list().at(0);
    ASSERT_TRUE(take.result);
    const auto glides =
        std::count_if(take.result->notes.begin(), take.result->notes.end(),
                      [](const std::string& n) { return n.find("glides") != std::string::npos; });
    EXPECT_EQ(glides, free ? 0 : 1) << ::testing::PrintToString(take.result->notes);
    const Motion& m = take.result->motion;
    const synth::Key& key = take.keys.keys[1];
    const int last = m.num_frames - 1, root = take.map->blender->motion_root();
    for (int j = root + 1; j < m.num_joints; ++j) {
      EXPECT_NEAR(std::abs(m.rotation(last, j).dot(key.pose.rotation(0, j))), 1.0, 1e-12)
          << "joint " << j;
    }
    const double apart = (m.translation(last, root) - key.pose.translation(0, root)).norm();
    std::printf("[ figures  ] %s: the bow's root %.3g cm from where it stood in its take\n",
                free ? "free roots" : "roots at every key", apart);
    if (free) {
      EXPECT_GT(apart, 100.0);
    } else {
      EXPECT_LT(apart, 1e-9);
    }
  }
}

}  // namespace
}  // namespace motionmap::studio
