#pragma once
// A four-joint clip for unit tests: Hips → Spine → {LeftThumb (End Site), Head (End Site)},
// with smooth motion (the spine bends, the head turns, the root walks and turns).
#include <cmath>
#include <string>

#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::test {

inline Skeleton chain_skeleton() {
  Skeleton s;
  s.joints.push_back({"Hips", -1, {0, 0, 0}, {}, {}});
  s.joints.push_back({"Spine", 0, {0, 10, 0}, {}, {}});
  s.joints.push_back({"LeftThumb", 1, {5, 5, 0}, {}, {{1, 0, 0}}});
  s.joints.push_back({"Head", 1, {0, 8, 0}, {}, {{0, 3, 0}}});
  return s;
}

inline Clip smooth_clip(int frames = 50, const std::string& path = "smooth.bvh") {
  Clip clip;
  clip.path = path;
  clip.skeleton = chain_skeleton();
  clip.motion.resize(frames, 4);
  for (int f = 0; f < frames; ++f) {
    const double t = f / 30.0;
    for (int j = 0; j < 4; ++j) clip.motion.translation(f, j) = clip.skeleton.joints[j].offset;
    clip.motion.translation(f, 0) = Eigen::Vector3d(3 * t, 90, 5 * t);
    clip.motion.rotation(f, 0) = axis_rotation(Axis::Y, 0.5 * t);
    clip.motion.rotation(f, 1) = axis_rotation(Axis::X, 0.3 * std::sin(2 * t));
    clip.motion.rotation(f, 2) = axis_rotation(Axis::Z, 0.2 * t);
    clip.motion.rotation(f, 3) = axis_rotation(Axis::Y, 0.4 * std::cos(3 * t));
  }
  return clip;
}

}  // namespace motionmap::test
