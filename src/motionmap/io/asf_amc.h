#pragma once
// Acclaim ASF (skeleton) + AMC (motion) reading — CMU's native format — converted into the same
// Skeleton/Motion model as BVH:
//  - joint 0 is the root, then one joint per bone, parents before children;
//  - a joint sits at the start of its bone: its offset is its parent bone's direction × length
//    (the root's children: zero, they start at the root);
//  - its local rotation is C·R(dofs)·C⁻¹, with C the bone's `axis` rotation. Both Euler triples
//    compose "first listed, first applied": `axis a b c XYZ` gives C = Rz(c)·Ry(b)·Rx(a), and
//    `dof rx ry rz` gives R = Rz·Ry·Rx (settled against CMU's own BVH conversion, docs/asf-amc.md);
//  - lengths are kept in the file's units as written (`:units length` is recorded, not applied),
//    angles are read in deg or rad as the files declare.
// AMC files carry no frame rate: 120 fps (CMU) unless the caller says otherwise.
//
//   motionmap::Clip clip = motionmap::io::load_asf_amc("02.asf", "02_03.amc");
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

/// Parses AMC text for `asf` into a Motion of the skeleton made by asf_to_skeleton():
/// #frames by (1 + #bones) local transforms. Frame numbers must count up by one from the first;
/// each bone line holds exactly that bone's dof count of values (the root: one per `order`
/// entry). Bones absent from a frame keep their rest pose. Angles are in the unit the AMC declares
/// (`:DEGREES`/`:RADIANS`), else the ASF's. Root translations replace the `position` components
/// they animate; a bone's tx ty tz move its joint by C·t; its `l` moves its children along its
/// direction (a leaf's End Site stays). Memory grows one frame per frame line, so it is
/// proportional to the text. @throws ParseError, ParameterError (fps not positive and finite).
Motion parse_amc(std::string_view text, const AsfSkeleton& asf, double fps = 120.0,
                 const std::string& path = "<memory>");

/// The Skeleton of an ASF: the root (named "root", offset = `position`) then every bone (parents
/// first). Each joint gets BVH channels so the clip can be written as BVH: the root Xposition
/// Yposition Zposition Zrotation Yrotation Xrotation; bones with rotation dofs Zrotation Yrotation
/// Xrotation, preceded by Xposition Yposition Zposition if the bone has tx/ty/tz or its parent an
/// `l` dof; leaf bones get an End Site at direction × length.
/// @throws ParameterError if a bone's parent index does not come before it.
Skeleton asf_to_skeleton(const AsfSkeleton& asf);

/// Reads both files into a Clip (path = the AMC's, warnings = the ASF's).
/// @throws Error (unreadable file, bad fps) / ParseError (malformed file).
Clip load_asf_amc(const std::string& asf_path, const std::string& amc_path, double fps = 120.0);

}  // namespace motionmap::io
