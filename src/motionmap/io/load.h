#pragma once
// One entry point for every supported clip format, chosen by file extension.
#include <string>
#include <string_view>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::io {

struct LoadOptions {
  /// Skeleton for an .amc file. Empty: the .asf beside it named like the take's subject
  /// (CMU layout: 02_03.amc → 02.asf), or the only .asf in that folder.
  std::string asf_path;
  /// Frames per second; 0 keeps the file's (BVH) or uses 120 (AMC, which stores none).
  double fps = 0.0;
  /// Also take the SHA-256 of the bytes parsed (Clip::sha256), for a map file's record of its
  /// clips: the hash is of exactly what was mapped, however the file changes after. Hashing adds
  /// about a fifth to a BVH's loading, so it is asked for only where a map file is made or checked.
  bool sha256 = false;
};

/// Loads a .bvh, or an .amc with its .asf, and runs check_clip() on the result.
/// @throws Error (unreadable, unknown extension, missing .asf), ParseError (malformed file), or
///         ParameterError / NumericalError from check_clip() (e.g. an `fps` so large that the
///         frame time is 0).
Clip load_clip(const std::string& path, const LoadOptions& options = {});

}  // namespace motionmap::io
