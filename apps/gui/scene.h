#pragma once
// Drawing data of the 3-D view as plain functions, testable without OpenGL: bone segments from
// forward kinematics, box meshes for shaded bones and joints, the ground grid, and an orbit
// camera with its matrices and the projection of world points to pixels.
#include <vector>

#include <Eigen/Core>
#include <QMatrix4x4>
#include <QPointF>
#include <QSize>

#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::studio {

/// One bone: from a joint to a child joint or to one of its end sites (world coordinates).
struct BoneSegment {
  Eigen::Vector3d from;
  Eigen::Vector3d to;
};

/// Every parent→child and joint→end-site segment of `pose` (a WorldPose of `skeleton`), skipping
/// zero-length ones (CMU's dummy joints).
std::vector<BoneSegment> boneSegments(const Skeleton& skeleton, const WorldPose& pose);

/// Diagonal of the bounding box of the pose's joints and end sites (1 when degenerate), the scale
/// the view sizes bones, grid and camera distance by.
double poseExtent(const WorldPose& pose);

/// A vertex of the view's single vertex layout: position, normal, colour.
struct MeshVertex {
  float position[3];
  float normal[3];
  float color[3];
};

/// Triangles (36 vertices) of a box of half-width `radius` from `from` to `to`, appended to `out`.
void appendBox(std::vector<MeshVertex>& out, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               double radius, const Eigen::Vector3f& color);

/// Shaded skeleton: a box per bone (radius = 1.2 % of `extent`) and a cube per joint.
std::vector<MeshVertex> skeletonMesh(const std::vector<BoneSegment>& bones, const WorldPose& pose,
                                     double extent);

/// Ground grid lines (pairs of vertices) on y = 0 around `center`'s floor position, 21 lines each
/// way, `step` apart, snapped to multiples of `step` so the grid stays put while the camera
/// follows.
std::vector<MeshVertex> gridLines(const Eigen::Vector3d& center, double step);

/// An orbit camera looking at target + pan from `distance` away, Y up.
struct OrbitCamera {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< followed point (the root)
  Eigen::Vector3d pan = Eigen::Vector3d::Zero();     ///< user offset added to target
  double yaw = 0.6;                                  ///< radians about +Y
  double pitch = 0.3;                                ///< radians above the horizon, |pitch| < 1.5
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
};

/// Pixel position (origin top-left) of world point `p` seen by `camera` in a `size` viewport;
/// nothing useful for points behind the camera (w ≤ 0 gives (NaN, NaN)).
QPointF projectToPixels(const OrbitCamera& camera, QSize size, const Eigen::Vector3d& p);

}  // namespace motionmap::studio
