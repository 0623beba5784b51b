#pragma once
// Options shared by the commands that compute a map (map, figure, pose, synth), and the code
// that turns them into library calls.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "motionmap/core/control.h"
#include "motionmap/io/clip_inputs.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/labels.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::cli {

struct MapCliOptions {
  std::vector<std::string> files;
  std::string asf;
  double fps = 0.0;
  embed::Method method = embed::Method::Isomap;
  int dims = 2;
  int k = -1;  ///< −1: not given (20; umap 15)
  double min_dist = 0.1;
  int epochs = 0;            ///< 0: umap's default (500 up to 10 000 frames, 200 above)
  int max_iterations = 300;  ///< gplvm's L-BFGS iterations at most
  int inducing = 0;          ///< gplvm's inducing points; 0: full model ≤ 1 000 frames, 100 above
  double lengthscale = embed::EmbedOptions{}.lengthscale;  ///< gplvm's ℓ held; 0: fitted
  int seed = 0;
  std::string heat = "auto";
  double reg = 1e-3;
  bool standardize = false;
  bool strict = false;
  features::FeatureKind features = features::FeatureKind::Quaternions;
  features::DistanceKind distance = features::DistanceKind::PointCloud;
  std::string exclude;
  std::string frames;
  int stride = 1;
  bool keep_first = false;
  std::string up = "y";
  bool quiet = false;
  // Libraries of clips: folders and @lists as inputs, clips that fail to load, clips of
  // different skeletons.
  bool recursive = false;
  bool keep_going = false;
  features::JointSelection joints = features::JointSelection::All;
  // Which path (pipeline::MapPath) and how it reports.
  bool exact = false;
  int landmarks = -1;  ///< −1: not given (automatic path); 0: the default count; else L
  bool verbose = false;
  /// map only: pca and svd read the clips from their files one at a time, twice, instead of
  /// holding them and X (pipeline/stream_map.h); automatic when they would not fit.
  bool stream = false;
  // Labels (docs/labels.md): from the clips' file names and/or a CSV/JSON file; what the plot is
  // coloured by: time, clip or a label's name.
  std::string labels_from_name;
  std::string labels_file;
  std::string color_by = "time";
};

/// Which command the map options are for: `map` (all of them), `figure` (no --method: it runs
/// all six), `pose`/`synth` (where --neighbors is the blend's K and --fps the new motion's frame
/// rate, so the graph's k is -k only and the AMC input rate --amc-fps).
enum class MapOptionsFor { Map, Figure, Synthesis };

/// The values of an enum by their library names (embed::method_name, …), for CLI11's
/// CheckedTransformer: the command line accepts exactly the names the CSV and Studio write.
template <class E, class Name>
std::map<std::string, E> choices(const std::vector<E>& values, Name name) {
  std::map<std::string, E> out;
  for (E v : values) out[std::string(name(v))] = v;
  return out;
}

/// Adds the input files and the feature and method options to `sub`.
void add_map_options(CLI::App* sub, MapCliOptions& opt, MapOptionsFor use);

/// Loads every clip the inputs name (files, folders, @lists: io::expand_clip_inputs), printing
/// their warnings, and with --keep-going the errors of the clips skipped, on stderr.
/// @throws Error / ParseError (the first clip that fails without --keep-going, or every one).
std::vector<Clip> load_inputs(const MapCliOptions& opt);

/// The clip paths the inputs name (io::expand_clip_inputs with --recursive).
/// @throws as io::expand_clip_inputs().
std::vector<std::string> input_paths(const MapCliOptions& opt);

/// load_inputs() of the paths input_paths() gave; with `sha256`, each clip's SHA-256 taken of the
/// bytes parsed (Clip::sha256), for the map file of --save.
std::vector<Clip> load_inputs(const MapCliOptions& opt, const std::vector<std::string>& paths,
                              bool sha256 = false);

/// The io::load_clips() options of --asf, --amc-fps and --keep-going (and `sha256`, as above).
io::LoadClipsOptions load_options(const MapCliOptions& opt, bool sha256 = false);

/// What load_inputs() prints of a loading of `paths` clips: the clips' warnings, and the failures
/// skipped with --keep-going with a note counting them.
void print_loading(const std::vector<Clip>& clips, const std::vector<std::string>& failures,
                   std::size_t paths);

/// The clips' paths, in order (the CSV's files= list).
std::vector<std::string> clip_paths(const std::vector<Clip>& clips);

/// The clips' file names for a title: "a.bvh, b.bvh, c.bvh", or "a.bvh, b.bvh and 38 more clips".
std::string clip_names(const std::vector<Clip>& clips);

/// The library options for `method`.
/// @throws ParameterError for malformed --frames or --heat values.
pipeline::ClipMapOptions clip_map_options(const MapCliOptions& opt, embed::Method method,
                                          bool metrics);

/// A progress line on stderr ("isomap  42%  shortest paths"), or a silent Control when --quiet
/// or stderr is not a terminal.
Control progress_line(const MapCliOptions& opt, std::string_view label);

/// Adds --labels-from-name, --labels and --color-by (map and figure).
void add_label_options(CLI::App* sub, MapCliOptions& opt);

/// The labels --labels-from-name and --labels give the clips (both: the file's labels after the
/// names', so a label both give is the file's), with their notes printed on stderr; nullopt
/// when neither option is given. A --color-by that names no label is a usage error.
/// @throws ParameterError / ParseError as pipeline::labels_from_names() and read_label_file();
///   CLI::ValidationError for --color-by.
std::optional<pipeline::LabelTable> read_clip_labels(const MapCliOptions& opt,
                                                     const std::vector<Clip>& clips);

/// The labels of the samples of `set` (empty without a table).
pipeline::Labels labels_of(const std::optional<pipeline::LabelTable>& table,
                           const features::FeatureSet& set);

/// Colours `plot` as --color-by says: by time (as it is), or by the values of a label — a clip's
/// file name for `clip` (`clip_of`: each sample's clip) — at most render::kCategoryColors of them
/// (the most frequent, when there are more: the rest grey as "other", with a note on stderr),
/// each with its count in the legend (the value "" as "(none)"). Sets plot.time_legend.
void color_plot(render::MapPlotOptions& plot, const MapCliOptions& opt,
                const pipeline::Labels& labels, const std::vector<Clip>& clips,
                std::span<const int> clip_of);

/// The label accuracy lines of the metrics table ("label accuracy (10-NN vote among other
/// clips' frames): action map 0.912 features 0.950 (2040 frames)").
void print_label_accuracy(std::ostream& out, std::span<const pipeline::LabelAccuracy> accuracy);

/// Prints the notes and warnings of a map to stderr ("note: …", "warning: …").
void print_diagnostics(const pipeline::ClipMap& map);

}  // namespace motionmap::cli
