#pragma once
// Acclaim AMC (motion) reading — the motion half of CMU's native format, read against the
// skeleton of its ASF (asf.h) — converted into the same Motion model as BVH, on the Skeleton that
// asf_to_skeleton() makes:
//  - a joint's local rotation is C·R(dofs)·C⁻¹, with C the bone's `axis` rotation. Both Euler
//    triples compose "first listed, first applied": `axis a b c XYZ` gives C = Rz(c)·Ry(b)·Rx(a),
//    and `dof rx ry rz` gives R = Rz·Ry·Rx (settled against CMU's own BVH conversion,
//    docs/asf-amc.md);
//  - angles are in the unit the AMC declares, else the ASF's; lengths in the file's units.
// AMC files carry no frame rate: 120 fps (CMU) unless the caller says otherwise.
//
//   motionmap::Clip clip = motionmap::io::load_asf_amc("02.asf", "02_03.amc");
#include <string>
#include <string_view>

#include "motionmap/io/asf.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::io {

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

/// Reads both files into a Clip (path = the AMC's, warnings = the ASF's).
/// @throws Error (unreadable file, bad fps) / ParseError (malformed file).
Clip load_asf_amc(const std::string& asf_path, const std::string& amc_path, double fps = 120.0);
/// The same with the AMC's content given as `amc_text` (the ASF is read from `asf_path`).
Clip load_asf_amc_text(const std::string& asf_path, const std::string& amc_path,
                       std::string_view amc_text, double fps = 120.0);

}  // namespace motionmap::io
