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

/// Deepest joint nesting read or written (real skeletons are < 30 deep); deeper files are rejected
/// so that nothing recurses or indents without bound.
constexpr int kBvhMaxDepth = 1000;

struct BvhDocument {
  /// Joints in file order (parents before children), with channels and End Sites as written
  /// (except a leaf JOINT with `CHANNELS 0`, read as an End Site: see parse_bvh).
  Skeleton skeleton;
  double frame_time = 0.0;  ///< seconds, > 0
  int num_frames = 0;
  /// #frames by #channels raw values, frames-major, channels in file order.
  std::vector<double> values;
  /// Non-fatal findings, in file order, e.g. `path:line: warning: 3 extra motion rows after the
  /// declared 100 frames ignored` or `path:line:col: warning: root declared with JOINT instead of
  /// ROOT; read as ROOT`.
  std::vector<std::string> warnings;

  int num_channels() const { return skeleton.num_channels(); }
  double value(int frame, int channel) const {
    return values[static_cast<std::size_t>(frame) * num_channels() + channel];
  }
};

/// Parses BVH text. `path` is only used in messages.
/// Accepts any channel order, any rotation order, position channels on any joint, several ROOTs,
/// End Sites, tabs, CRLF/LF/CR, blank lines, scientific notation. Line-based parts: a joint name is
/// the rest of its ROOT/JOINT line (so it may contain ':' or spaces; a trailing ` {` opens the
/// block), OFFSET's three numbers and CHANNELS' count and names are on one line, and each motion
/// row is one line of exactly #channels values. `Frames: 0` (a skeleton without motion) is valid. A
/// skeleton without channels has no motion rows: its `Frames:` lines are empty. CHANNELS may be
/// left out (no channels).
/// What real exporters write is read with a warning in `warnings` naming its first line:
///  - more motion rows than `Frames:` declares: ignored
///    (`path:line: warning: 3 extra motion rows after the declared 100 frames ignored`);
///  - a root declared with JOINT: read as ROOT
///    (`path:line:col: warning: root declared with JOINT instead of ROOT; read as ROOT`);
///  - a leaf JOINT with `CHANNELS 0` (an OFFSET, no child joints, no End Site): read as an End Site
///    of its parent, offset kept
///    (`path:line:col: warning: joint 'X' has CHANNELS 0 and no children; read as an end site`).
///    A JOINT with `CHANNELS 0` and children is a static joint, a leaf JOINT without a CHANNELS
///    line a joint without channels.
/// @throws ParseError `path:line:col: error: expected <what>, found '<token>'` on any malformed
///         input (also duplicate joint names, nesting deeper than kBvhMaxDepth, a frame time
///         that is not > 0); where the file ends (nothing but whitespace left) inside the
///         hierarchy or the motion block, `path:line:col: error: file ends early: expected
///         <what>` at the end of the file, e.g. `expected '}' closing joint 'LeftArm'`, `expected
///         'Frame Time:'`, `expected 6 more values of frame 12`, `expected 2 more frames (Frames:
///         declares 10, the file holds 8)`; fewer frames than `Frames:` declares are an error.
///         Nothing is allocated that the file could not fill: a `Frames:` count the rest of the
///         file cannot hold at 2 bytes per value is reported where the rows stop (reading them
///         without storing), and beyond 4M frame·joint transforms (the size of to_motion's result)
///         `Frames:` may not exceed 1 byte of the rest of the file per transform.
BvhDocument parse_bvh(std::string_view text, const std::string& path = "<memory>");

/// Reads and parses a BVH file. @throws Error if it cannot be read, ParseError if malformed.
BvhDocument read_bvh(const std::string& path);

/// Writes `doc` as BVH text (tabs, LF, the original channel order, shortest round-trip numbers),
/// which parse_bvh reads back to the same skeleton and bit-identical values. Joints are written
/// depth-first, children in index order (the order parse_bvh produces); a skeleton in another
/// parent-before-child order is written in that depth-first order, its value columns moved along.
/// Every joint gets a CHANNELS line except a non-root joint without channels, child joints or End
/// Sites, which `CHANNELS 0` would turn into an End Site when read back.
/// @throws ParameterError if `doc` cannot be written as valid BVH: values.size() is not
///         num_frames·num_channels, a value, offset or the frame time is not finite (frame time
///         not > 0), the skeleton fails Skeleton::validate, a joint name is empty, has leading or
///         trailing blanks, a line end, or ends in " {", or nesting exceeds kBvhMaxDepth.
void write_bvh(const BvhDocument& doc, std::ostream& out);
/// @throws Error if the file cannot be written; ParameterError as above.
void write_bvh(const BvhDocument& doc, const std::string& path);

/// Converts raw channel values to local rotations (composed in the order written: channels
/// `Zrotation Yrotation Xrotation` give R = Rz·Ry·Rx, degrees → radians; any number of rotation
/// channels, repeats allowed) and local translations (position channels replace the offset's
/// components, a later channel of the same axis winning; joints without them keep the offset).
/// Result: #frames by #joints rotations and translations.
Motion to_motion(const BvhDocument& doc);

/// The inverse: a document with `skeleton`'s channel layout holding `motion` (#frames by
/// skeleton.num_joints()). Rotations are decomposed into each joint's rotation channels, each
/// frame's angles chosen closest to the previous frame's, so exported clips have no ±360° wraps:
///  - 0 rotation axes: the rotation is not stored;
///  - 1 axis: the twist about it (exact for rotations about that axis);
///  - 3 distinct axes: exact Euler angles (middle angle first in [-90°, 90°], then continuous);
///  - 2 distinct axes (i, j): the angles of the decomposition in order (i, j, k), the angle about
///    the missing axis k dropped (exact only for rotations that have none);
/// with repeated axes the first channel of each axis carries the angle, later repeats are 0.
/// Position channels get the translation's components; translations of joints (or axes) without
/// position channels are not stored (the file's OFFSET is the skeleton's).
/// @throws as check_motion(): ParameterError if the motion does not fit the skeleton (joint
///         count, array sizes, parents) or its frame time is not > 0; NumericalError for NaN,
///         infinite or zero-length values.
BvhDocument from_motion(const Skeleton& skeleton, const Motion& motion);

/// read_bvh + to_motion, as a Clip carrying the document's warnings.
Clip load_bvh(const std::string& path);
/// The same of `text`, the content of the file at `path` (named in errors and the Clip).
Clip load_bvh_text(std::string_view text, const std::string& path);

}  // namespace motionmap::io
