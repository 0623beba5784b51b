#pragma once
// The map file's layout shared by its writer (layout.cpp) and its reader (read_map_file.cpp):
// the names its attributes spell enums with, and who wrote the file. What is written where, and
// the version policy, is write_map_file() and docs/map-file.md.
#include <string>

#include "motionmap/core/names.h"
#include "motionmap/embed/embed.h"
#include "motionmap/pipeline/clip_map.h"

namespace motionmap::mapfile::detail {

inline constexpr EnumName<Metric> kMetrics[] = {{Metric::Euclidean, "euclidean"},
                                                {Metric::QuaternionAngles, "quaternion-angles"}};
inline constexpr EnumName<embed::EmbedOptions::Search> kSearches[] = {
    {embed::EmbedOptions::Search::Auto, "auto"},
    {embed::EmbedOptions::Search::Exact, "exact"},
    {embed::EmbedOptions::Search::Approximate, "approximate"}};
inline constexpr EnumName<pipeline::MapPath> kPaths[] = {
    {pipeline::MapPath::Auto, "auto"},
    {pipeline::MapPath::Dense, "dense"},
    {pipeline::MapPath::Landmarks, "landmarks"}};
inline constexpr EnumName<Axis> kAxes[] = {{Axis::X, "x"}, {Axis::Y, "y"}, {Axis::Z, "z"}};

/// The root attribute `generator`: "MotionMap <version>".
inline std::string generator_name() {
#ifdef MOTIONMAP_VERSION
  return std::string("MotionMap ") + MOTIONMAP_VERSION;
#else
  return "MotionMap";
#endif
}

}  // namespace motionmap::mapfile::detail
