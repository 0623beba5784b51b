#include "scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace motionmap::studio {

std::vector<BoneSegment> boneSegments(const Skeleton& skeleton, const WorldPose& pose) {
  std::vector<BoneSegment> out;
  std::size_t end_site = 0;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joints[static_cast<std::size_t>(j)];
    const Eigen::Vector3d& p = pose.positions[static_cast<std::size_t>(j)];
    if (joint.parent >= 0) {
      const Eigen::Vector3d& q = pose.positions[static_cast<std::size_t>(joint.parent)];
      if ((p - q).squaredNorm() > 0.0) out.push_back({q, p});
    }
    for (std::size_t e = 0; e < joint.end_sites.size(); ++e, ++end_site) {
      if (end_site >= pose.end_sites.size()) break;
      const Eigen::Vector3d& s = pose.end_sites[end_site];
      if ((s - p).squaredNorm() > 0.0) out.push_back({p, s});
    }
  }
  return out;
}

double poseExtent(const WorldPose& pose) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto* points : {&pose.positions, &pose.end_sites}) {
    for (const auto& p : *points) {
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  const double d = (hi - lo).norm();
  return std::isfinite(d) && d > 0.0 ? d : 1.0;
}

void appendBox(std::vector<MeshVertex>& out, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
               double radius, const Eigen::Vector3f& color) {
  Eigen::Vector3d axis = to - from;
  const double length = axis.norm();
  axis = length > 0.0 ? Eigen::Vector3d(axis / length) : Eigen::Vector3d::UnitY();
  // Two directions perpendicular to the bone span its cross-section.
  const Eigen::Vector3d helper =
      std::abs(axis.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d u = axis.cross(helper).normalized() * radius;
  const Eigen::Vector3d v = axis.cross(u).normalized() * radius;
  const Eigen::Vector3d a = length > 0.0 ? from : Eigen::Vector3d(from - axis * radius);
  const Eigen::Vector3d b = length > 0.0 ? to : Eigen::Vector3d(from + axis * radius);
  Eigen::Vector3d corners[8];
  for (int i = 0; i < 8; ++i) {
    corners[i] = ((i & 4) ? b : a) + ((i & 1) ? u : Eigen::Vector3d(-u)) +
                 ((i & 2) ? v : Eigen::Vector3d(-v));
  }
  // Faces as corner quads (counter-clockwise seen from outside) with their normals.
  struct Face {
    int c[4];
    Eigen::Vector3d n;
  };
  const Face faces[6] = {{{0, 2, 3, 1}, -axis},           {{4, 5, 7, 6}, axis},
                         {{0, 1, 5, 4}, -v.normalized()}, {{2, 6, 7, 3}, v.normalized()},
                         {{0, 4, 6, 2}, -u.normalized()}, {{1, 3, 7, 5}, u.normalized()}};
  for (const Face& f : faces) {
    for (int k : {0, 1, 2, 0, 2, 3}) {
      const Eigen::Vector3d& p = corners[f.c[k]];
      out.push_back({{float(p.x()), float(p.y()), float(p.z())},
                     {float(f.n.x()), float(f.n.y()), float(f.n.z())},
                     {color.x(), color.y(), color.z()}});
    }
  }
}

std::vector<MeshVertex> skeletonMesh(const std::vector<BoneSegment>& bones, const WorldPose& pose,
                                     double extent) {
  std::vector<MeshVertex> out;
  out.reserve((bones.size() + pose.positions.size()) * 36);
  const double radius = 0.012 * extent;
  for (const auto& bone : bones) appendBox(out, bone.from, bone.to, radius, {0.85f, 0.78f, 0.62f});
  for (const auto& p : pose.positions) {
    appendBox(out, p - Eigen::Vector3d(0, radius * 1.25, 0),
              p + Eigen::Vector3d(0, radius * 1.25, 0), radius * 1.25, {0.25f, 0.45f, 0.85f});
  }
  return out;
}

std::vector<MeshVertex> gridLines(const Eigen::Vector3d& center, double step) {
  std::vector<MeshVertex> out;
  if (!(step > 0.0) || !center.allFinite()) return out;
  const int half = 10;
  const double cx = std::round(center.x() / step) * step, cz = std::round(center.z() / step) * step;
  const double lo = -half * step, hi = half * step;
  for (int i = -half; i <= half; ++i) {
    const float shade = i == 0 ? 0.35f : 0.6f;
    const float t = float(i * step);
    out.push_back({{float(cx + t), 0.f, float(cz + lo)}, {0, 1, 0}, {shade, shade, shade}});
    out.push_back({{float(cx + t), 0.f, float(cz + hi)}, {0, 1, 0}, {shade, shade, shade}});
    out.push_back({{float(cx + lo), 0.f, float(cz + t)}, {0, 1, 0}, {shade, shade, shade}});
    out.push_back({{float(cx + hi), 0.f, float(cz + t)}, {0, 1, 0}, {shade, shade, shade}});
  }
  return out;
}

Eigen::Vector3d OrbitCamera::eye() const {
  const Eigen::Vector3d dir(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                            std::cos(pitch) * std::cos(yaw));
  return target + pan + dir * distance;
}

QMatrix4x4 OrbitCamera::view() const {
  const Eigen::Vector3d e = eye(), c = target + pan;
  QMatrix4x4 m;
  m.lookAt(QVector3D(float(e.x()), float(e.y()), float(e.z())),
           QVector3D(float(c.x()), float(c.y()), float(c.z())), QVector3D(0, 1, 0));
  return m;
}

QMatrix4x4 OrbitCamera::projection(QSize size) const {
  QMatrix4x4 m;
  const float aspect = size.height() > 0 ? float(size.width()) / float(size.height()) : 1.0f;
  m.perspective(float(fovDegrees), aspect, float(distance * 0.01), float(distance * 100.0));
  return m;
}

void OrbitCamera::orbit(double dx, double dy) {
  yaw -= dx * 0.01;
  pitch = std::clamp(pitch + dy * 0.01, -1.5, 1.5);
}

void OrbitCamera::panBy(double dx, double dy, QSize size) {
  const double h = std::max(1, size.height());
  const double units = 2.0 * distance * std::tan(fovDegrees * M_PI / 360.0) / h;  // world per pixel
  const Eigen::Vector3d forward = (target + pan - eye()).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  pan += (-dx * right + dy * up) * units;
}

void OrbitCamera::zoom(double steps) {
  distance = std::clamp(distance * std::pow(0.85, steps), 1e-3, 1e7);
}

QPointF projectToPixels(const OrbitCamera& camera, QSize size, const Eigen::Vector3d& p) {
  const QVector4D clip = camera.projection(size) * camera.view() *
                         QVector4D(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  if (clip.w() <= 0.0f) return {std::nan(""), std::nan("")};
  const double x = clip.x() / clip.w(), y = clip.y() / clip.w();
  return {(x + 1.0) * 0.5 * size.width(), (1.0 - y) * 0.5 * size.height()};
}

}  // namespace motionmap::studio
