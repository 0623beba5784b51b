#pragma once
// Acclaim ASF (skeleton) reading — the skeleton half of CMU's native format; amc.h reads the
// motion — converted into the same Skeleton model as BVH:
//  - joint 0 is the root, then one joint per bone, parents before children;
//  - a joint sits at the start of its bone: its offset is its parent bone's direction × length
//    (the root's children: zero, they start at the root);
//  - each bone keeps its `axis` rotation C as written, for the AMC reader, which turns the dof
//    values R into the local rotation C·R·C⁻¹ (docs/asf-amc.md);
//  - lengths are kept in the file's units as written (`:units length` is recorded, not applied),
//    angles are read in deg or rad as the file declares.
//
//   motionmap::io::AsfSkeleton asf = motionmap::io::read_asf("02.asf");
//   motionmap::Skeleton skeleton = motionmap::io::asf_to_skeleton(asf);
#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::io {

/// Degrees of freedom of an ASF bone, in the order of its `dof` line. L stretches the bone.
enum class Dof { RX, RY, RZ, TX, TY, TZ, L };

struct AsfBone {
  std::string name;
  int id = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit vector in world rest frame
  double length = 0.0;
  Eigen::Vector3d axis_angles = Eigen::Vector3d::Zero();  ///< `axis` angles as written
  std::array<Axis, 3> axis_order{Axis::X, Axis::Y, Axis::Z};
  std::vector<Dof> dofs;
  /// One (min, max) per dof, as written (±inf allowed); empty when the file gives no `limits`.
  std::vector<std::pair<double, double>> limits;
  int parent = -1;  ///< index into AsfSkeleton::bones, −1 = root
};

struct AsfSkeleton {
  std::string name;
  double mass_unit = 1.0;
  double length_unit = 1.0;  ///< `:units length` as written; lengths are NOT multiplied by it
  bool angles_in_degrees = true;
  std::vector<Dof> root_order;  ///< the root's `order` (e.g. TX TY TZ RX RY RZ); never L
  std::array<Axis, 3> root_axis_order{Axis::X, Axis::Y, Axis::Z};
  Eigen::Vector3d root_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d root_orientation = Eigen::Vector3d::Zero();  ///< as written (angle unit)
  /// Bones parents first: depth-first from the root, children in `:hierarchy` order (for CMU
  /// files this is the file order).
  std::vector<AsfBone> bones;
  /// Non-fatal findings, like "path:line: warning: ':skin' section ignored".
  std::vector<std::string> warnings;
};

/// Parses ASF text. Keywords, section names, dof names and axis orders are case-insensitive;
/// bone names are not. Blank lines and `#` comments are skipped; `:skin` is skipped with a
/// warning; anything else unknown is an error. `path` is only used in messages.
/// @throws ParseError `path:line:col: error: expected …, found '…'`.
AsfSkeleton parse_asf(std::string_view text, const std::string& path = "<memory>");
/// Reads and parses an ASF file. @throws Error if unreadable, ParseError if malformed.
AsfSkeleton read_asf(const std::string& path);

/// The Skeleton of an ASF: the root (named "root", offset = `position`) then every bone (parents
/// first). Each joint gets BVH channels so the clip can be written as BVH: the root Xposition
/// Yposition Zposition Zrotation Yrotation Xrotation; bones with rotation dofs Zrotation Yrotation
/// Xrotation, preceded by Xposition Yposition Zposition if the bone has tx/ty/tz or its parent an
/// `l` dof; leaf bones get an End Site at direction × length.
/// @throws ParameterError if a bone's parent index does not come before it.
Skeleton asf_to_skeleton(const AsfSkeleton& asf);

}  // namespace motionmap::io
