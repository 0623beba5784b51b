#pragma once
// Acclaim ASF (skeleton) + AMC (motion) reading — CMU's native format — converted into the same
// Skeleton/Motion model as BVH:
//  - the offset of a bone is its parent's direction × length (the root's children: from the root);
//  - its local rotation is C·R(dofs)·C⁻¹, with C the bone's `axis` rotation;
//  - lengths are scaled to the file's `:units length` as written (no unit change), angles read in
//    deg or rad as the files declare.
// AMC files carry no frame rate: 120 fps (CMU) unless the caller says otherwise.
//
//   motionmap::Clip clip = motionmap::io::load_asf_amc("02.asf", "02_03.amc");
#include <array>
#include <string>
#include <utility>
#include <string_view>
#include <vector>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::io {

/// Degrees of freedom of an ASF bone, in the order of its `dof` line.
enum class Dof { RX, RY, RZ, TX, TY, TZ, L };

struct AsfBone {
  std::string name;
  int id = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit vector in world rest frame
  double length = 0.0;
  Eigen::Vector3d axis_angles = Eigen::Vector3d::Zero();  ///< `axis` angles as written
  std::array<Axis, 3> axis_order{Axis::X, Axis::Y, Axis::Z};
  std::vector<Dof> dofs;
  std::vector<std::pair<double, double>> limits;  ///< one (min, max) per dof, as written
  int parent = -1;                                ///< index into AsfSkeleton::bones, −1 = root
};

struct AsfSkeleton {
  std::string name;
  double mass_unit = 1.0;
  double length_unit = 1.0;
  bool angles_in_degrees = true;
  std::vector<Dof> root_order;  ///< the root's `order` (e.g. TX TY TZ RX RY RZ)
  std::array<Axis, 3> root_axis_order{Axis::X, Axis::Y, Axis::Z};
  Eigen::Vector3d root_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d root_orientation = Eigen::Vector3d::Zero();
  /// Bones in an order where parents come before children (reordered from the file if needed).
  std::vector<AsfBone> bones;
};

/// Parses ASF text. @throws ParseError `path:line:col: error: expected …, found '…'`.
AsfSkeleton parse_asf(std::string_view text, const std::string& path = "<memory>");
AsfSkeleton read_asf(const std::string& path);

/// Parses AMC text for `asf` into a Motion of the skeleton made by asf_to_skeleton().
/// Bones absent from a frame keep their rest pose. @throws ParseError.
Motion parse_amc(std::string_view text, const AsfSkeleton& asf, double fps = 120.0,
                 const std::string& path = "<memory>");

/// The Skeleton of an ASF: the root then every bone (parents first). Each joint gets BVH channels
/// so the clip can be written as BVH: the root Xposition Yposition Zposition Zrotation Yrotation
/// Xrotation, bones with rotation dofs Zrotation Yrotation Xrotation (plus position channels for
/// translation/length dofs); leaf bones get an End Site at direction × length.
Skeleton asf_to_skeleton(const AsfSkeleton& asf);

/// Reads both files. @throws Error / ParseError.
Clip load_asf_amc(const std::string& asf_path, const std::string& amc_path, double fps = 120.0);

}  // namespace motionmap::io
