#pragma once
// What the commands that blend poses from a map share (pose, synth, reach, inbetween): their map
// and blending options, and the blender they make from them — over a saved map (--map
// lib.mmap.h5: its clips read on demand and checked), or over the clips given, their map computed
// or read from a map CSV (--map map.csv). One definition, so every command blends alike.
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "map_options.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/synth/blender.h"

namespace motionmap::cli {

struct BlendCliOptions {
  CLI::App* sub = nullptr;
  MapCliOptions map;
  std::string map_path;  ///< --map: a saved map or a map CSV
  synth::BlendMode blend = synth::BlendMode::Local;
  int neighbors = 12;
  double reach = 3.0;
};

/// Adds the map options (FILE… optional), --map, --blend, --neighbors and --reach to `sub`.
/// `map_help`: what --map says (the commands differ in whether a map CSV will do).
void add_blend_options(CLI::App* sub, BlendCliOptions& o, const std::string& map_help);

/// The blend options chosen, along the up axis `up` (the map's).
synth::BlendOptions blend_options(const BlendCliOptions& o, Axis up);

/// A blender and what it was made from.
struct PreparedBlender {
  std::unique_ptr<synth::MapBlender> blender;
  features::FeatureSet samples;
  std::vector<std::string> clip_paths;  ///< the clips' paths (a saved map's: as it records them)
  /// A saved map (--map lib.mmap.h5), else null.
  std::shared_ptr<const mapfile::SavedMap> saved;
  /// Otherwise the clips, their map (null when read from a map CSV) and its options.
  std::shared_ptr<const std::vector<Clip>> clips;
  std::shared_ptr<pipeline::ClipMap> map;
  pipeline::ClipMapOptions options;
};

/// The blender `o` asks for. With a saved map: the options it fixes (FILE…, the features, method
/// and frames) are usage errors, its read notes are printed, the local and idw modes read the
/// clips on demand (mapfile::make_blender) and kriging loads them all. `who` names the command in
/// the message for clips of several skeletons; `csv_allowed`: whether --map may be a map CSV.
/// @throws CLI::ValidationError for usage errors; what loading, mapping and blending throw.
PreparedBlender prepare_blender(const BlendCliOptions& o, const std::string& who,
                                bool csv_allowed = true);

}  // namespace motionmap::cli
