#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace motionmap::studio {

MotionBounds motionBounds(const Skeleton& skeleton, const Motion& motion,
                          const std::vector<bool>& body, int rootJoint) {
  MotionBounds out;
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(inf), hi = -lo;
  Eigen::Vector3d flo = lo, fhi = hi;
  if (rootJoint < 0 || rootJoint >= skeleton.num_joints()) return out;
  WorldPose world;
  const auto visit = [&](int f) {
    forward_kinematics(skeleton, motion.pose(f), world);
    const Eigen::Vector3d& root = world.positions[std::size_t(rootJoint)];
    const Eigen::Vector3d floor(root.x(), 0.0, root.z());
    const auto add = [&](const Eigen::Vector3d& p) {
      if (!p.allFinite() || !floor.allFinite()) return;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      flo = flo.cwiseMin(p - floor);
      fhi = fhi.cwiseMax(p - floor);
    };
    for (std::size_t j = 0; j < world.positions.size(); ++j) {
      if (body.empty() || (j < body.size() && body[j])) add(world.positions[j]);
    }
    for (const auto& e : world.end_sites) add(e);
  };
  // A long clip is sampled, as a click into another clip of a library frames it anew (every frame
  // of a 6000-frame clip: 10 ms): every 3rd frame of it, 1/40 s apart at 120 fps, misses only
  // millimetres of the extremes, well within the view's margin.
  const int step = std::max(1, (motion.num_frames + kMaxBoundsFrames - 1) / kMaxBoundsFrames);
  for (int f = 0; f < motion.num_frames; f += step) visit(f);
  if (motion.num_frames > 0 && (motion.num_frames - 1) % step != 0) visit(motion.num_frames - 1);
  if (!lo.allFinite()) return out;
  out = {lo, hi, flo, fhi, true};
  return out;
}

std::vector<Eigen::Vector3d> jointTrail(const Skeleton& skeleton, const Motion& motion, int joint) {
  std::vector<Eigen::Vector3d> out;
  if (joint < 0 || joint >= skeleton.num_joints() || motion.num_joints != skeleton.num_joints())
    return out;
  out.reserve(std::size_t(motion.num_frames));
  WorldPose world;
  for (int f = 0; f < motion.num_frames; ++f) {
    forward_kinematics(skeleton, motion.pose(f), world);
    out.push_back(world.positions[std::size_t(joint)]);
  }
  return out;
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

namespace {

void pushVertex(std::vector<MeshVertex>& out, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                const Eigen::Vector3f& c) {
  out.push_back({{float(p.x()), float(p.y()), float(p.z())},
                 {float(n.x()), float(n.y()), float(n.z())},
                 {c.x(), c.y(), c.z()}});
}

}  // namespace

void appendCapsule(std::vector<MeshVertex>& out, const Eigen::Vector3d& from,
                   const Eigen::Vector3d& to, double radius, const Eigen::Vector3f& color,
                   bool caps) {
  Eigen::Vector3d axis = to - from;
  const double length = axis.norm();
  axis = length > 0.0 ? Eigen::Vector3d(axis / length) : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d helper =
      std::abs(axis.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d u = axis.cross(helper).normalized();
  const Eigen::Vector3d v = axis.cross(u);
  // A point of the capsule's surface: angle `a` round the axis, latitude `lat` (0 on the
  // cylinder, ±π/2 at the poles) on the cap at `end` (from or to); returns its normal too.
  const auto surface = [&](double a, double lat, const Eigen::Vector3d& end, Eigen::Vector3d& n) {
    n = (std::cos(a) * u + std::sin(a) * v) * std::cos(lat) + axis * std::sin(lat);
    return Eigen::Vector3d(end + radius * n);
  };
  // One ring of quads between latitudes lat0 and lat1 about `end0`/`end1`.
  const auto band = [&](double lat0, const Eigen::Vector3d& end0, double lat1,
                        const Eigen::Vector3d& end1) {
    for (int s = 0; s < kCapsuleSegments; ++s) {
      const double a0 = 2.0 * M_PI * s / kCapsuleSegments,
                   a1 = 2.0 * M_PI * (s + 1) / kCapsuleSegments;
      Eigen::Vector3d n[4];
      const Eigen::Vector3d p[4] = {surface(a0, lat0, end0, n[0]), surface(a1, lat0, end0, n[1]),
                                    surface(a1, lat1, end1, n[2]), surface(a0, lat1, end1, n[3])};
      for (int k : {0, 1, 2, 0, 2, 3}) pushVertex(out, p[k], n[k], color);
    }
  };
  band(0.0, from, 0.0, to);
  if (!caps) return;
  for (int b = 0; b < kCapsuleBands; ++b) {
    const double l0 = 0.5 * M_PI * b / kCapsuleBands, l1 = 0.5 * M_PI * (b + 1) / kCapsuleBands;
    band(l0, to, l1, to);        // the cap beyond `to`
    band(-l1, from, -l0, from);  // the cap before `from`
  }
}

std::vector<MeshVertex> skeletonMesh(const std::vector<BoneSegment>& bones, const WorldPose& pose,
                                     double extent, const std::vector<JointSide>& sides,
                                     const std::vector<bool>& body, int selected) {
  std::vector<MeshVertex> out;
  out.reserve((bones.size() + pose.positions.size()) * std::size_t(capsuleVertexCount()));
  const double radius = boneRadius(extent);
  const auto side = [&](int j) {
    return j >= 0 && std::size_t(j) < sides.size() ? sides[std::size_t(j)] : JointSide::Center;
  };
  for (const auto& bone : bones) {
    if (bone.from.allFinite() && bone.to.allFinite())
      appendCapsule(out, bone.from, bone.to, radius, side_color(side(bone.joint), true));
  }
  for (std::size_t j = 0; j < pose.positions.size(); ++j) {
    const Eigen::Vector3d& p = pose.positions[j];
    if (!p.allFinite() || (!body.empty() && (j >= body.size() || !body[j]))) continue;
    if (int(j) == selected) {
      appendCapsule(out, p, p, radius * 2.0, {1.0f, 0.6f, 0.05f});
    } else {
      appendCapsule(out, p, p, radius * 1.25, side_color(side(int(j))));
    }
  }
  return out;
}

std::vector<MeshVertex> shadowMesh(const std::vector<BoneSegment>& bones, double extent,
                                   double floor, const Eigen::Vector3f& background) {
  std::vector<MeshVertex> out;
  const double width = 2.5 * boneRadius(extent);
  const double lift = 1e-3 * extent;  // above the grid's lines, below any body part
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  // Darkness at a point `height` above the floor: 45 % on it, none 1.5 extents up.
  const auto shade = [&](double height) {
    const double k = 0.45 * std::clamp(1.0 - std::abs(height - floor) / (1.5 * extent), 0.0, 1.0);
    return Eigen::Vector3f(background * float(1.0 - k));
  };
  const auto onFloor = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p.x(), floor + lift, p.z());
  };
  const int fan = 16;
  const auto disc = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d c = onFloor(p);
    const Eigen::Vector3f dark = shade(p.y());
    for (int i = 0; i < fan; ++i) {
      const double a0 = 2.0 * M_PI * i / fan, a1 = 2.0 * M_PI * (i + 1) / fan;
      pushVertex(out, c, up, dark);
      pushVertex(out, c + width * Eigen::Vector3d(std::cos(a0), 0, std::sin(a0)), up, background);
      pushVertex(out, c + width * Eigen::Vector3d(std::cos(a1), 0, std::sin(a1)), up, background);
    }
  };
  for (const auto& bone : bones) {
    if (!bone.from.allFinite() || !bone.to.allFinite()) continue;
    const Eigen::Vector3d a = onFloor(bone.from), b = onFloor(bone.to);
    const Eigen::Vector3d along = b - a;
    if (along.norm() > 1e-9 * extent) {
      const Eigen::Vector3d side = along.cross(up).normalized() * width;
      const Eigen::Vector3f da = shade(bone.from.y()), db = shade(bone.to.y());
      // Two quads: the axis (dark) to each edge (background).
      for (const double s : {1.0, -1.0}) {
        pushVertex(out, a, up, da);
        pushVertex(out, b, up, db);
        pushVertex(out, b + s * side, up, background);
        pushVertex(out, a, up, da);
        pushVertex(out, b + s * side, up, background);
        pushVertex(out, a + s * side, up, background);
      }
    }
    disc(bone.from);
    disc(bone.to);
  }
  return out;
}

Eigen::Vector3f trailColor(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return Eigen::Vector3f(float(0.85 * (1 - t) + 0.15 * t), 0.2f, float(0.15 * (1 - t) + 0.9 * t));
}

std::vector<MeshVertex> trailMesh(const std::vector<Eigen::Vector3d>& points, double extent) {
  std::vector<MeshVertex> out;
  const double radius = 0.35 * boneRadius(extent);
  const std::size_t n = points.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    if (!points[i].allFinite() || !points[i + 1].allFinite()) continue;
    if ((points[i + 1] - points[i]).squaredNorm() == 0.0) continue;
    appendCapsule(out, points[i], points[i + 1], radius, trailColor(double(i) / double(n - 1)),
                  /*caps=*/false);
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

Eigen::Vector3d OrbitCamera::right() const {
  // forward × Y, normalized; written out so it stays defined looking straight down.
  return {std::cos(yaw), 0.0, -std::sin(yaw)};
}

Eigen::Vector3d OrbitCamera::up() const {
  return {-std::sin(pitch) * std::sin(yaw), std::cos(pitch), -std::sin(pitch) * std::cos(yaw)};
}

QMatrix4x4 OrbitCamera::view() const {
  const Eigen::Vector3d e = eye(), c = target + pan, u = up();
  QMatrix4x4 m;
  m.lookAt(QVector3D(float(e.x()), float(e.y()), float(e.z())),
           QVector3D(float(c.x()), float(c.y()), float(c.z())),
           QVector3D(float(u.x()), float(u.y()), float(u.z())));
  return m;
}

double OrbitCamera::fitDistance(double radius, QSize size) const {
  const double halfV = fovDegrees * M_PI / 360.0;
  const double aspect = size.height() > 0 ? double(size.width()) / size.height() : 1.0;
  const double halfH = std::atan(std::tan(halfV) * aspect);
  // A sphere of radius r seen from d subtends asin(r / d) each side of its centre.
  return 1.08 * radius / std::sin(std::min(halfV, halfH));
}

void applyPreset(OrbitCamera& camera, CameraPreset preset) {
  switch (preset) {
    case CameraPreset::Front:
      camera.yaw = 0.0, camera.pitch = 0.0;
      break;
    case CameraPreset::Side:
      camera.yaw = 0.5 * M_PI, camera.pitch = 0.0;
      break;
    case CameraPreset::Top:
      camera.yaw = 0.0, camera.pitch = OrbitCamera::kMaxPitch;
      break;
  }
}

QMatrix4x4 OrbitCamera::projection(QSize size) const {
  QMatrix4x4 m;
  const float aspect = size.height() > 0 ? float(size.width()) / float(size.height()) : 1.0f;
  m.perspective(float(fovDegrees), aspect, float(distance * 0.01), float(distance * 100.0));
  return m;
}

void OrbitCamera::orbit(double dx, double dy) {
  yaw -= dx * 0.01;
  pitch = std::clamp(pitch + dy * 0.01, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::panBy(double dx, double dy, QSize size) {
  const double h = std::max(1, size.height());
  const double units = 2.0 * distance * std::tan(fovDegrees * M_PI / 360.0) / h;  // world per pixel
  pan += (-dx * right() + dy * up()) * units;
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
