#pragma once
// BVH (Biovision Hierarchy) reading and writing, in two layers:
//  1. BvhDocument, a lossless mirror of the file: the hierarchy with every joint's channel layout
//     exactly as written and the raw #frames by #channels values (degrees, file units);
//  2. to_motion()/from_motion(), the conversion to and from the Motion model (quaternions).
// A document written back unchanged round-trips exactly (numbers are written in their shortest
// round-trip form).
//
//   auto doc = motionmap::io::read_bvh("64_08.bvh");     // throws ParseError on bad input
//   motionmap::Motion m = motionmap::io::to_motion(doc);
//   motionmap::io::write_bvh(doc, "copy.bvh");
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::io {

struct BvhDocument {
  /// Joints in file order (parents before children), with channels and End Sites as written.
  Skeleton skeleton;
  double frame_time = 0.0;  ///< seconds, > 0
  int num_frames = 0;
  /// #frames by #channels raw values, frames-major, channels in file order.
  std::vector<double> values;
  /// Non-fatal findings, e.g. `path:line: warning: 3 rows after the declared 100 frames ignored`.
  std::vector<std::string> warnings;

  int num_channels() const { return skeleton.num_channels(); }
  double value(int frame, int channel) const {
    return values[static_cast<std::size_t>(frame) * num_channels() + channel];
  }
};

/// Parses BVH text. `path` is only used in messages.
/// Accepts any channel order, any rotation order, position channels on any joint, several ROOTs,
/// End Sites, tabs, CRLF/LF/CR, blank lines, scientific notation. More motion rows than `Frames:`
/// declares give a warning and are ignored.
/// @throws ParseError `path:line:col: error: expected <what>, found '<token>'` on any malformed
///         input, before allocating memory the file could not fill.
BvhDocument parse_bvh(std::string_view text, const std::string& path = "<memory>");

/// Reads and parses a BVH file. @throws Error if it cannot be read, ParseError if malformed.
BvhDocument read_bvh(const std::string& path);

/// Writes `doc` as BVH text (tabs, LF, the original channel order, shortest round-trip numbers).
void write_bvh(const BvhDocument& doc, std::ostream& out);
/// @throws Error if the file cannot be written.
void write_bvh(const BvhDocument& doc, const std::string& path);

/// Converts raw channel values to local rotations (composed in the order written: channels
/// `Zrotation Yrotation Xrotation` give R = Rz·Ry·Rx) and local translations (position channels
/// replace the offset's components; joints without them keep the offset).
Motion to_motion(const BvhDocument& doc);

/// The inverse: a document with `skeleton`'s channel layout holding `motion` (which must have
/// skeleton.num_joints() joints). Rotations are decomposed into each joint's rotation channels,
/// each frame's angles chosen closest to the previous frame's, so exported clips have no ±360°
/// wraps. @throws ParameterError if the motion does not fit the skeleton.
BvhDocument from_motion(const Skeleton& skeleton, const Motion& motion);

/// read_bvh + to_motion, as a Clip carrying the document's warnings.
Clip load_bvh(const std::string& path);

}  // namespace motionmap::io
