// The 3-D view drawn by real OpenGL 3.3 core (Mesa's llvmpipe under Xvfb): a known pose is
// rendered, the framebuffer read back, and the skeleton's pixels compared with where the camera
// projects its joints and bones: every joint and every bone is drawn, and nothing of the skeleton
// is drawn anywhere else. The renderings are saved as test artefacts in the build directory.
//
// Run by ctest as `studio_gl_render` through `xvfb-run -a` with QT_QPA_PLATFORM=xcb (registered
// only where xvfb-run exists, see tests/CMakeLists.txt); by hand:
//   QT_QPA_PLATFORM=xcb xvfb-run -a -s "-screen 0 1280x1024x24" build/tests/motionmap_gui_gl_tests
// A platform without OpenGL fails the test (it is only registered where it can run).
#include <gtest/gtest.h>

#include <QApplication>
#include <QFileInfo>
#include <QMouseEvent>
#include <QPainter>
#include <QProcess>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <cmath>

#include "app/main_window.h"
#include "export/animation_export.h"
#include "export/picture_export.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "scene/scene.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {
namespace {

constexpr int kTimeoutMs = 60000;

/// The skeleton's colours are saturated (bones tan, joints blue); background and grid are gray.
bool isSkeletonPixel(QRgb c) {
  const int hi = std::max({qRed(c), qGreen(c), qBlue(c)}),
            lo = std::min({qRed(c), qGreen(c), qBlue(c)});
  return hi - lo > 14;
}

/// Skeleton colour somewhere in the 3×3 block around p (antialiased edges, rounding).
bool skeletonNear(const QImage& image, QPointF p) {
  const QPoint q = p.toPoint();
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const QPoint r = q + QPoint(dx, dy);
      if (image.rect().contains(r) && isSkeletonPixel(image.pixel(r))) return true;
    }
  }
  return false;
}

double distanceToSegment(QPointF p, QPointF a, QPointF b) {
  const QPointF ab = b - a;
  const double len2 = QPointF::dotProduct(ab, ab);
  const double t = len2 > 0 ? std::clamp(QPointF::dotProduct(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const QPointF d = p - (a + t * ab);
  return std::hypot(d.x(), d.y());
}

QString artefact(const QString& name) {
  return QString(MOTIONMAP_TEST_ARTIFACT_DIR) + "/" + name;
}

struct RenderCheck {
  int joints = 0, jointsDrawn = 0;
  int bonePoints = 0, bonePointsDrawn = 0;
  int skeletonPixels = 0, strayPixels = 0;
  QPoint firstStray{-1, -1};
};

/// Compares `image` (the view's framebuffer) with the view's camera projection of its pose.
RenderCheck check(const SkeletonView& view, const QImage& image) {
  RenderCheck out;
  const QSize size = view.size();
  const OrbitCamera& camera = view.camera();
  const WorldPose& pose = view.worldPose();
  // Projected bones, each with how far (pixels) its box and joint cubes may reach from its axis.
  const double radius = 0.012 * view.extent();  // scene.h: skeletonMesh
  const Eigen::Vector3d right =
      (camera.target + camera.pan - camera.eye()).cross(Eigen::Vector3d::UnitY()).normalized();
  auto pixelRadius = [&](const Eigen::Vector3d& p) {
    const QPointF a = projectToPixels(camera, size, p),
                  b = projectToPixels(camera, size, p + right * radius);
    return std::hypot(a.x() - b.x(), a.y() - b.y());
  };
  struct Segment {
    QPointF a, b;
    double reach;
  };
  std::vector<Segment> segments;
  for (const BoneSegment& bone : bone_segments(view.skeleton(), pose)) {
    // Box corners: √2 radii off the axis; joint cubes: 1.25·√3 ≈ 2.2 radii off the joint.
    const double reach = 2.3 * std::max(pixelRadius(bone.from), pixelRadius(bone.to)) + 2.0;
    segments.push_back(
        {projectToPixels(camera, size, bone.from), projectToPixels(camera, size, bone.to), reach});
    for (double t : {0.25, 0.5, 0.75}) {
      const QPointF p = projectToPixels(camera, size, bone.from + t * (bone.to - bone.from));
      if (!image.rect().contains(p.toPoint())) continue;
      ++out.bonePoints;
      if (skeletonNear(image, p)) ++out.bonePointsDrawn;
    }
  }
  for (const Eigen::Vector3d& p : pose.positions) {
    const QPointF q = projectToPixels(camera, size, p);
    segments.push_back({q, q, 2.3 * pixelRadius(p) + 2.0});
    if (!image.rect().contains(q.toPoint())) continue;
    ++out.joints;
    if (skeletonNear(image, q)) ++out.jointsDrawn;
  }
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      if (!isSkeletonPixel(image.pixel(x, y))) continue;
      ++out.skeletonPixels;
      const QPointF p(x + 0.5, y + 0.5);
      const bool explained = std::any_of(segments.begin(), segments.end(), [&](const Segment& s) {
        return distanceToSegment(p, s.a, s.b) <= s.reach;
      });
      if (!explained) {
        if (out.strayPixels++ == 0) out.firstStray = QPoint(x, y);
      }
    }
  }
  return out;
}

/// The image with every projected joint ringed in red and every bone's axis in black.
QImage annotated(const SkeletonView& view, QImage image) {
  QPainter painter(&image);
  painter.setRenderHint(QPainter::Antialiasing);
  painter.setPen(QPen(Qt::black, 1));
  for (const BoneSegment& bone : bone_segments(view.skeleton(), view.worldPose())) {
    painter.drawLine(projectToPixels(view.camera(), view.size(), bone.from),
                     projectToPixels(view.camera(), view.size(), bone.to));
  }
  painter.setPen(QPen(Qt::red, 1.5));
  for (const QPointF& p : view.jointPixels()) painter.drawEllipse(p, 5, 5);
  return image;
}

void orbit(SkeletonView& view, QPoint from, QPoint to) {
  QMouseEvent press(QEvent::MouseButtonPress, QPointF(from), view.mapToGlobal(QPointF(from)),
                    Qt::LeftButton, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&view, &press);
  QMouseEvent move(QEvent::MouseMove, QPointF(to), view.mapToGlobal(QPointF(to)), Qt::NoButton,
                   Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&view, &move);
}

TEST(StudioGl, DrawsAKnownPoseExactlyWhereTheCameraProjectsIt) {
  ASSERT_EQ(QGuiApplication::platformName(), "xcb")
      << "run under a display (xvfb-run) with QT_QPA_PLATFORM=xcb";
  const Clip clip =
      sample::make_sample_clip(sample::SampleKind::Swing);  // frame 150: top of the backswing
  SkeletonView view;
  view.resize(640, 480);
  view.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
  view.setSkeleton(clip.skeleton);
  view.setPose(clip.motion, 150);
  ASSERT_TRUE(QTest::qWaitFor([&] { return view.glReady(); }, kTimeoutMs))
      << "no OpenGL context: is Mesa installed (libgl1-mesa-dri, libglx-mesa0)?";
  const QString gl = view.glDescription();
  std::printf("3-D view: %s\n", qPrintable(gl));
  // 3.3 core asked for; Mesa answers with its newest compatible core version.
  const QStringList version = gl.section(' ', 1, 1).split('.');
  ASSERT_EQ(version.size(), 2) << gl.toStdString();
  EXPECT_GE(version[0].toInt() * 10 + version[1].toInt(), 33) << gl.toStdString();
  EXPECT_EQ(gl.section(' ', 2, 2), "core") << gl.toStdString();

  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1)
      orbit(view, QPoint(300, 240), QPoint(440, 200));  // 1.4 rad round, a little lower
    QTest::qWait(20);
    const QImage image = view.renderImage().convertToFormat(QImage::Format_RGB32);
    ASSERT_EQ(image.size(), view.size() * view.devicePixelRatio());
    ASSERT_EQ(view.devicePixelRatio(), 1.0);
    const QString name = QString("studio-gl-render-%1").arg(pass);
    ASSERT_TRUE(image.save(artefact(name + ".png")));
    ASSERT_TRUE(annotated(view, image).save(artefact(name + "-annotated.png")));
    std::printf("saved %s.png and %s-annotated.png in %s\n", qPrintable(name), qPrintable(name),
                MOTIONMAP_TEST_ARTIFACT_DIR);
    // The background is the view's clear colour (0.93, 0.94, 0.96).
    const QColor corner = image.pixelColor(1, 1);
    EXPECT_NEAR(corner.redF(), 0.93, 0.01);
    EXPECT_NEAR(corner.blueF(), 0.96, 0.01);
    const RenderCheck c = check(view, image);
    std::printf(
        "pass %d: %d/%d joints and %d/%d bone points drawn; %d skeleton pixels, %d outside the "
        "projected "
        "bones\n",
        pass, c.jointsDrawn, c.joints, c.bonePointsDrawn, c.bonePoints, c.skeletonPixels,
        c.strayPixels);
    EXPECT_EQ(c.joints, clip.skeleton.num_joints());  // the whole body is in view
    EXPECT_EQ(c.jointsDrawn, c.joints);
    EXPECT_GT(c.bonePoints, 3 * 20);
    EXPECT_EQ(c.bonePointsDrawn, c.bonePoints);
    EXPECT_GT(c.skeletonPixels, 1500);
    EXPECT_EQ(c.strayPixels, 0) << "first at (" << c.firstStray.x() << ", " << c.firstStray.y()
                                << ")";
  }
}

/// Renders `clip` at `frame` through OpenGL as Studio shows it (the whole motion given, so the
/// clip is framed and detached joints get no bone) with `selected`'s trail, saves `name`.png, and
/// checks: every drawn joint is drawn, the selected joint is orange, the trail is drawn, the floor
/// under the body is darkened by the shadow (gray, not coloured), and where a bone from a static
/// root to a detached joint would run nothing is drawn.
void renderClip(const Clip& clip, int frame, const std::string& selectedName, const QString& name) {
  SkeletonView view;
  view.resize(640, 480);
  view.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
  view.setSkeleton(clip.skeleton);
  view.setMotion(clip.motion);
  view.setPose(clip.motion, frame);
  const int selected = clip.skeleton.find(selectedName);
  ASSERT_GE(selected, 0) << selectedName;
  view.setSelectedJoint(selected);
  ASSERT_TRUE(QTest::qWaitFor([&] { return view.glReady(); }, kTimeoutMs));
  QTest::qWait(20);
  const QImage image = view.renderImage().convertToFormat(QImage::Format_RGB32);
  ASSERT_TRUE(image.save(artefact(name + ".png")));
  std::printf("saved %s.png in %s\n", qPrintable(name), MOTIONMAP_TEST_ARTIFACT_DIR);
  const OrbitCamera& camera = view.camera();
  const WorldPose& pose = view.worldPose();
  int joints = 0, drawn = 0;
  for (std::size_t j = 0; j < pose.positions.size(); ++j) {
    if (!view.body()[j]) continue;
    const QPointF q = projectToPixels(camera, view.size(), pose.positions[j]);
    ASSERT_TRUE(image.rect().contains(q.toPoint())) << clip.skeleton.joints[j].name;
    ++joints;
    drawn += skeletonNear(image, q);
  }
  EXPECT_EQ(drawn, joints);
  const QColor mark = image.pixelColor(
      projectToPixels(camera, view.size(), pose.positions[std::size_t(selected)]).toPoint());
  EXPECT_GT(mark.red(), 150) << "selected joint not orange";
  EXPECT_LT(mark.blue(), 90) << "selected joint not orange";
  int trailPoints = 0, trailDrawn = 0;
  for (std::size_t f = 0; f < view.trail().size(); f += 5) {
    const QPointF p = projectToPixels(camera, view.size(), view.trail()[f]);
    if (!image.rect().contains(p.toPoint())) continue;
    ++trailPoints;
    trailDrawn += skeletonNear(image, p);
  }
  EXPECT_GT(trailPoints, 10);
  EXPECT_GE(trailDrawn, trailPoints * 8 / 10);
  // The shadow: under the feet (the lowest end of the body), the floor is darker than the
  // background (0.93, 0.94, 0.96) yet gray.
  Eigen::Vector3d low = pose.positions[std::size_t(motion_root(clip.skeleton, clip.motion))];
  for (const auto& p : pose.positions) {
    if (p.y() < low.y()) low = p;
  }
  const QPointF under = projectToPixels(camera, view.size(), {low.x(), 0.0, low.z()});
  int shadowed = 0;
  for (int dy = -6; dy <= 6; dy += 3) {
    for (int dx = -6; dx <= 6; dx += 3) {
      const QColor c = image.pixelColor((under + QPointF(dx, dy)).toPoint());
      shadowed += !isSkeletonPixel(c.rgb()) && c.redF() < 0.85;
    }
  }
  EXPECT_GT(shadowed, 3) << "no shadow under the body";
  // No bone to a detached joint: along where it would run, nothing of the skeleton is drawn away
  // from the bones that are.
  const std::vector<BoneSegment> bones = view.bones();
  const double reach = 3.0 * boneRadius(view.extent()) * view.height() / camera.distance + 6.0;
  int checked = 0, stray = 0;
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    if (!view.detached()[std::size_t(j)]) continue;
    const int parent = clip.skeleton.joints[std::size_t(j)].parent;
    for (double t = 0.05; t < 0.95; t += 0.01) {
      const Eigen::Vector3d p =
          pose.positions[std::size_t(parent)] +
          t * (pose.positions[std::size_t(j)] - pose.positions[std::size_t(parent)]);
      const QPointF q = projectToPixels(camera, view.size(), p);
      if (!image.rect().contains(q.toPoint())) continue;
      const bool nearBone = std::any_of(bones.begin(), bones.end(), [&](const BoneSegment& b) {
        return distanceToSegment(q, projectToPixels(camera, view.size(), b.from),
                                 projectToPixels(camera, view.size(), b.to)) < reach;
      });
      const bool nearTrail =
          std::any_of(view.trail().begin(), view.trail().end(), [&](const auto& w) {
            const QPointF r = projectToPixels(camera, view.size(), w);
            return std::hypot(r.x() - q.x(), r.y() - q.y()) < 6.0;
          });
      if (nearBone || nearTrail) continue;
      ++checked;
      stray += skeletonNear(image, q);
    }
  }
  EXPECT_EQ(stray, 0) << "a bone is drawn to a joint that moves by itself (" << checked
                      << " points checked)";
}

TEST(StudioGl, BandaiWalkAndSwingWithShadowCapsulesAndATrail) {
  const std::string data = MOTIONMAP_SHARED_DATA;
  const std::string walk = data + "/other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh";
  const std::string swing = data + "/cmu/64_08.bvh";
  if (QFileInfo::exists(QString::fromStdString(swing))) {
    renderClip(io::load_clip(swing), 190, "RightHand", "studio-gl-swing-trail");
  } else {
    renderClip(sample::make_sample_clip(sample::SampleKind::Swing), 150, "RightHand",
               "studio-gl-swing-trail");
  }
  if (!QFileInfo::exists(QString::fromStdString(walk)))
    GTEST_SKIP() << "SKIPPED: " << walk << " not found";
  const Clip clip = io::load_clip(walk);
  renderClip(clip, 100, "Foot_L", "studio-gl-bandai-walk");
  // Not following the root: the whole walk framed, the static root at the origin in view.
  {
    SkeletonView view;
    view.resize(640, 480);
    view.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
    view.setSkeleton(clip.skeleton);
    view.setFollowRoot(false);
    view.setMotion(clip.motion);
    view.setPose(clip.motion, 100);
    view.setSelectedJoint(clip.skeleton.find("Hips"));
    ASSERT_TRUE(QTest::qWaitFor([&] { return view.glReady(); }, kTimeoutMs));
    QTest::qWait(20);
    ASSERT_TRUE(view.renderImage().save(artefact("studio-gl-bandai-walk-fixed.png")));
  }
}

// Compare, overlaid: a second character drawn by OpenGL in the same view, translucent in the
// comparison colour (its depth first, then its colour once), over the first and the grid.
TEST(StudioGl, AnOverlaidCharacterIsTranslucentInItsColour) {
  const Clip clip = sample::make_sample_clip(sample::SampleKind::Swing);
  SkeletonView view;
  view.resize(640, 480);
  view.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
  view.setSkeleton(clip.skeleton);
  view.setMotion(clip.motion);
  view.setPose(clip.motion, 0);
  ASSERT_TRUE(QTest::qWaitFor([&] { return view.glReady(); }, kTimeoutMs));
  const auto teal = [](const QImage& image) {
    int n = 0;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) {
        const QColor c = image.pixelColor(x, y);
        n += c.green() > c.red() + 40 && c.blue() > c.red() + 40 &&
             std::abs(c.green() - c.blue()) < 50;
      }
    return n;
  };
  QTest::qWait(20);
  const QImage alone = view.renderImage().convertToFormat(QImage::Format_RGB32);
  EXPECT_LT(teal(alone), 20);
  // The same pose a little to the side.
  WorldPose moved = forward_kinematics(clip.skeleton, clip.motion, 0);
  for (Eigen::Vector3d& p : moved.positions) p.x() += 0.3 * view.extent();
  view.setOverlay(clip.skeleton, moved, {}, MapView::comparisonColor());
  QTest::qWait(20);
  const QImage both = view.renderImage().convertToFormat(QImage::Format_RGB32);
  ASSERT_TRUE(both.save(artefact("studio-gl-overlay.png")));
  EXPECT_GT(teal(both), 300);
  // Translucent: no pixel is the comparison colour itself at full strength over the background.
  const std::vector<QPointF> pixels = view.overlayJointPixels();
  int seen = 0;
  for (const QPointF& p : pixels) {
    if (!both.rect().contains(p.toPoint())) continue;
    const QColor c = both.pixelColor(p.toPoint());
    ++seen;
    EXPECT_GT(c.red(), 30) << "an opaque teal joint at " << p.x() << "," << p.y();
  }
  EXPECT_GT(seen, 5);
  view.clearOverlay();
  QTest::qWait(20);
  EXPECT_LT(teal(view.renderImage().convertToFormat(QImage::Format_RGB32)), 20);
}

TEST(StudioGl, WindowScreenshotHasTheGlViewAndTheMap) {
  MainWindow w;
  w.setInteractive(false);
  w.resize(1280, 720);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  w.setMethod(embed::Method::Isomap);
  w.openClip(sample::make_sample_clip(sample::SampleKind::Swing));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w.currentMap() != nullptr || !w.isComputing(); }, kTimeoutMs));
  ASSERT_NE(w.currentMap(), nullptr) << w.lastError().toStdString();
  w.setFrame(150);
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.skeletonView()->glReady(); }, kTimeoutMs));
  QTest::qWait(50);
  const QImage shot = w.screenshot().convertToFormat(QImage::Format_RGB32);
  ASSERT_TRUE(shot.save(artefact("studio-gl-window.png")));
  std::printf("saved studio-gl-window.png in %s\n", MOTIONMAP_TEST_ARTIFACT_DIR);
  // Skeleton colours inside the 3-D view's rectangle of the screenshot, map colours in the map's.
  auto count = [&](QWidget* widget) {
    const QRect r(widget->mapTo(&w, QPoint(0, 0)), widget->size());
    int n = 0;
    for (int y = r.top(); y <= r.bottom(); ++y) {
      for (int x = r.left(); x <= r.right(); ++x) n += isSkeletonPixel(shot.pixel(x, y));
    }
    return n;
  };
  EXPECT_GT(count(w.skeletonView()), 1500);
  EXPECT_GT(count(w.mapView()), 1500);  // the coloured trajectory
}

// File → Export picture and Export animation with the OpenGL view: its framebuffer, not a blank
// GL child, in the pictures and in every frame of an animation.
TEST(StudioGl, ExportedPicturesAndAnimationFramesHaveTheGlView) {
  MainWindow w;
  w.setInteractive(false);
  w.resize(1000, 560);
  w.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&w));
  w.setMethod(embed::Method::Isomap);
  sample::SampleOptions half;
  half.seconds = 0.5;
  w.openClip(sample::make_sample_clip(sample::SampleKind::Swing, half));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w.currentMap() != nullptr || !w.isComputing(); }, kTimeoutMs));
  ASSERT_NE(w.currentMap(), nullptr) << w.lastError().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.skeletonView()->glReady(); }, kTimeoutMs));
  w.setFrame(40);
  const QString view3d = artefact("studio-gl-export-3d.png"),
                both = artefact("studio-gl-export-both.png");
  ASSERT_TRUE(w.exportPicture(view3d, PictureKind::View3D)) << w.lastError().toStdString();
  ASSERT_TRUE(w.exportPicture(both, PictureKind::Both)) << w.lastError().toStdString();
  std::printf("saved studio-gl-export-3d.png and studio-gl-export-both.png in %s\n",
              MOTIONMAP_TEST_ARTIFACT_DIR);
  const QImage picture = QImage(view3d).convertToFormat(QImage::Format_RGB32);
  const QImage sideBySide = QImage(both).convertToFormat(QImage::Format_RGB32);
  const QSize viewSize = w.skeletonView()->size(), mapSize = w.mapView()->size();
  ASSERT_EQ(picture.size(), viewSize);
  EXPECT_EQ(sideBySide.size(), QSize(viewSize.width() + mapSize.width(),
                                     std::max(viewSize.height(), mapSize.height())));
  auto skeletonPixels = [](const QImage& image, QRect r) {
    int n = 0;
    for (int y = r.top(); y <= r.bottom(); ++y) {
      for (int x = r.left(); x <= r.right(); ++x) n += isSkeletonPixel(image.pixel(x, y));
    }
    return n;
  };
  EXPECT_GT(skeletonPixels(picture, picture.rect()), 1500);
  EXPECT_NEAR(picture.pixelColor(1, 1).redF(), 0.93, 0.01);  // the GL clear colour, not black
  EXPECT_EQ(sideBySide.copy(QRect(QPoint(0, 0), viewSize)), picture);

  // Three frames as an image sequence (and as MP4 when ffmpeg is there): the GL view in each,
  // the pose moving from one to the next.
  QTemporaryDir dir;
  AnimationSettings settings;
  settings.folder = dir.path();
  settings.name = "gl";
  settings.first = 10;
  settings.last = 50;
  settings.video = !ffmpegProgram().isEmpty();
  ASSERT_TRUE(w.exportAnimation(settings)) << w.lastError().toStdString();
  const QRect left(QPoint(0, 0), viewSize);
  const QImage first = QImage(dir.filePath("gl_0000.png")).convertToFormat(QImage::Format_RGB32);
  const QImage last = QImage(dir.filePath("gl_0040.png")).convertToFormat(QImage::Format_RGB32);
  ASSERT_FALSE(first.isNull());
  ASSERT_FALSE(last.isNull());
  EXPECT_FALSE(QFileInfo::exists(dir.filePath("gl_0041.png")));
  EXPECT_GT(skeletonPixels(first, left), 1500);
  EXPECT_GT(skeletonPixels(last, left), 1500);
  EXPECT_NE(first.copy(left), last.copy(left));
  if (settings.video) {
    EXPECT_GT(QFileInfo(dir.filePath("gl.mp4")).size(), 1000);
  }
  EXPECT_EQ(w.currentFrame(), 40);  // the frame shown before is back
}

// The picture in docs/studio.png: the screenshot mode on the golf swing, under this display.
TEST(StudioGl, ScreenshotModeOnTheGolfSwing) {
  const QString clip = QString(MOTIONMAP_SHARED_DATA) + "/cmu/64_08.bvh";
  if (!QFileInfo::exists(clip)) GTEST_SKIP() << "SKIPPED: " << clip.toStdString() << " not found";
  const QString png = artefact("studio-64_08.png");
  QProcess studio;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert("XDG_CONFIG_HOME",
             QString(MOTIONMAP_TEST_ARTIFACT_DIR) + "/studio-gl-config");  // no user settings
  studio.setProcessEnvironment(env);
  studio.start(MOTIONMAP_STUDIO_EXE,
               {clip, "--method", "isomap", "--frame", "190", "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  ASSERT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
  const QImage image = QImage(png).convertToFormat(QImage::Format_RGB32);
  ASSERT_EQ(image.size(), QSize(1280, 720));
  // Shaded bones (saturated colours) in the left half, where the 3-D view is.
  int skeleton = 0;
  for (int y = 30; y < 650; ++y) {
    for (int x = 0; x < 620; ++x) skeleton += isSkeletonPixel(image.pixel(x, y));
  }
  EXPECT_GT(skeleton, 1500);
  std::printf("saved studio-64_08.png in %s (copy it to docs/studio.png)\n",
              MOTIONMAP_TEST_ARTIFACT_DIR);
}

}  // namespace
}  // namespace motionmap::studio

int main(int argc, char** argv) {
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "xcb");
  qputenv("MOTIONMAP_STUDIO_NO_CONFIRM", "1");
  motionmap::studio::SkeletonView::installSurfaceFormat();
  QStandardPaths::setTestModeEnabled(true);
  QApplication app(argc, argv);
  QApplication::setOrganizationName("MotionMapTests");
  QApplication::setApplicationName("MotionMap Studio GL Tests");
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
