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
};

/// Loads a .bvh, or an .amc with its .asf, and runs check_clip() on the result.
/// @throws Error (unreadable, unknown extension, missing .asf), ParseError (malformed file), or
///         ParameterError / NumericalError from check_clip() (e.g. an `fps` so large that the
///         frame time is 0).
Clip load_clip(const std::string& path, const LoadOptions& options = {});
/// load_clip of a file whose bytes were read already: `text` is the content of `path` (the
/// format from its extension, named in errors; an .amc's .asf is read from disk), so a caller
/// that checked those bytes (a saved map, its clips' SHA-256) parses exactly them.
Clip load_clip_text(const std::string& path, std::string_view text,
                    const LoadOptions& options = {});

}  // namespace motionmap::io
