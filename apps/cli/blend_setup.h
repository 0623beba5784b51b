#pragma once
// What the commands that blend poses from a map share (pose, synth, reach, inbetween): their map
// and blending options, and the blender they make from them — over a saved map (--map
// lib.mmap.h5: its clips read on demand and checked), or over the clips given, their map computed
// or read from a map CSV (--map map.csv). One definition, so every command blends alike.
#include <charconv>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

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

/// Where `blender`'s map ends, in words, for the notes on points moved to its edge: "farther
/// than the reach R from every sample", or on a gplvm map "where the GP's predictive variance
/// exceeds τ of its prior".
std::string outside_rule(const synth::MapBlender& blender);

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

/// `count` finite numbers separated by commas, or nothing.
template <int count>
std::optional<Eigen::Matrix<double, count, 1>> parse_numbers(const std::string& text) {
  Eigen::Matrix<double, count, 1> v;
  std::size_t begin = 0;
  for (int k = 0; k < count; ++k) {
    const std::size_t comma = k + 1 < count ? text.find(',', begin) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    const std::string_view part = std::string_view(text).substr(begin, comma - begin);
    const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), v[k]);
    if (part.empty() || ec != std::errc() || ptr != part.data() + part.size() ||
        !std::isfinite(v[k]))
      return std::nullopt;
    begin = comma + 1;
  }
  return v;
}

}  // namespace motionmap::cli
