#pragma once
// The map file's layout shared by its writer (layout.cpp) and its reader (read_map_file.cpp):
// who wrote the file (enums are spelled with the name tables beside them: kMetricNames,
// kSearchNames, kMapPathNames, kAxisNames). What is written where, and
// the version policy, is write_map_file() and docs/map-file.md.
#include <string>

#include "motionmap/core/names.h"
#include "motionmap/embed/embed.h"
#include "motionmap/pipeline/clip_map.h"

namespace motionmap::mapfile::detail {

/// The root attribute `generator`: "MotionMap <version>".
inline std::string generator_name() {
#ifdef MOTIONMAP_VERSION
  return std::string("MotionMap ") + MOTIONMAP_VERSION;
#else
  return "MotionMap";
#endif
}

}  // namespace motionmap::mapfile::detail
