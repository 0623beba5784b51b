#pragma once
// A map as CSV: what `motionmap map` writes and `motionmap pose|synth --map` read back.
//
//   # motionmap map method=isomap dims=2 k=20 features=quat distance=pointcloud up=y
//   files=64_08.bvh # note: 64_08.bvh: frame 0 looks like a bind pose (…): left out (--keep-first
//   keeps it) frame,x,y                 ← `clip,frame,x,y` with several clips, `,z` in 3-D
//   1,-1.0734,0.2213
//
//   auto table = motionmap::embed::read_map_csv("map.csv");
//   table.check_matches(motionmap::features::select_samples(clips, options.features), "map.csv");
//
// Lines starting with '#' and blank lines are skipped; LF, CRLF and CR line ends are accepted.
// Coordinates are written with 17 significant digits, so a map read back is the map written.
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/labels.h"

namespace motionmap::pipeline {

struct MapTable {
  std::string path;                ///< the file (for messages)
  std::vector<int> clip_of;        ///< per row: clip index (all 0 when the file has no clip column)
  std::vector<int> frame_of;       ///< per row: the frame's index in its clip's file
  Eigen::MatrixXd coords;          ///< #rows by 2 or 3
  std::vector<std::size_t> lines;  ///< per row: its line in the file
  /// The label columns after the coordinates (write_map_csv with labels), one value per row.
  Labels labels;
  int num_rows() const { return static_cast<int>(frame_of.size()); }

  /// Checks that this table is a map of `samples` (as select_samples() or build_features()
  /// choose them from the clips): as many rows, each the same clip and frame.
  /// @throws ParameterError naming the file, and the first row (with its line) that differs.
  void check_matches(const features::FeatureSet& samples) const;
};

/// Writes `map` as CSV: a '#' line with the effective parameters and the input files' names,
/// '#' lines with the notes, warnings and metrics, the header, one row per sample. With
/// `labels`, one more column per label after the coordinates (`clip,frame,x,y,action,style`;
/// values quoted as csv_field() quotes them), and with `accuracy` a '# label accuracy' line.
void write_map_csv(std::ostream& out, const ClipMap& map, const ClipMapOptions& options,
                   std::span<const std::string> files, const Labels* labels = nullptr,
                   std::span<const LabelAccuracy> accuracy = {});

/// Parses map CSV text. `path` is only used in messages.
/// Columns after the coordinates are labels (MapTable::labels; quoted fields allowed).
/// @throws ParseError `path:line:col: error: …` for a missing or unknown header, a label column
///         that is not a label name or given twice, a row with
///         another field count, a clip or frame that is not an integer ≥ 0, a coordinate that is
///         not a finite number, or no rows.
MapTable parse_map_csv(std::string_view text, const std::string& path = "<memory>");

/// Reads and parses a map CSV file. @throws Error if unreadable, ParseError as above.
MapTable read_map_csv(const std::string& path);

}  // namespace motionmap::pipeline
