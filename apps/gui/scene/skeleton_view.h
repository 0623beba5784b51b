#pragma once
// The 3-D view: a shaded skeleton (a capsule per bone, a sphere per joint, coloured by body side)
// with a soft ground shadow over a ground grid. Left drag orbits, middle or right drag pans, the
// wheel zooms; the camera follows the motion root (unless setFollowRoot(false)). Given the whole
// motion (setMotion) it frames the clip's bounding volume, draws no bone to a joint that moves by
// its own translation channels, and draws the selected joint's trail. Hovering names the joint
// under the mouse; a click on a joint selects it; Home (with the view focused) resets the camera.
// With joint dragging enabled (setJointDragEnabled: a map to pose from), a left drag that starts
// on a joint drags it instead of orbiting: the view reports where in space the mouse puts it
// (jointDragged; a JointDrag controller poses the body), and Shift-click pins or unpins a joint.
// A second character can be drawn with the first (setOverlay: Compare, overlaid): one colour,
// translucent, over the scene, in the same shadow; it is not picked, hovered or followed.
// Drawn by an OpenGL 3.3 core child widget when the platform gives a context, else (offscreen
// tests, no GL) by QPainter from the same scene data. The pose shown is kept on the CPU
// (currentPose(), jointPixels()) so it is testable without a GL context.
#include <memory>
#include <optional>
#include <vector>

#include <QColor>
#include <QImage>
#include <QWidget>

#include "motionmap/skeleton/forward_kinematics.h"
#include "scene/scene.h"

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
  /// (another clip of the same body). Clears the pose, the motion and the selected joint.
  void setSkeleton(const Skeleton& skeleton, bool keepCamera = false);
  /// The whole motion that will play (of the current skeleton; copied): which joints are
  /// detached (detached_joints), the clip's bounds, the selected joint's trail. The first call
  /// after setSkeleton without keepCamera frames the clip (frameClip); later ones (another clip,
  /// a synthesized motion) keep the camera.
  void setMotion(const Motion& motion);
  /// Default yaw and pitch, no pan, and the clip's bounding volume framed (Home on the view).
  void resetCamera();
  /// Frames the clip's bounding volume (all frames, all drawn joints and end sites) at the current
  /// yaw and pitch: following the root, the volume around the root's floor point that the body
  /// ever reaches, else the whole box the clip covers. Every joint of every frame then projects
  /// inside the view, whatever the yaw and pitch. Without a motion, the current pose.
  void frameClip();
  /// Frames the current pose tightly (F): its body centred, its bounding sphere filling the view.
  void frameCharacter();
  /// Front, side or top view (yaw and pitch; look-at point and distance stay).
  void applyCameraPreset(CameraPreset preset);
  /// Camera state, for tests.
  void setCamera(const OrbitCamera& camera);
  /// Joints detached from their parent (no bone drawn to them) and joints drawn (body_joints).
  const std::vector<bool>& detached() const { return m_detached; }
  const std::vector<bool>& body() const { return m_body; }
  const std::vector<JointSide>& sides() const { return m_sides; }
  const MotionBounds& bounds() const { return m_bounds; }
  /// The bones drawn for the current pose.
  std::vector<BoneSegment> bones() const;

  /// The drawn joint nearest to `pixel` within `maxDistance` pixels, or −1.
  int jointAt(QPointF pixel, double maxDistance = 12.0) const;
  /// The joint under the mouse (its name shown beside it and as a tooltip), or −1.
  int hoveredJoint() const { return m_hovered; }
  /// Highlights joint `joint` and draws its trail over the whole motion (−1: none).
  void setSelectedJoint(int joint);
  int selectedJoint() const { return m_selected; }
  /// World positions of the selected joint in every frame of the motion (empty: none).
  const std::vector<Eigen::Vector3d>& trail() const { return m_trail; }
  /// Shows frame `frame` of `motion` (a motion of the current skeleton).
  void setPose(const Motion& motion, int frame);
  /// The local pose shown, as a one-frame Motion (empty before setPose).
  const Motion& currentPose() const { return m_pose; }
  const Skeleton& skeleton() const { return m_skeleton; }
  const WorldPose& worldPose() const { return m_world; }
  /// The joint that carries the body's motion (motion_root of the motion shown), whose floor
  /// point the camera follows.
  int motionRoot() const { return m_root; }
  const OrbitCamera& camera() const { return m_camera; }
  double extent() const { return m_extent; }
  /// Whether the camera follows the motion root (on by default); off, it stays where it is. On,
  /// the look-at point keeps its offset from the root's floor point.
  void setFollowRoot(bool follow);
  bool followRoot() const { return m_followRoot; }
  /// Joint dragging (see the top of the file); off by default and whenever a drag is not possible.
  void setJointDragEnabled(bool on);
  bool jointDragEnabled() const { return m_jointDrag; }
  /// The joint being dragged, or −1.
  int draggedJoint() const { return m_dragJoint; }
  /// Ends the drag under way (the mouse then orbits nothing until released).
  void cancelJointDrag();
  /// Where a drag of the joint that was at `from` (world) puts it when the mouse is at `pixel`:
  /// the point under the pixel in the plane through `from` facing the camera.
  Eigen::Vector3d dragTarget(const Eigen::Vector3d& from, QPointF pixel) const;
  /// Joints pinned (Shift-click toggles), increasing: a joint drag keeps them where they are.
  const std::vector<int>& pinnedJoints() const { return m_pinned; }
  void setPinnedJoints(std::vector<int> joints);
  /// The dragged joint's target, drawn as a cross joined to the joint (nothing: none).
  void setDragTarget(std::optional<Eigen::Vector3d> target);

  /// Draws `skeleton` in pose `pose` (world positions) with the character shown, in `color`
  /// (translucent); no bone to a joint `detached` marks (empty: none). Copied; replaces the
  /// overlay before.
  void setOverlay(const Skeleton& skeleton, const WorldPose& pose,
                  const std::vector<bool>& detached, const QColor& color);
  /// No overlay drawn.
  void clearOverlay();
  bool hasOverlay() const { return m_overlay != nullptr; }
  /// The overlay's pose (empty without one), its bones and its joints' pixels.
  const WorldPose& overlayPose() const;
  std::vector<BoneSegment> overlayBones() const;
  std::vector<QPointF> overlayJointPixels() const;
  QColor overlayColor() const;

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
  /// A new skeleton is shown (the joint panel rebuilds its tree).
  void skeletonChanged();
  void selectedJointChanged(int joint);
  /// A joint drag began on `joint` (at its world position `from`).
  void jointDragStarted(int joint, const Eigen::Vector3d& from);
  /// The mouse, dragging `joint`, asks for it at world point `target`.
  void jointDragged(int joint, const Eigen::Vector3d& target);
  void jointDragFinished(int joint);
  void pinnedJointsChanged();

 protected:
  bool event(QEvent* event) override;
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void leaveEvent(QEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  friend class SkeletonCanvas;
  void refresh();
  /// The hovered joint's name and where to write it (empty when none).
  QString hoverLabel(QPointF* at) const;
  /// What is drawn over the scene in both paths: pins, the drag target, the hover label.
  void paintOverlay(QPainter& painter) const;
  /// The look-at point for the current pose when following the root.
  Eigen::Vector3d rootFloor() const;
  /// Points the camera at a sphere (centre, radius) and fits the distance to this widget.
  void aim(const Eigen::Vector3d& center, double radius);
  /// The QPainter drawing (no OpenGL): shadow, capsules, trail, labels.
  void paintFallback(QPainter& painter);

  Skeleton m_skeleton;
  Motion m_pose;
  WorldPose m_world;
  double m_extent = 1.0;
  OrbitCamera m_camera;
  bool m_followRoot = true;
  bool m_hasTarget = false;  ///< the camera has looked at a pose since setSkeleton
  /// Look-at point minus the root's floor point while following the root.
  Eigen::Vector3d m_followOffset = Eigen::Vector3d::Zero();
  std::shared_ptr<const Motion> m_motion;  ///< the whole motion (setMotion), null before
  int m_root = 0;                          ///< motion_root of m_motion
  std::vector<bool> m_detached, m_body;
  std::vector<JointSide> m_sides;
  MotionBounds m_bounds;
  bool m_needsFraming = false;  ///< frame the next motion (a new skeleton)
  /// The camera was framed automatically and not moved since: a resize refits it.
  bool m_autoFramed = false;
  double m_frameRadius = 0.0;
  int m_hovered = -1;
  int m_selected = -1;
  std::vector<Eigen::Vector3d> m_trail;
  QPoint m_lastMouse;
  QPoint m_pressMouse;
  bool m_jointDrag = false;
  int m_dragJoint = -1;      ///< joint pressed on (a drag once it moves)
  bool m_dragMoved = false;  ///< the press became a drag
  Eigen::Vector3d m_dragFrom = Eigen::Vector3d::Zero();
  std::vector<int> m_pinned;
  std::optional<Eigen::Vector3d> m_dragTarget;
  SkeletonCanvas* m_canvas = nullptr;  ///< the GL child, null without OpenGL
  struct Overlay;
  std::unique_ptr<Overlay> m_overlay;  ///< setOverlay's character, null when none
  /// The overlay's capsules and spheres in its colour (for the GL view).
  std::vector<MeshVertex> overlayMesh() const;
};

}  // namespace motionmap::studio
