#pragma once
// The 3-D view: a shaded skeleton (a box per bone, a cube per joint) over a ground grid. Left
// drag orbits, middle or right drag pans, the wheel zooms; the camera follows the motion root
// (unless setFollowRoot(false)).
// Drawn by an OpenGL 3.3 core child widget when the platform gives a context, else (offscreen
// tests, no GL) by QPainter from the same scene data. The pose shown is kept on the CPU
// (currentPose(), jointPixels()) so it is testable without a GL context.
#include <vector>

#include <QImage>
#include <QWidget>

#include "motionmap/skeleton/forward_kinematics.h"
#include "scene.h"

namespace motionmap::studio {

class SkeletonCanvas;

class SkeletonView : public QWidget {
  Q_OBJECT
 public:
  explicit SkeletonView(QWidget* parent = nullptr);
  /// Asks for OpenGL 3.3 core (24-bit depth, 4× multisampling) as every context's default
  /// format; call it before the QApplication is created.
  static void installSurfaceFormat();
  ~SkeletonView() override;

  /// Shows `skeleton` (copied); resets the camera to frame its rest pose unless `keepCamera`
  /// (another clip of the same body). Clears the pose.
  void setSkeleton(const Skeleton& skeleton, bool keepCamera = false);
  /// Shows frame `frame` of `motion` (a motion of the current skeleton).
  void setPose(const Motion& motion, int frame);
  /// The local pose shown, as a one-frame Motion (empty before setPose).
  const Motion& currentPose() const { return m_pose; }
  const Skeleton& skeleton() const { return m_skeleton; }
  const WorldPose& worldPose() const { return m_world; }
  const OrbitCamera& camera() const { return m_camera; }
  double extent() const { return m_extent; }
  /// Whether the camera follows the motion root (on by default); off, it stays where it is.
  void setFollowRoot(bool follow);
  bool followRoot() const { return m_followRoot; }
  /// Pixel positions of the joints shown, as the camera projects them in this widget.
  std::vector<QPointF> jointPixels() const;
  /// True when an OpenGL context draws the view (false on platforms without GL, e.g. offscreen).
  bool glReady() const;
  /// "OpenGL 3.3 core · <renderer> · <version string>" once the GL view has initialized, else
  /// empty.
  QString glDescription() const;
  /// The view as an image (the GL framebuffer, or the QPainter fallback).
  QImage renderImage();

 signals:
  void poseChanged();

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  void refresh();

  Skeleton m_skeleton;
  Motion m_pose;
  WorldPose m_world;
  double m_extent = 1.0;
  OrbitCamera m_camera;
  bool m_followRoot = true;
  bool m_hasTarget = false;  ///< the camera has looked at a pose since setSkeleton
  QPoint m_lastMouse;
  SkeletonCanvas* m_canvas = nullptr;  ///< the GL child, null without OpenGL
};

}  // namespace motionmap::studio
