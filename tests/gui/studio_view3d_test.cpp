// The 3-D view (issue #10, part A), offscreen: no bone from a static root to a hips that moves by
// its own translation channels; the whole clip framed in any unit and for wide, low bodies; F,
// Home and the camera presets; capsule meshes, left/right colours, trails, hover names and the
// Joints panel. The OpenGL drawing of the same is checked in gl_render_xvfb.cpp.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QFileInfo>
#include <QMouseEvent>
#include <QTest>
#include <QTreeWidget>
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "app/main_window.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "scene/joint_panel.h"
#include "scene/scene.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

const std::string kData = MOTIONMAP_SHARED_DATA;
const std::string kBandai = kData + "/other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh";
const std::string kSwing = kData + "/cmu/64_08.bvh";

bool exists(const std::string& path) {
  return QFileInfo::exists(QString::fromStdString(path));
}

/// `clip` with every offset, end site and translation scaled by `s` per axis.
Clip scaled(Clip clip, const Eigen::Vector3d& s) {
  for (Joint& joint : clip.skeleton.joints) {
    joint.offset = joint.offset.cwiseProduct(s);
    for (auto& e : joint.end_sites) e = e.cwiseProduct(s);
  }
  for (auto& t : clip.motion.translations) t = t.cwiseProduct(s);
  return clip;
}

/// Longest rest offset (joints and end sites).
double longestOffset(const Skeleton& skeleton) {
  double out = 0.0;
  for (const Joint& joint : skeleton.joints) {
    if (joint.parent >= 0) out = std::max(out, joint.offset.norm());
    for (const auto& e : joint.end_sites) out = std::max(out, e.norm());
  }
  return out;
}

TEST(StudioView3d, NoBoneFromAStaticRootToAHipsThatMovesByItself) {
  if (!exists(kBandai)) GTEST_SKIP() << "SKIPPED: " << kBandai << " not found";
  const Clip clip = io::load_clip(kBandai);
  const Skeleton& skeleton = clip.skeleton;
  const int root = skeleton.find("joint_Root"), hips = skeleton.find("Hips");
  ASSERT_EQ(root, 0);
  ASSERT_GE(hips, 0);
  const std::vector<bool> detached = detached_joints(skeleton, clip.motion);
  // Only the hips moves by its own channels; the other joints' channels repeat their offsets.
  for (int j = 0; j < skeleton.num_joints(); ++j)
    EXPECT_EQ(detached[std::size_t(j)], j == hips) << skeleton.joints[std::size_t(j)].name;
  const std::vector<bool> body = body_joints(skeleton, detached);
  EXPECT_FALSE(body[std::size_t(root)]) << "the static root has no bone left";
  EXPECT_EQ(std::count(body.begin(), body.end(), true), skeleton.num_joints() - 1);
  // Every parent→child bone but root→hips, and every end site's of non-zero length (this file's
  // end sites are all at their joints).
  int endSites = 0;
  for (const Joint& joint : skeleton.joints) {
    for (const auto& e : joint.end_sites) endSites += e.norm() > 0.0;
  }
  const int expected = skeleton.num_joints() - 2 + endSites;
  const double longest = longestOffset(skeleton);
  double worst = 0.0;
  for (int f = 0; f < clip.motion.num_frames; ++f) {
    const WorldPose pose = forward_kinematics(skeleton, clip.motion, f);
    const std::vector<BoneSegment> bones = bone_segments(skeleton, pose, detached);
    ASSERT_EQ(int(bones.size()), expected) << "frame " << f;
    for (const BoneSegment& b : bones) {
      worst = std::max(worst, (b.to - b.from).norm());
      EXPECT_NE(b.joint, hips) << "a bone ends at the hips in frame " << f;
    }
  }
  EXPECT_LE(worst, 2.0 * longest);
  // Without the rule the root→hips bone is metres long (the walk starts 4 m from the origin).
  const std::vector<BoneSegment> all =
      bone_segments(skeleton, forward_kinematics(skeleton, clip.motion, 0));
  double longestAll = 0.0;
  for (const BoneSegment& b : all) longestAll = std::max(longestAll, (b.to - b.from).norm());
  EXPECT_GT(longestAll, 3.0 * longest);

  // The view given the clip draws the same bones.
  SkeletonView view;
  view.resize(640, 480);
  view.setSkeleton(skeleton);
  view.setMotion(clip.motion);
  view.setPose(clip.motion, 100);
  EXPECT_EQ(int(view.bones().size()), expected);
  EXPECT_TRUE(view.detached()[std::size_t(hips)]);
}

TEST(StudioView3d, ASkeletonWhoseChannelsRepeatItsOffsetsKeepsAllBones) {
  const Clip clip = testing::swing();
  const std::vector<bool> detached = detached_joints(clip.skeleton, clip.motion);
  EXPECT_EQ(std::count(detached.begin(), detached.end(), true), 0);
  const std::vector<bool> body = body_joints(clip.skeleton, detached);
  EXPECT_EQ(std::count(body.begin(), body.end(), true), clip.skeleton.num_joints());
}

/// Pixel bounds of every body joint and end site of every frame, for the view framed on `clip`.
struct Coverage {
  int outside = 0, points = 0;
  QRectF box;  ///< union of the projected points
  std::string first;
};

Coverage playThrough(SkeletonView& view, const Clip& clip, bool follow) {
  view.setSkeleton(clip.skeleton);
  view.setFollowRoot(follow);
  view.setMotion(clip.motion);
  Coverage c;
  const QRectF inside(0, 0, view.width(), view.height());
  for (int f = 0; f < clip.motion.num_frames; ++f) {
    view.setPose(clip.motion, f);
    const WorldPose& pose = view.worldPose();
    std::vector<Eigen::Vector3d> points = pose.end_sites;
    for (std::size_t j = 0; j < pose.positions.size(); ++j) {
      if (view.body()[j]) points.push_back(pose.positions[j]);
    }
    for (const auto& p : points) {
      const QPointF q = projectToPixels(view.camera(), view.size(), p);
      ++c.points;
      c.box = c.box.isNull() ? QRectF(q, QSizeF(0.01, 0.01))
                             : c.box.united(QRectF(q, QSizeF(0.01, 0.01)));
      if (!inside.contains(q)) {
        if (c.outside++ == 0)
          c.first = "frame " + std::to_string(f) + " at (" + std::to_string(q.x()) + ", " +
                    std::to_string(q.y()) + ")";
      }
    }
  }
  return c;
}

void expectFramed(const Clip& clip, const std::string& what) {
  for (const QSize size : {QSize(640, 480), QSize(300, 600)}) {
    for (const bool follow : {true, false}) {
      SkeletonView view;
      view.resize(size);
      const Coverage c = playThrough(view, clip, follow);
      EXPECT_EQ(c.outside, 0) << what << (follow ? " following" : " fixed") << " in "
                              << size.width() << "×" << size.height() << ": " << c.outside << " of "
                              << c.points << " points outside, first " << c.first;
      // Not lost in the distance either: the motion spans a good part of the view.
      EXPECT_GT(std::max(c.box.width() / size.width(), c.box.height() / size.height()), 0.3)
          << what;
    }
  }
}

TEST(StudioView3d, FramesTheWholeClipInAnyUnitAndShape) {
  expectFramed(testing::swing(), "sample swing");
  // A crab: four times as wide, a third as high.
  expectFramed(scaled(testing::swing(), {4.0, 0.3, 1.0}), "wide, low swing");
  if (exists(kSwing)) expectFramed(io::load_clip(kSwing), "64_08");
  // Other exporters' files: nothing detached, everything framed.
  for (const std::string& other :
       {kData + "/asfamc/02_02.amc", kData + "/other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"}) {
    if (!exists(other)) continue;
    const Clip clip = io::load_clip(other);
    const auto detached = detached_joints(clip.skeleton, clip.motion);
    EXPECT_EQ(std::count(detached.begin(), detached.end(), true), 0) << other;
    expectFramed(clip, other);
  }
  if (!exists(kBandai)) GTEST_SKIP() << "SKIPPED: " << kBandai << " not found";
  const Clip walk = io::load_clip(kBandai);
  expectFramed(walk, "Bandai walk (cm)");
  expectFramed(scaled(walk, Eigen::Vector3d::Constant(0.01)), "Bandai walk (m)");
  expectFramed(scaled(walk, Eigen::Vector3d::Constant(1.0 / 2.54)), "Bandai walk (in)");
}

TEST(StudioView3d, FramesTheCharacterResetsAndPresets) {
  const Clip clip = testing::swing();
  SkeletonView view;
  view.resize(640, 480);
  view.show();
  view.setSkeleton(clip.skeleton);
  view.setMotion(clip.motion);
  view.setPose(clip.motion, 150);
  const OrbitCamera framed = view.camera();
  EXPECT_DOUBLE_EQ(framed.yaw, OrbitCamera::kDefaultYaw);
  EXPECT_DOUBLE_EQ(framed.pitch, OrbitCamera::kDefaultPitch);

  // Somewhere else: orbited, panned, zoomed out.
  OrbitCamera away = framed;
  away.yaw = 2.5;
  away.pitch = -0.4;
  away.pan = Eigen::Vector3d(50, 20, -30);
  away.distance *= 6.0;
  view.setCamera(away);

  // F: the current pose centred and filling the view; the angle stays.
  view.frameCharacter();
  EXPECT_DOUBLE_EQ(view.camera().yaw, 2.5);
  EXPECT_DOUBLE_EQ(view.camera().pitch, -0.4);
  EXPECT_TRUE(view.camera().pan.isZero());
  QRectF box;
  for (const QPointF& p : view.jointPixels()) {
    EXPECT_TRUE(QRectF(0, 0, 640, 480).contains(p)) << p.x() << ", " << p.y();
    box = box.isNull() ? QRectF(p, QSizeF(0.01, 0.01)) : box.united(QRectF(p, QSizeF(0.01, 0.01)));
  }
  EXPECT_GT(std::max(box.width() / 640.0, box.height() / 480.0), 0.5);
  const Eigen::Vector3d mid = view.camera().target;
  // The look-at point is the pose's box centre.
  Eigen::Vector3d lo = view.worldPose().positions[0], hi = lo;
  for (const auto* ps : {&view.worldPose().positions, &view.worldPose().end_sites}) {
    for (const auto& p : *ps) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  EXPECT_LT((mid - 0.5 * (lo + hi)).norm(), 1e-9 * view.extent());

  // Presets: yaw and pitch only.
  view.applyCameraPreset(CameraPreset::Front);
  EXPECT_DOUBLE_EQ(view.camera().yaw, 0.0);
  EXPECT_DOUBLE_EQ(view.camera().pitch, 0.0);
  EXPECT_EQ(view.camera().target, mid);
  view.applyCameraPreset(CameraPreset::Side);
  EXPECT_NEAR(view.camera().yaw, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(view.camera().pitch, 0.0);
  view.applyCameraPreset(CameraPreset::Top);
  EXPECT_NEAR(view.camera().pitch, M_PI / 2, 1e-12);
  // Straight down: the camera's up is −Z (so +Z runs down the screen), and it still projects.
  EXPECT_LT((view.camera().up() - Eigen::Vector3d(0, 0, -1)).norm(), 1e-9);
  for (const QPointF& p : view.jointPixels()) EXPECT_TRUE(std::isfinite(p.x()));

  // Home with the view focused: default angle, no pan, the clip's framing.
  view.setCamera(away);
  QTest::keyClick(&view, Qt::Key_Home);
  EXPECT_DOUBLE_EQ(view.camera().yaw, OrbitCamera::kDefaultYaw);
  EXPECT_DOUBLE_EQ(view.camera().pitch, OrbitCamera::kDefaultPitch);
  EXPECT_TRUE(view.camera().pan.isZero());
  EXPECT_NEAR(view.camera().distance, framed.distance, 1e-9 * framed.distance);
  EXPECT_LT((view.camera().target - framed.target).norm(), 1e-9 * view.extent());

  // Another motion of the same skeleton (a synthesized one) keeps the camera, but its bounds and
  // the selected joint's trail are its own.
  view.setCamera(away);
  view.setSelectedJoint(3);
  Clip other = testing::swing(1.0);
  const int root = other.skeleton.roots().front();
  for (int f = 0; f < other.motion.num_frames; ++f)
    other.motion.translation(f, root) += Eigen::Vector3d(10 * view.extent(), 0, 0);
  view.setMotion(other.motion);
  EXPECT_DOUBLE_EQ(view.camera().yaw, away.yaw);
  EXPECT_DOUBLE_EQ(view.camera().distance, away.distance);
  EXPECT_EQ(int(view.trail().size()), other.motion.num_frames);
  EXPECT_GT(view.bounds().boxMin.x(), 8 * view.extent());
}

TEST(StudioView3d, WindowKeysFrameAndPresetsAndHomeOnTheViewResetsTheCamera) {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1000, 600);
  w->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(w.get()));
  w->activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(w.get()));
  w->openClip(testing::swing());
  w->setFrame(150);
  SkeletonView* view = w->skeletonView();
  EXPECT_TRUE(view->bounds().valid) << "the window gives the view the whole clip";
  // The window's Home (the timeline's first frame) must not take Home from the focused view.

  OrbitCamera away = view->camera();
  away.yaw = 2.0;
  away.pitch = 1.0;
  away.distance *= 5;
  view->setCamera(away);
  QTest::keyClick(w.get(), Qt::Key_7, Qt::ControlModifier);
  EXPECT_NEAR(view->camera().pitch, M_PI / 2, 1e-12) << "Ctrl+7: top";
  QTest::keyClick(w.get(), Qt::Key_3, Qt::ControlModifier);
  EXPECT_NEAR(view->camera().yaw, M_PI / 2, 1e-12) << "Ctrl+3: side";
  EXPECT_DOUBLE_EQ(view->camera().pitch, 0.0);
  QTest::keyClick(w.get(), Qt::Key_1, Qt::ControlModifier);
  EXPECT_DOUBLE_EQ(view->camera().yaw, 0.0) << "Ctrl+1: front";
  const double far = view->camera().distance;
  QTest::keyClick(w.get(), Qt::Key_F);  // no click into the view needed
  EXPECT_LT(view->camera().distance, far / 2) << "F frames the character";
  for (const QPointF& p : view->jointPixels()) EXPECT_TRUE(view->rect().contains(p.toPoint()));

  // Home without the view focused is the window's (first frame); with it focused, the camera's.
  w->mapView()->setFocus();
  QTest::keyClick(w.get(), Qt::Key_Home);
  EXPECT_EQ(w->currentFrame(), 0);
  w->setFrame(150);
  view->setCamera(away);
  view->setFocus();
  ASSERT_TRUE(QTest::qWaitFor([&] { return view->hasFocus(); }, 2000));
  QTest::keyClick(view, Qt::Key_Home);
  EXPECT_EQ(w->currentFrame(), 150) << "the window's Home fired with the 3-D view focused";
  EXPECT_DOUBLE_EQ(view->camera().yaw, OrbitCamera::kDefaultYaw);
  EXPECT_DOUBLE_EQ(view->camera().pitch, OrbitCamera::kDefaultPitch);

  // The Camera submenu's entries have tooltips.
  for (const char* name :
       {"frameCharacter", "resetCamera", "cameraFront", "cameraSide", "cameraTop"}) {
    auto* action = w->findChild<QAction*>(name);
    ASSERT_NE(action, nullptr) << name;
    EXPECT_FALSE(action->toolTip().isEmpty()) << name;
  }
}

TEST(StudioView3d, CapsulesAreRoundAndClosed) {
  std::vector<MeshVertex> mesh;
  const Eigen::Vector3d a(1, 2, 3), b(4, 6, 3);
  const double r = 0.5;
  appendCapsule(mesh, a, b, r, {1, 0, 0});
  ASSERT_EQ(int(mesh.size()), capsuleVertexCount());
  EXPECT_EQ(capsuleVertexCount(), 6 * kCapsuleSegments * (1 + 2 * kCapsuleBands));
  EXPECT_GE(kCapsuleSegments, 16) << "enough segments to look round";
  for (const MeshVertex& v : mesh) {
    const Eigen::Vector3d p(v.position[0], v.position[1], v.position[2]);
    const Eigen::Vector3d n(v.normal[0], v.normal[1], v.normal[2]);
    EXPECT_NEAR(n.norm(), 1.0, 1e-5);
    // On the surface: r from the segment, the normal pointing away from it.
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const Eigen::Vector3d nearest = a + t * (b - a);
    EXPECT_NEAR((p - nearest).norm(), r, 1e-5);
    EXPECT_GT(n.dot(p - nearest), 0.99 * r);
  }
  // The caps reach r beyond each end along the axis.
  double beyond = 0.0;
  for (const MeshVertex& v : mesh) {
    const Eigen::Vector3d p(v.position[0], v.position[1], v.position[2]);
    beyond = std::max(beyond, (p - b).dot((b - a).normalized()));
  }
  EXPECT_NEAR(beyond, r, 1e-5);
  // A joint's sphere: the same count, every vertex r from its centre.
  std::vector<MeshVertex> sphere;
  appendCapsule(sphere, a, a, r, {0, 0, 1});
  ASSERT_EQ(int(sphere.size()), capsuleVertexCount());
  for (const MeshVertex& v : sphere)
    EXPECT_NEAR((Eigen::Vector3d(v.position[0], v.position[1], v.position[2]) - a).norm(), r, 1e-5);
}

void expectSides(const Skeleton& skeleton,
                 const std::vector<std::pair<std::string, JointSide>>& expected) {
  const std::vector<JointSide> sides = joint_sides(skeleton);
  for (const auto& [name, side] : expected) {
    const int j = skeleton.find(name);
    ASSERT_GE(j, 0) << name;
    EXPECT_EQ(int(sides[std::size_t(j)]), int(side)) << name;
  }
}

TEST(StudioView3d, JointColoursByBodySide) {
  using enum JointSide;
  if (exists(kSwing)) {
    expectSides(io::load_clip(kSwing).skeleton, {{"Hips", Center},
                                                 {"LHipJoint", Left},
                                                 {"LeftUpLeg", Left},
                                                 {"LeftToeBase", Left},
                                                 {"RHipJoint", Right},
                                                 {"RightFoot", Right},
                                                 {"LowerBack", Center},
                                                 {"Spine1", Center},
                                                 {"Head", Center},
                                                 {"LeftHandIndex1", Left},
                                                 {"LThumb", Left},
                                                 {"RThumb", Right},
                                                 {"RightShoulder", Right}});
  }
  if (exists(kBandai)) {
    expectSides(io::load_clip(kBandai).skeleton, {{"joint_Root", Center},
                                                  {"Hips", Center},
                                                  {"Chest", Center},
                                                  {"Head", Center},
                                                  {"Shoulder_L", Left},
                                                  {"Hand_L", Left},
                                                  {"Toes_L", Left},
                                                  {"UpperArm_R", Right},
                                                  {"Foot_R", Right}});
  }
  // ASF-style lower-case prefixes only count beside their mirror; a child takes its parent's.
  Skeleton asf;
  for (const char* name : {"root", "lowerback", "lfemur", "rfemur", "lhand", "rhand"})
    asf.joints.push_back({name, 0, Eigen::Vector3d(0, 1, 0), {}, {}});
  asf.joints.front().parent = -1;
  asf.joints.push_back({"thumb", 4, Eigen::Vector3d(0, 1, 0), {}, {}});
  asf.joints.push_back({"spine.L", 0, Eigen::Vector3d(0, 1, 0), {}, {}});
  expectSides(asf, {{"root", Center},
                    {"lowerback", Center},
                    {"lfemur", Left},
                    {"rfemur", Right},
                    {"lhand", Left},
                    {"thumb", Left},
                    {"spine.L", Left}});
  // Three distinct colours.
  EXPECT_NE(side_color(Left), side_color(Right));
  EXPECT_NE(side_color(Left), side_color(Center));
  EXPECT_NE(side_color(Right), side_color(Center));
}

TEST(StudioView3d, TrailHasEveryFrame) {
  const Clip clip = testing::swing();
  const int hand = clip.skeleton.find("RightHand") >= 0 ? clip.skeleton.find("RightHand") : 1;
  const auto trail = jointTrail(clip.skeleton, clip.motion, hand);
  ASSERT_EQ(int(trail.size()), clip.motion.num_frames);
  for (int f : {0, clip.motion.num_frames / 2, clip.motion.num_frames - 1}) {
    EXPECT_LT((trail[std::size_t(f)] -
               forward_kinematics(clip.skeleton, clip.motion, f).positions[std::size_t(hand)])
                  .norm(),
              1e-9);
  }
  const auto mesh = trailMesh(trail, 100.0);
  EXPECT_GT(mesh.size(), 0u);
  EXPECT_LE(int(mesh.size()), (clip.motion.num_frames - 1) * capsuleVertexCount(false));
}

/// A joint whose projection is at least `gap` pixels from every other drawn joint's.
int isolatedJoint(const SkeletonView& view, double gap) {
  const auto pixels = view.jointPixels();
  for (std::size_t j = 0; j < pixels.size(); ++j) {
    if (!view.body()[j]) continue;
    bool alone = true;
    for (std::size_t k = 0; k < pixels.size() && alone; ++k) {
      if (k != j && view.body()[k] &&
          std::hypot(pixels[j].x() - pixels[k].x(), pixels[j].y() - pixels[k].y()) < gap)
        alone = false;
    }
    if (alone && view.rect().contains(pixels[j].toPoint())) return int(j);
  }
  return -1;
}

void hover(QWidget* widget, QPointF at) {
  QMouseEvent move(QEvent::MouseMove, at, widget->mapToGlobal(at), Qt::NoButton, Qt::NoButton,
                   Qt::NoModifier);
  QApplication::sendEvent(widget, &move);
}

TEST(StudioView3d, HoverNamesTheJointUnderTheMouse) {
  const Clip clip = testing::swing();
  SkeletonView view;
  view.resize(640, 480);
  view.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
  view.setSkeleton(clip.skeleton);
  view.setMotion(clip.motion);
  view.setPose(clip.motion, 150);
  const int j = isolatedJoint(view, 30.0);
  ASSERT_GE(j, 0);
  const QPointF at = view.jointPixels()[std::size_t(j)];
  hover(&view, at + QPointF(6, -5));  // within 12 px
  EXPECT_EQ(view.hoveredJoint(), j);
  // The name is written beside it: dark text pixels appear in the rendering there.
  const QImage image = view.grab().toImage();
  int dark = 0;
  for (int y = int(at.y()) - 30; y < int(at.y()); ++y) {
    for (int x = int(at.x()) + 10; x < int(at.x()) + 80; ++x) {
      if (image.rect().contains(x, y) && qGray(image.pixel(x, y)) < 60) ++dark;
    }
  }
  EXPECT_GT(dark, 10) << "no label drawn beside " << clip.skeleton.joints[std::size_t(j)].name;
  hover(&view, at + QPointF(20, 20));  // beyond 12 px of it and of every other joint
  EXPECT_EQ(view.hoveredJoint(), -1);
}

int countNear(const QImage& image, QPointF at, int radius, const std::function<bool(QColor)>& is) {
  int n = 0;
  for (int y = int(at.y()) - radius; y <= int(at.y()) + radius; ++y) {
    for (int x = int(at.x()) - radius; x <= int(at.x()) + radius; ++x) {
      if (image.rect().contains(x, y) && is(image.pixelColor(x, y))) ++n;
    }
  }
  return n;
}

TEST(StudioView3d, JointsPanelSelectsAndTheViewHighlightsAndDrawsTheTrail) {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1000, 600);
  w->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(w.get()));
  const Clip clip = testing::swing();
  w->openClip(clip);
  w->setFrame(150);
  auto* panel = w->findChild<JointPanel*>();
  ASSERT_NE(panel, nullptr);
  EXPECT_FALSE(panel->isVisible());
  // View → Joints panel shows it.
  QAction* toggle = panel->toggleViewAction();
  EXPECT_EQ(toggle->text(), QMainWindow::tr("&Joints panel"));
  toggle->trigger();
  EXPECT_TRUE(panel->isVisible());
  // The hierarchy: every joint, children under their parents.
  QTreeWidget* tree = panel->tree();
  EXPECT_EQ(tree->topLevelItemCount(), int(clip.skeleton.roots().size()));
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    QTreeWidgetItem* item = panel->item(j);
    ASSERT_NE(item, nullptr);
    EXPECT_EQ(item->text(0).toStdString(), clip.skeleton.joints[std::size_t(j)].name);
    const int parent = clip.skeleton.joints[std::size_t(j)].parent;
    EXPECT_EQ(item->parent(), parent >= 0 ? panel->item(parent) : nullptr);
  }
  SkeletonView* view = w->skeletonView();
  QApplication::processEvents();
  const QImage before = view->grab().toImage();
  const int j = isolatedJoint(*view, 20.0);
  ASSERT_GE(j, 0);
  tree->setCurrentItem(panel->item(j));
  EXPECT_EQ(view->selectedJoint(), j);
  EXPECT_EQ(int(view->trail().size()), clip.motion.num_frames);
  const QImage after = view->grab().toImage();
  if (!qEnvironmentVariableIsEmpty("MOTIONMAP_TEST_PNG_DIR")) {  // to look at by hand
    const QString dir = qEnvironmentVariable("MOTIONMAP_TEST_PNG_DIR");
    after.save(dir + "/view3d-selected-fallback.png");
    w->grab().save(dir + "/view3d-window-joints-panel.png");
  }
  const QPointF at = view->jointPixels()[std::size_t(j)];
  const auto orange = [](QColor c) {
    return c.red() > 200 && c.green() > 90 && c.green() < 190 && c.blue() < 90;
  };
  EXPECT_EQ(countNear(before, at, 6, orange), 0);
  EXPECT_GT(countNear(after, at, 6, orange), 10) << "the selected joint is highlighted";
  // The trail: its points are drawn (red early, blue late) along its projection.
  int drawn = 0, checked = 0;
  for (std::size_t f = 0; f < view->trail().size(); f += 10) {
    const QPointF p = projectToPixels(view->camera(), view->size(), view->trail()[f]);
    if (!view->rect().contains(p.toPoint())) continue;
    ++checked;
    drawn += countNear(after, p, 1, [](QColor c) {
               return std::abs(c.red() - c.blue()) > 60 && c.green() < 90;
             }) > 0;
  }
  EXPECT_GT(checked, 5);
  EXPECT_GE(drawn, checked * 6 / 10);
  // Clicking another joint in the view selects it in the panel.
  const int other = j == 0 ? 1 : 0;
  const QPointF q = view->jointPixels()[std::size_t(other)];
  if (view->jointAt(q) == other) {
    QTest::mouseClick(view, Qt::LeftButton, Qt::NoModifier, q.toPoint());
    EXPECT_EQ(view->selectedJoint(), other);
    EXPECT_EQ(tree->currentItem(), panel->item(other));
  }
}

TEST(StudioView3d, FallbackDrawingHasSideColoursAndAGroundShadow) {
  const Clip clip = testing::swing();
  SkeletonView view;
  view.resize(640, 480);
  view.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
  view.setSkeleton(clip.skeleton);
  view.setMotion(clip.motion);
  view.setPose(clip.motion, 0);
  const QImage image = view.grab().toImage();
  if (!qEnvironmentVariableIsEmpty("MOTIONMAP_TEST_PNG_DIR"))
    image.save(qEnvironmentVariable("MOTIONMAP_TEST_PNG_DIR") + "/view3d-fallback.png");
  int blue = 0, red = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const QColor c = image.pixelColor(x, y);
      blue += c.blue() > c.red() + 60;
      red += c.red() > c.blue() + 60 && c.red() > c.green() + 40;
    }
  }
  EXPECT_GT(blue, 200) << "left side";
  EXPECT_GT(red, 200) << "right side";
  // Under the hips on the floor, the shadow darkens the background.
  const Eigen::Vector3d hips = view.worldPose().positions[0];
  const QPointF floor = projectToPixels(view.camera(), view.size(), {hips.x(), 0.0, hips.z()});
  const QPointF aside =
      projectToPixels(view.camera(), view.size(), {hips.x() + 0.6 * view.extent(), 0.0, hips.z()});
  EXPECT_LT(qGray(image.pixel(floor.toPoint())) + 10, qGray(image.pixel(aside.toPoint())));
}

}  // namespace
}  // namespace motionmap::studio
