#pragma once
// Drawing data of the 3-D view as plain functions, testable without OpenGL: bone segments from
// forward kinematics (none to a child that moves by its own translation channels), capsule meshes
// for shaded bones and joints coloured by body side, a soft ground shadow, a joint's trail, the
// ground grid, the clip's bounding volume, and an orbit camera with its matrices, framing and
// presets, and the projection of world points to pixels.
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <QMatrix4x4>
#include <QPointF>
#include <QSize>

#include "motionmap/skeleton/bones.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::studio {

// Bone segments, detached joints, body joints, joint sides and their colours, and the pose's
// extent come from the library (motionmap/skeleton/bones.h), shared with `motionmap keyposes`.

/// Frames motionBounds() looks at, at most (evenly spaced, and the last).
inline constexpr int kMaxBoundsFrames = 2000;

/// Bounding boxes of a whole clip (joints of body_joints and end sites, every finite point of up to
/// kMaxBoundsFrames evenly spaced frames and the last): `box*`
/// in world coordinates, `follow*` relative to the root's floor point (x, 0, z) of each frame, the
/// volume a camera following the root must keep in view.
struct MotionBounds {
  Eigen::Vector3d boxMin = Eigen::Vector3d::Zero(), boxMax = Eigen::Vector3d::Zero();
  Eigen::Vector3d followMin = Eigen::Vector3d::Zero(), followMax = Eigen::Vector3d::Zero();
  bool valid = false;  ///< false when no frame had a finite point
};
/// `rootJoint`: the joint followed (motion_root).
MotionBounds motionBounds(const Skeleton& skeleton, const Motion& motion,
                          const std::vector<bool>& body, int rootJoint);

/// World positions of `joint` in every frame of `motion` (its trail).
std::vector<Eigen::Vector3d> jointTrail(const Skeleton& skeleton, const Motion& motion, int joint);

/// A vertex of the view's single vertex layout: position, normal, colour.
struct MeshVertex {
  float position[3];
  float normal[3];
  float color[3];
};

/// Triangles (36 vertices) of a box of half-width `radius` from `from` to `to`, appended to `out`.
void appendBox(std::vector<MeshVertex>& out, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               double radius, const Eigen::Vector3f& color);

/// Segments around a capsule and latitude bands per hemispherical cap of appendCapsule.
constexpr int kCapsuleSegments = 20;
constexpr int kCapsuleBands = 5;
/// Vertices appendCapsule adds: 6 per quad, kCapsuleSegments·(1 + 2·kCapsuleBands) quads
/// (without caps: kCapsuleSegments quads).
constexpr int capsuleVertexCount(bool caps = true) {
  return 6 * kCapsuleSegments * (caps ? 1 + 2 * kCapsuleBands : 1);
}

/// Triangles of a capsule (a cylinder of `radius` from `from` to `to` with hemispherical caps;
/// a sphere when they coincide) with unit outward normals, appended to `out`. Without `caps`,
/// the open cylinder only (the trail's tube).
void appendCapsule(std::vector<MeshVertex>& out, const Eigen::Vector3d& from,
                   const Eigen::Vector3d& to, double radius, const Eigen::Vector3f& color,
                   bool caps = true);

/// Bone radius for a skeleton of rest extent `extent` (1.2 %).
inline double boneRadius(double extent) {
  return 0.012 * extent;
}

/// Shaded skeleton: a capsule per bone (radius boneRadius(extent), lighter side colour of its
/// joint) and a sphere (1.25 radii) per joint of `body` (empty: all), coloured by `sides` (empty:
/// all centre). `selected` (≥ 0) is drawn as a larger orange sphere.
std::vector<MeshVertex> skeletonMesh(const std::vector<BoneSegment>& bones, const WorldPose& pose,
                                     double extent, const std::vector<JointSide>& sides = {},
                                     const std::vector<bool>& body = {}, int selected = -1);

/// The soft ground shadow of `bones` under a light straight above, on the plane y = floor:
/// for each bone a strip along its floor projection, darkest (`background` × 0.55) on its axis
/// and fading to `background` at 2.5 bone radii, with a radial fan of the same fall-off around
/// each end. Drawn with glBlendEquation(GL_MIN), so overlaps do not darken twice. Shadows of
/// points higher above the floor are fainter.
std::vector<MeshVertex> shadowMesh(const std::vector<BoneSegment>& bones, double extent,
                                   double floor, const Eigen::Vector3f& background);

/// A joint's trail as a thin tube (0.35 bone radii) through `points`, coloured red → blue over
/// time like the map's trajectory; non-finite points break it.
std::vector<MeshVertex> trailMesh(const std::vector<Eigen::Vector3d>& points, double extent);
/// Red → blue colour of time t ∈ [0, 1] (the map's trajectory colours).
Eigen::Vector3f trailColor(double t);

/// Ground grid lines (pairs of vertices) on y = 0 around `center`'s floor position, 21 lines each
/// way, `step` apart, snapped to multiples of `step` so the grid stays put while the camera
/// follows.
std::vector<MeshVertex> gridLines(const Eigen::Vector3d& center, double step);

/// An orbit camera looking at target + pan from `distance` away, Y up.
struct OrbitCamera {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< followed point (the root)
  Eigen::Vector3d pan = Eigen::Vector3d::Zero();     ///< user offset added to target
  double yaw = 0.6;                                  ///< radians about +Y
  double pitch = 0.3;  ///< radians above the horizon, |pitch| ≤ π/2
  double distance = 400.0;
  double fovDegrees = 40.0;

  Eigen::Vector3d eye() const;
  QMatrix4x4 view() const;
  /// Perspective for a viewport of `size` pixels; near/far from `distance`.
  QMatrix4x4 projection(QSize size) const;
  /// Rotates by a mouse move of (dx, dy) pixels.
  void orbit(double dx, double dy);
  /// Moves the look-at point in the view plane by (dx, dy) pixels of a `size` viewport.
  void panBy(double dx, double dy, QSize size);
  /// Wheel zoom: `steps` > 0 moves closer (×0.85 per step).
  void zoom(double steps);
  /// Unit vectors of the camera frame (right, up; forward = up × right).
  Eigen::Vector3d right() const;
  Eigen::Vector3d up() const;
  /// Distance at which a sphere of `radius` around the look-at point fills the smaller of the
  /// two fields of view of a `size` viewport (with 8 % margin), whatever the yaw and pitch.
  double fitDistance(double radius, QSize size) const;

  static constexpr double kDefaultYaw = 0.6;
  static constexpr double kDefaultPitch = 0.3;
  static constexpr double kMaxPitch = 1.5707963267948966;  ///< straight down (top view)
};

/// Camera presets (View → Camera): yaw and pitch only, the look-at point and distance stay.
enum class CameraPreset { Front, Side, Top };
/// Front: from +Z (yaw 0, pitch 0); Side: from +X (yaw π/2, pitch 0); Top: from +Y (yaw 0,
/// pitch π/2, +Z down the screen).
void applyPreset(OrbitCamera& camera, CameraPreset preset);

/// Pixel position (origin top-left) of world point `p` seen by `camera` in a `size` viewport;
/// nothing useful for points behind the camera (w ≤ 0 gives (NaN, NaN)).
QPointF projectToPixels(const OrbitCamera& camera, QSize size, const Eigen::Vector3d& p);

}  // namespace motionmap::studio
