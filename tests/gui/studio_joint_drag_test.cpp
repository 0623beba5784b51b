// Posing by dragging a joint in the 3-D view (map/joint_drag.h): the view turns a drag that
// starts on a joint into targets in space, the controller poses the body from the map.
#include <QSignalSpy>
#include <QTest>

#include "map/joint_drag.h"
#include "map/map_view.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::windowWithMap;

int jointNamed(const Skeleton& skeleton, const std::string& part) {
  for (int j = 0; j < skeleton.num_joints(); ++j)
    if (skeleton.joints[std::size_t(j)].name.find(part) != std::string::npos) return j;
  return -1;
}

TEST(StudioJointDrag, AHandDraggedToWhereItIsInAnotherFramePosesTheBodyFromTheMap) {
  auto w = windowWithMap();
  SkeletonView* view = w->skeletonView();
  ASSERT_TRUE(view->jointDragEnabled());
  const Clip& clip = *w->clip();
  const int hand = jointNamed(clip.skeleton, "Hand");
  ASSERT_GE(hand, 0);
  w->setFrame(0);
  const Eigen::Vector3d from = view->worldPose().positions[std::size_t(hand)];
  // Where the hand is in frame 40's pose standing where frame 0 stands (the drag's placement): a
  // pose of the data, which the map has at frame 40's point.
  const MapResult* map = w->currentMap();
  const synth::MapBlender& blender = *map->blender;
  Motion pose40 = blender.pose_at(blender.sample_point(map->rowOfFrame[0][40]));
  synth::place_root(
      pose40, blender.motion_root(),
      synth::root_placement(clip.motion, 0, blender.motion_root(), blender.options().up),
      blender.options().up);
  const Eigen::Vector3d target =
      forward_kinematics(clip.skeleton, pose40, 0).positions[std::size_t(hand)];
  const double moved = (target - from).norm();
  ASSERT_GT(moved, 0.0);
  QSignalSpy reached(w->jointDrag(), &JointDrag::reached);
  emit view->jointDragStarted(hand, from);
  // A drag of several steps, as the mouse moves.
  for (int step = 1; step <= 5; ++step)
    emit view->jointDragged(hand, from + (target - from) * (step / 5.0));
  ASSERT_EQ(reached.count(), 5);
  ASSERT_TRUE(w->jointDrag()->last().has_value());
  const synth::ReachResult& r = *w->jointDrag()->last();
  const Eigen::Vector3d now = view->worldPose().positions[std::size_t(hand)];
  std::printf("hand moved %.3g, now %.3g from the target (%.2f %% of the height)\n", moved,
              (now - target).norm(), 100.0 * r.error_fraction);
  EXPECT_NEAR((now - target).norm(), r.error, 1e-9 * (1.0 + moved));
  EXPECT_LT(r.error, 0.05 * moved);
  EXPECT_LT(r.error_fraction, 0.01);
  // The pointer is where the pose came from, inside the data.
  ASSERT_TRUE(w->mapView()->pointer().has_value());
  EXPECT_EQ(*w->mapView()->pointer(), r.point);
  EXPECT_FALSE(w->currentMap()->blender->locate(r.point).validity.clamped);
  emit view->jointDragFinished(hand);
}

TEST(StudioJointDrag, ThePinnedFootStaysWhileTheHandIsDragged) {
  auto w = windowWithMap();
  SkeletonView* view = w->skeletonView();
  const Clip& clip = *w->clip();
  const int hand = jointNamed(clip.skeleton, "Hand");
  const int foot = jointNamed(clip.skeleton, "Foot");
  ASSERT_GE(hand, 0);
  ASSERT_GE(foot, 0);
  w->setFrame(0);
  view->setPinnedJoints({foot});
  const Eigen::Vector3d from = view->worldPose().positions[std::size_t(hand)];
  const Eigen::Vector3d footAt = view->worldPose().positions[std::size_t(foot)];
  const Eigen::Vector3d target =
      forward_kinematics(clip.skeleton, clip.motion, 60).positions[std::size_t(hand)];
  emit view->jointDragStarted(hand, from);
  emit view->jointDragged(hand, target);
  ASSERT_TRUE(w->jointDrag()->last().has_value());
  const synth::ReachResult& r = *w->jointDrag()->last();
  ASSERT_EQ(r.pin_errors.size(), 1u);
  const Eigen::Vector3d footNow = view->worldPose().positions[std::size_t(foot)];
  EXPECT_NEAR((footNow - footAt).norm(), r.pin_errors[0], 1e-9 * (1.0 + r.height));
  EXPECT_LT(r.pin_errors[0], 0.05 * r.height);
}

TEST(StudioJointDrag, AMouseDragStartingOnAJointDragsItAndDoesNotOrbit) {
  auto w = windowWithMap();
  SkeletonView* view = w->skeletonView();
  w->setFrame(0);
  const int near = jointNamed(view->skeleton(), "Hand");
  ASSERT_GE(near, 0);
  const QPointF at = view->jointPixels()[std::size_t(near)];
  const int hand = view->jointAt(at);  // the hand, or a finger drawn over it
  ASSERT_GE(hand, 0);
  const OrbitCamera camera = view->camera();
  QSignalSpy started(view, &SkeletonView::jointDragStarted);
  int dragged = 0;
  Eigen::Vector3d lastTarget = Eigen::Vector3d::Zero();
  QObject::connect(view, &SkeletonView::jointDragged, view,
                   [&](int, const Eigen::Vector3d& target) {
                     ++dragged;
                     lastTarget = target;
                   });
  QSignalSpy finished(view, &SkeletonView::jointDragFinished);
  QTest::mousePress(view, Qt::LeftButton, {}, at.toPoint());
  QTest::mouseMove(view, (at + QPointF(30, -20)).toPoint());
  QTest::mouseRelease(view, Qt::LeftButton, {}, (at + QPointF(30, -20)).toPoint());
  EXPECT_EQ(started.count(), 1);
  EXPECT_GE(dragged, 1);
  EXPECT_EQ(finished.count(), 1);
  EXPECT_EQ(view->camera().yaw, camera.yaw);
  EXPECT_EQ(view->camera().pitch, camera.pitch);
  // The target lies in the plane through the joint facing the camera, under the mouse.
  if (dragged >= 1) {
    const QPointF pixel = projectToPixels(view->camera(), view->size(), lastTarget);
    EXPECT_NEAR(pixel.x(), at.toPoint().x() + 30, 1.0);
    EXPECT_NEAR(pixel.y(), at.toPoint().y() - 20, 1.0);
  }
  // Shift-click pins and unpins.
  const QPointF now = view->jointPixels()[std::size_t(hand)];
  const int under = view->jointAt(now);
  ASSERT_GE(under, 0);
  QTest::mouseClick(view, Qt::LeftButton, Qt::ShiftModifier, now.toPoint());
  EXPECT_EQ(view->pinnedJoints(), std::vector<int>{under});
  QTest::mouseClick(view, Qt::LeftButton, Qt::ShiftModifier, now.toPoint());
  EXPECT_TRUE(view->pinnedJoints().empty());
}

}  // namespace
}  // namespace motionmap::studio
