#pragma once
// Map files: a map saved with everything needed to read it back and to place new clips' frames
// on it without refitting (`motionmap map … --save lib.mmap.h5`, then `motionmap map NEW.bvh
// --onto lib.mmap.h5`). HDF5 on disk, so h5py, MATLAB and every HDF5 tool read it too; the
// layout (group and dataset names, shapes, types, version policy) is docs/map-file.md.
//
//   auto map = motionmap::pipeline::map_clips(clips, options);
//   motionmap::mapfile::MapFile file = motionmap::mapfile::make_map_file(clips, map, options);
//   motionmap::mapfile::write_map_file("lib.mmap.h5", file);
//   …
//   const auto saved = motionmap::mapfile::read_map_file("lib.mmap.h5");
//   const auto placed = motionmap::mapfile::place_clips(new_clips, saved);
//   // placed.coordinates row i ↔ new clip placed.features.clip_of[i], frame frame_of[i]
//
// A file of another format, of a layout version this library does not know, with a missing
// item, an item of the wrong shape or type, or values out of range (indices, non-finite numbers)
// is refused with an error naming the file and what was expected: what read_map_file() returns
// can be placed on without further checks.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/embed/placement.h"
#include "motionmap/features/features.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/labels.h"

namespace motionmap::mapfile {

/// The root attribute `format` of every map file.
inline constexpr std::string_view kFormatName = "motionmap-map";
/// The layout this library writes, and the newest it reads (root attribute `format_version`):
/// 3, with a checksum on every dataset and every object's attributes and no variable-length
/// strings. It reads 1 and 2 too (2: a map whose rows were placed on a model fitted on other
/// frames, placed_map_file), which have no checksums.
inline constexpr int kFormatVersion = 3;

/// One clip the map was made from.
struct ClipRecord {
  std::string path;         ///< as it was given (relative paths stay relative)
  std::string sha256;       ///< of the clip file's bytes (an .amc's, not its .asf's): 64 hex digits
  int frames = 0;           ///< frames in the file
  double frame_time = 0.0;  ///< seconds per frame
  int first_sample = 0;     ///< its first row of the map
  int samples = 0;          ///< how many rows of the map are its frames
};

/// The joints of the skeleton the map's first clip has (for checking a new clip against it).
struct SkeletonRecord {
  std::vector<std::string> names;
  std::vector<int> parents;    ///< −1 for a root
  std::vector<int> end_sites;  ///< End Sites per joint
};

/// What a blender reading the clips on demand needs to know of all of them together (the rest of
/// synth::ClipsSummary is in the clip records): recorded when the map is made from clips of one
/// joint hierarchy, so that `pose`/`synth --map` read only the clips they blend.
struct BlendRecord {
  int motion_root = 0;      ///< synth::MapBlender::motion_root() of the map's clips
  std::vector<int> moving;  ///< joints whose translation the blend averages, increasing
};

/// Everything a map file holds. make_map_file() fills it from a map; read_map_file() from a file.
struct MapFile {
  /// The file it was read from (for messages); empty for a map made in memory.
  std::string path;
  std::vector<ClipRecord> clips;
  /// Per map row (sample): its clip (index into `clips`) and its frame in that clip's file.
  std::vector<int> clip_of;
  std::vector<int> frame_of;

  /// The effective parameters as pipeline::describe_parameters() wrote them.
  std::string parameters;
  /// The options the map was made with (features, embed, path). embed.heat is nullopt when the
  /// heat was automatic; the width used is `heat_used`.
  pipeline::ClipMapOptions options;
  bool dense = true;            ///< the map took the dense path (from D), not the points path
  int k_used = 0;               ///< graph methods: neighbours per frame
  double heat_used = 0.0;       ///< le: heat-kernel width used
  int landmarks_used = 0;       ///< points path of mds and isomap: landmarks chosen (else 0)
  std::string neighbor_search;  ///< Embedding::neighbor_search
  int graph_components = 0;     ///< Embedding::graph_components
  int connecting_edges = 0;     ///< Embedding::connecting_edges
  /// The features' notes and the map's warnings, as the CSV's comments give them.
  std::vector<std::string> notes;
  std::vector<std::string> warnings;
  /// What reading the file found worth saying (a file without checksums); never written.
  std::vector<std::string> read_notes;

  SkeletonRecord skeleton;
  /// Absent for clips of several hierarchies, for a map of placed clips, and in files written
  /// before MotionMap recorded it (SavedMap::clips_summary() then reads every clip once).
  std::optional<BlendRecord> blend;
  /// The joints the features use (features::FeatureSet::joints, by name, in order): with
  /// quaternion features X holds their rotations, 4 columns per joint (w, x, y, z).
  std::vector<std::string> joints;
  /// JointSelection::Common: the joint names every mapped clip had (what the map compares by).
  std::vector<std::string> shared_joints;
  int x_columns = 0;      ///< columns of X
  int point_columns = 0;  ///< columns of the points D is computed from

  /// #samples by dims: the map (the CSV's x, y[, z]).
  Eigen::MatrixXd coordinates;
  /// The samples' labels (group /labels; none in files written without labels or before them).
  pipeline::Labels labels;
  /// What placing frames needs. Its samples are the map's rows (its `coordinates` equal the
  /// ones above), except in a map of placed clips (placed_map_file), where they are the frames
  /// the model was fitted on.
  embed::MapModel model;

  int num_samples() const { return static_cast<int>(clip_of.size()); }
};

/// The blend record of the map rows `samples` of `clips` (synth::summarize_clips), or nothing for
/// clips of several joint hierarchies or clips whose poses were freed (no frames held).
/// @throws ParameterError if `samples` does not index `clips`.
std::optional<BlendRecord> blend_record(std::span<const Clip> clips,
                                        const features::FeatureSet& samples);

/// The SHA-256 a map file records for `clip`: Clip::sha256, of the bytes that were parsed (a clip
/// loaded with io::LoadOptions::sha256); for a clip loaded without it or made in memory, of the
/// file at its path, read now. @throws Error if that file cannot be read.
std::string recorded_sha256(const Clip& clip);

/// The file record of `map`, a map_clips() result for `clips` with `options`: the clips' hashes
/// (recorded_sha256()), the parameters, the joints, the placement model
/// (pipeline::map_model, which takes the map's landmark fit: pass std::move(map) when done with
/// it, so that a 10⁶-frame landmark Isomap map's 2 GB of geodesic distances are not copied) and,
/// when the clips still hold their poses, the blend record (a caller that frees them first sets
/// MapFile::blend from blend_record()).
/// @throws Error if a clip file cannot be read for its hash; ParameterError if `map` is not a
///   map of `clips`; as embed::make_model().
MapFile make_map_file(std::span<const Clip> clips, pipeline::ClipMap map,
                      const pipeline::ClipMapOptions& options);

/// Writes `file` to `path` as HDF5 (docs/map-file.md), replacing what is there; a failed write
/// leaves no file. @throws Error naming the path.
void write_map_file(const std::string& path, const MapFile& file);

/// What read_map_file() reads.
struct ReadOptions {
  /// Read and check /model (what placing new frames needs). False leaves MapFile::model empty:
  /// for showing and blending a map (MotionMap Studio, `pose`/`synth --map`), whose model may be
  /// far larger than its coordinates (a landmark Isomap map of 10⁶ frames holds an L × N
  /// geodesic matrix; an LLE map every sample's X row). A gplvm map's model is read either way:
  /// its GP is its blends' and its validity's (SavedMap::gplvm()).
  bool model = true;
};

/// Reads and checks a map file. @throws Error naming the path and what was expected: missing
/// or unreadable, not HDF5, another format, a newer or unknown layout version, a missing group,
/// dataset or attribute, a wrong shape or element type, an unknown name (method, metric, …),
/// an index out of range, a non-finite value, a text that is not printable UTF-8, or data whose
/// checksum is not the one recorded (damage, naming the dataset). A file of layout 1 or 2 has no
/// checksums: MapFile::read_notes says so.
MapFile read_map_file(const std::string& path, const ReadOptions& options = {});

/// Whether `path` starts as a map file does (the structure checksum of layout 3, or HDF5's
/// signature: files of layouts 1 and 2), rather than as a map CSV. Reads 4 096 bytes at most; no
/// check of anything else.
bool looks_like_map_file(const std::string& path);

/// Which frames of the new clips place_clips() places (the map's own clips' selection was for
/// them). The feature definition (kind, distance, up axis, excluded and shared joints) always
/// comes from the map.
struct PlaceOptions {
  int first_frame = 0;      ///< first file frame placed (per clip)
  int end_frame = -1;       ///< one past the last; −1 = the clip's end
  int stride = 1;           ///< every stride-th frame
  bool keep_first = false;  ///< keep a leading bind pose (left out by default, with a note)
};

/// New frames on a saved map.
struct Placement {
  /// The new clips' samples: X and the points (no D), clip_of, frame_of, segment_starts, notes.
  features::FeatureSet features;
  /// #samples by dims: where each new frame lands.
  Eigen::MatrixXd coordinates;
};

/// Places every selected frame of `clips` on `map` without refitting it: builds their features
/// with the map's feature options, checks that they are comparable with the map's (joint
/// hierarchy, or for a --joints common map the shared joint names; the columns of X and of the
/// points), then embed::place() (with `search`, embed::make_search(map.model), when the caller
/// keeps one for placing many clips on the same map). A frame's place depends on that frame only.
/// @throws ParameterError naming the clip and what differs from the map (its skeleton, a joint
///   the map needs, the columns); as features::build_features() and embed::place(); Cancelled.
Placement place_clips(std::span<const Clip> clips, const MapFile& map,
                      const PlaceOptions& options = {}, const Control& control = {},
                      const embed::SampleSearch* search = nullptr);

/// One clip placed on a saved map, as a map of placed clips records it: what a Dask worker sends
/// back (motionmap.dask.map_library) and placed_map_file() gathers.
struct PlacedClip {
  /// Its path, SHA-256, frames and frame time (first_sample and samples are set when gathered).
  ClipRecord record;
  std::vector<int> frames;      ///< the file frame of each placed row
  Eigen::MatrixXd coordinates;  ///< where each of those frames landed (#frames by dims)
};

/// The PlacedClip of each of `clips` in `placement` (their place_clips() result), with the clip
/// files' SHA-256 (recorded_sha256()). @throws Error if a clip file cannot be read;
/// ParameterError if `placement` is not of `clips`.
std::vector<PlacedClip> placed_clips(std::span<const Clip> clips, const Placement& placement);

/// A map of clips placed on `fitted` without refitting it (`motionmap map LIB --onto
/// fitted.mmap.h5 --save lib.mmap.h5`, motionmap.dask.map_library(save=)): its rows are the
/// placed clips' frames, in order — what Studio draws and `pose`/`synth --map` blend — and its
/// parameters, skeleton, joints and model are `fitted`'s, so that placing a frame on it gives what
/// placing it on `fitted` gives. A note names `fitted_name` and how many frames the model was
/// fitted on. Layout version 2 when the model's samples are not as many as the rows.
/// @throws ParameterError for no clips, a clip without frames or with coordinates of another
///   shape than `fitted`'s dimensions.
MapFile placed_map_file(const MapFile& fitted, std::span<const PlacedClip> placed,
                        const std::string& fitted_name);

/// The map's Embedding as far as describe_parameters() and the CSV writer read it (method,
/// coordinates, k, heat, landmark count, neighbour search, components), with `coordinates` in
/// place of the map's. For writing placed frames in the map CSV format.
embed::Embedding embedding_for_csv(const MapFile& map, const Eigen::MatrixXd& coordinates);

}  // namespace motionmap::mapfile
