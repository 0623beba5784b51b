// The fitted maps behind the estimators of motionmap (PCA, …, LLE in motionmap/__init__.py):
//  - ClipMapState, a map of clips: map_clips() and the map file record (make_map_file), which is
//    also its pickled form (the map file's bytes) and what read_map/write_map read and write;
//    new clips are placed with mapfile::place_clips();
//  - MatrixMapState, a map of a matrix X (rows = frames, Euclidean distances between rows) or of
//    a precomputed D: embed::embed() and, for X, the placement model (embed::place()).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>

#include "common.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/features/features.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/frame_key.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/synth/inbetween.h"
#include "motionmap/synth/path_edit.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::python {

features::FeatureOptions feature_options(const py::dict& o);

namespace {

constexpr const char* kFeatureKeys[] = {"features", "distance", "joints", "up",
                                        "exclude",  "frames",   "stride", "keep_first"};

// The map options of the estimators' parameters (names as in motionmap/__init__.py).
pipeline::ClipMapOptions clip_map_options(const py::dict& o) {
  pipeline::ClipMapOptions out;
  out.features = feature_options(o);
  embed::EmbedOptions& e = out.embed;
  for (const auto& [key, value] : o) {
    const std::string k = key.cast<std::string>();
    if (k == "method") {
      const std::string name = value.cast<std::string>();
      const auto method = embed::parse_method(name);
      if (!method) {
        throw ParameterError("method: unknown name '" + name +
                             "' (expected one of pca, svd, mds, isomap, le, lle, umap, gplvm)");
      }
      e.method = *method;
    } else if (k == "n_components") {
      e.dimensions = value.cast<int>();
    } else if (k == "n_neighbors") {
      e.k = value.cast<int>();
    } else if (k == "heat") {
      if (!value.is_none()) e.heat = value.cast<double>();
    } else if (k == "reg") {
      e.reg = value.cast<double>();
    } else if (k == "min_dist") {
      e.min_dist = value.cast<double>();
    } else if (k == "n_epochs") {
      e.epochs = value.is_none() ? 0 : value.cast<int>();
    } else if (k == "random_state") {
      e.seed = value.is_none() ? 0 : value.cast<int>();
    } else if (k == "max_iter") {
      e.max_iterations = value.cast<int>();
      if (e.max_iterations < 1 || e.max_iterations > 100000) {
        throw ParameterError("max_iter: " + std::to_string(e.max_iterations) +
                             " is out of range; it must be in [1, 100000] (default 300)");
      }
    } else if (k == "n_inducing") {
      e.inducing = value.is_none() ? 0 : value.cast<int>();
      if (!value.is_none() && e.inducing < 1) {
        throw ParameterError("n_inducing: " + std::to_string(e.inducing) +
                             " is not a number of inducing points >= 1 (None: the full model up "
                             "to 1000 frames, 100 inducing points above)");
      }
    } else if (k == "lengthscale") {
      e.lengthscale = value.cast<double>();
      if (!(e.lengthscale >= 0.0 && std::isfinite(e.lengthscale))) {
        throw ParameterError("lengthscale: " + format_number(e.lengthscale) +
                             " is out of range; it must be a finite lengthscale > 0 (held "
                             "through the fit), or 0 to fit it");
      }
    } else if (k == "standardize") {
      e.standardize = value.cast<bool>();
    } else if (k == "strict") {
      e.strict = value.cast<bool>();
    } else if (k == "n_landmarks") {
      if (!value.is_none()) e.landmarks = value.cast<int>();
    } else if (k == "path") {
      const std::string path = value.cast<std::string>();
      const std::optional<pipeline::MapPath> parsed = pipeline::parse_map_path(path);
      if (!parsed) {
        throw ParameterError("path: unknown name '" + path +
                             "' (expected one of auto, dense, landmarks)");
      }
      out.path = *parsed;
    } else if (std::find(std::begin(kFeatureKeys), std::end(kFeatureKeys), k) ==
               std::end(kFeatureKeys)) {
      throw ParameterError("unknown option '" + k + "'");
    }
  }
  if (e.dimensions != 2 && e.dimensions != 3) {
    throw ParameterError("n_components: " + std::to_string(e.dimensions) +
                         " is not a map dimension (expected 2 or 3)");
  }
  return out;
}

// The estimator parameters of saved options (the inverse of clip_map_options, for read_map).
py::dict option_dict(const pipeline::ClipMapOptions& o) {
  py::dict d;
  const auto& e = o.embed;
  const auto& f = o.features;
  d["method"] = std::string(embed::method_name(e.method));
  d["n_components"] = e.dimensions;
  d["n_neighbors"] = e.k;
  d["heat"] = e.heat ? py::cast(*e.heat) : py::none();
  d["reg"] = e.reg;
  d["min_dist"] = e.min_dist;
  d["n_epochs"] = e.epochs > 0 ? py::cast(e.epochs) : py::none();
  d["random_state"] = e.seed;
  d["max_iter"] = e.max_iterations;
  d["n_inducing"] = e.inducing > 0 ? py::cast(e.inducing) : py::none();
  d["lengthscale"] = e.lengthscale;
  d["standardize"] = e.standardize;
  d["strict"] = e.strict;
  d["n_landmarks"] = e.landmarks;
  d["path"] = std::string(pipeline::map_path_name(o.path));
  d["features"] = std::string(features::feature_kind_name(f.features));
  d["distance"] = std::string(features::distance_kind_name(f.distance));
  d["joints"] = std::string(features::joint_selection_name(f.joints));
  d["up"] = std::string(axis_name(f.up));
  d["exclude"] = f.exclude.empty() ? py::none() : py::cast(f.exclude);
  d["frames"] = py::make_tuple(f.first_frame, f.end_frame < 0 ? py::none() : py::cast(f.end_frame));
  d["stride"] = f.stride;
  d["keep_first"] = f.keep_first;
  return d;
}

// A new, empty temporary file (mkstemps: a name no one else has), removed when this goes.
struct TempFile {
  std::string path;
  TempFile() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "motionmap-py-XXXXXX.mmap.h5").string();
    const int fd = mkstemps(pattern.data(), 8);  // 8: the length of ".mmap.h5"
    if (fd < 0) throw Error(pattern + ": error: cannot create a temporary file");
    close(fd);
    path = pattern;
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
};

// The nearest-sample search of a fitted map's placement model (embed::make_search), built by the
// first transform that needs it and kept: placing many clips on one map, as a Dask worker does
// one clip per task, pays the k-d tree over the samples once (about 1 s at 10⁵ samples). Not
// copyable, as the state it lives in: the search reads that state's model.
class SearchOnce {
 public:
  const embed::SampleSearch* get(const embed::MapModel& model, const Control& control) {
    std::call_once(m_once, [&] { m_search = embed::make_search(model, control); });
    return m_search.get();
  }

 private:
  std::once_flag m_once;
  std::unique_ptr<embed::SampleSearch> m_search;
};

// The library's check of EmbedOptions::inducing against the number of frames (known only once the
// frames are chosen) reported under the estimator's name for it, n_inducing.
template <typename Fn>
auto naming_n_inducing(Fn&& fn) {
  try {
    return fn();
  } catch (const ParameterError& e) {
    std::string what = e.what();
    const std::size_t at = what.find("inducing = ");
    if (at == std::string::npos) throw;
    // "gplvm: inducing = 500 is out of range; …, or 0 for the default (…)" in Python's terms.
    what = what.substr(at + 11);
    if (const std::size_t zero = what.find("or 0 for"); zero != std::string::npos) {
      what.replace(zero, 4, "or None");
    }
    throw ParameterError("n_inducing: " + what);
  }
}

// ---- maps of clips ----------------------------------------------------------------------------

struct ClipMapState {
  mapfile::MapFile file;
  /// The map as map_clips() made it, while it lives in the process that fitted it (for the CSV,
  /// which is the CLI's byte for byte); not pickled, not in a map file.
  std::optional<pipeline::ClipMap> map;
  /// The clips the map was fitted on, while it lives in the process that fitted it (pose
  /// synthesis blends them); a map read back or unpickled loads them again from `paths`.
  std::vector<Clip> clips;
  std::vector<std::string> paths;
  SearchOnce search;  ///< over file.model's samples
};

// The label table of `labels_from_name` (a file-name pattern) and `labels_file` (CSV or JSON)
// for `clips`, the file's labels after the names' (docs/labels.md); nullopt with neither.
std::optional<pipeline::LabelTable> clip_labels(const std::vector<Clip>& clips,
                                                const std::string& labels_from_name,
                                                const std::string& labels_file) {
  if (labels_from_name.empty() && labels_file.empty()) return std::nullopt;
  std::vector<std::string> paths;
  std::vector<int> frames;
  for (const Clip& clip : clips) {
    paths.push_back(clip.path);
    frames.push_back(clip.motion.num_frames);
  }
  pipeline::LabelTable table;
  if (!labels_from_name.empty()) {
    table = pipeline::labels_from_names(paths, pipeline::NamePattern(labels_from_name));
  }
  if (!labels_file.empty()) {
    pipeline::merge_labels(table, pipeline::read_label_file(labels_file, paths, frames),
                           labels_file);
  }
  return table;
}

std::shared_ptr<ClipMapState> fit_clips(const py::object& clips, const py::dict& options,
                                        const std::string& asf, double fps, py::object progress,
                                        const std::string& labels_from_name,
                                        const std::string& labels_file) {
  const pipeline::ClipMapOptions opts = clip_map_options(options);
  std::vector<Clip> loaded = clips_from_python(clips, asf, fps, /*sha256=*/true);
  auto state = std::make_shared<ClipMapState>();
  naming_n_inducing([&] {
    return run_released(std::move(progress), [&](const Control& control) {
      const std::optional<pipeline::LabelTable> table =
          clip_labels(loaded, labels_from_name, labels_file);
      state->map = pipeline::map_clips(loaded, opts, control);
      state->file = mapfile::make_map_file(loaded, *state->map, opts);
      if (table) {
        state->file.labels =
            pipeline::sample_labels(*table, state->file.clip_of, state->file.frame_of);
      }
      return 0;
    });
  });
  for (const Clip& c : loaded) state->paths.push_back(c.path);
  state->clips = std::move(loaded);
  return state;
}

// ---- poses and motions from map points (inverse_transform, synthesize) ------------------------

// A blender over the map's clips: the fitted clips, or (a map read back or unpickled) its clips
// loaded again from their recorded paths and checked to give the map's samples. Call with the
// GIL released.
// A gplvm map's GP is its rule of where it is valid, and with `default_mode` (blend=None in
// Python) its blends are the GP's predictive mean (the gp mode).
synth::MapBlender make_blender(const ClipMapState& s, const synth::BlendOptions& blend,
                               bool default_mode, const Control& control,
                               features::FeatureSet* samples_out = nullptr) {
  if (s.file.coordinates.cols() != 2) {
    throw ParameterError("poses are blended on 2-D maps; this map has " +
                         std::to_string(s.file.coordinates.cols()) + " dimensions");
  }
  std::vector<Clip> reloaded;
  if (s.clips.empty()) {
    for (const auto& path : s.paths) reloaded.push_back(io::load_clip(path));
  }
  const std::vector<Clip>& clips = s.clips.empty() ? reloaded : s.clips;
  for (const Clip& clip : clips) {
    if (const std::string why = features::hierarchy_difference(clips.front(), clip); !why.empty())
      throw ParameterError(clip.path + ": its joint hierarchy differs from " + clips.front().path +
                           "'s (" + why + "); poses are blended from clips of one skeleton");
  }
  features::FeatureSet samples;
  if (s.map) {
    samples = *s.map->features;
  } else {
    samples = features::select_samples(clips, s.file.options.features);
    if (samples.clip_of != s.file.clip_of || samples.frame_of != s.file.frame_of) {
      throw ParameterError(
          "the clips at the map's paths no longer give its samples (a clip changed or moved "
          "since the map was made): poses cannot be blended from them");
    }
  }
  synth::BlendOptions options = blend;
  options.up = s.file.options.features.up;
  options.gplvm = s.map ? pipeline::map_gplvm(*s.map) : nullptr;
  if (!options.gplvm) options.gplvm = embed::gplvm_map(s.file.model, s.file.coordinates);
  if (options.gplvm && default_mode) options.mode = synth::BlendMode::Gp;
  synth::MapBlender blender(clips, samples, s.file.coordinates, options, control);
  if (samples_out) *samples_out = std::move(samples);
  return blender;
}

synth::BlendOptions blend_options(const std::string& mode, int neighbors, double reach) {
  synth::BlendOptions b;
  // "": the map's default (local; gp on a gplvm map, make_blender).
  const auto parsed = mode.empty() ? synth::BlendMode::Local : synth::parse_blend_mode(mode);
  if (!parsed) {
    throw ParameterError("blend: unknown name '" + mode +
                         "' (expected one of local, kriging, idw, gp)");
  }
  b.mode = *parsed;
  b.neighbors = neighbors;
  b.reach = reach;
  return b;
}

std::vector<Eigen::Vector2d> map_points(const InputArray& array, const std::string& what) {
  const RowMatrix p = to_row_matrix(array, what);
  if (p.cols() != 2) {
    throw ParameterError(what + ": expected #points by 2 map coordinates, got " +
                         std::to_string(p.cols()) + " columns");
  }
  std::vector<Eigen::Vector2d> out;
  for (Eigen::Index i = 0; i < p.rows(); ++i) out.emplace_back(p(i, 0), p(i, 1));
  return out;
}

Clip poses_at(const ClipMapState& s, const InputArray& Y, const std::string& mode, int neighbors,
              double reach, py::object progress) {
  const std::vector<Eigen::Vector2d> points = map_points(Y, "Y");
  return run_released(std::move(progress), [&](const Control& control) {
    const synth::MapBlender blender = make_blender(s, blend_options(mode, neighbors, reach),
                                                   mode.empty(), control.part(0.0, 0.5));
    Clip out;
    out.path = "<poses at " + std::to_string(points.size()) + " map points>";
    out.skeleton = blender.skeleton();
    const int joints = out.skeleton.num_joints();
    out.motion.resize(static_cast<int>(points.size()), joints);
    out.motion.frame_time = blender.frame_time();
    const Control part = control.part(0.5, 1.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Motion pose = blender.pose_at(points[i]);
      for (int j = 0; j < joints; ++j) {
        out.motion.rotation(static_cast<int>(i), j) = pose.rotation(0, j);
        out.motion.translation(static_cast<int>(i), j) = pose.translation(0, j);
      }
      part.update(double(i + 1) / double(points.size()));
    }
    part.finish();
    return out;
  });
}

// A path of map points (`xy_name`: #points by 2) and their times (`times_name`; None: untimed).
synth::MapPath map_path(const InputArray& xy, const py::object& times, const std::string& xy_name,
                        const std::string& times_name) {
  synth::MapPath path;
  path.points = map_points(xy, xy_name);
  if (!times.is_none()) {
    path.times = times.cast<std::vector<double>>();
    if (path.times.size() != path.points.size()) {
      throw ParameterError(times_name + ": " + std::to_string(path.times.size()) + " times for " +
                           std::to_string(path.points.size()) + " path points");
    }
  }
  return path;
}

// A synthesized clip's warnings: frames of its path outside the map's data, and the result's
// notes (a gait whose legs stalled, feet out of reach, …).
void warn_synthesized(Clip& clip, const synth::SynthResult& result) {
  if (result.clamped_frames > 0) {
    clip.warnings.push_back(
        std::to_string(result.clamped_frames) +
        " frames were outside the map's data: " + synth::outside_frames_note(result));
  }
  clip.warnings.insert(clip.warnings.end(), result.notes.begin(), result.notes.end());
}

// The options of synthesize and edit_path, checked.
synth::SynthOptions synth_options(double speed, double fps, double smooth, bool clean_feet) {
  synth::SynthOptions options;
  options.speed = speed;
  options.fps = fps;
  options.smooth = smooth;
  options.clean_feet = clean_feet;
  options.validate();
  return options;
}

Clip synthesize_path(const ClipMapState& s, const InputArray& path_xy, const py::object& times,
                     double speed, double fps, double smooth, const std::string& mode,
                     int neighbors, double reach, bool clean_feet, py::object progress) {
  const synth::MapPath path = map_path(path_xy, times, "path_xy", "times");
  const synth::SynthOptions options = synth_options(speed, fps, smooth, clean_feet);
  return run_released(std::move(progress), [&](const Control& control) {
    const synth::MapBlender blender = make_blender(s, blend_options(mode, neighbors, reach),
                                                   mode.empty(), control.part(0.0, 0.3));
    synth::SynthResult result = synth::synthesize(blender, path, options, control.part(0.3, 1.0));
    Clip out;
    out.path = "<motion along a path of " + std::to_string(path.points.size()) + " points>";
    out.skeleton = blender.skeleton();
    out.motion = std::move(result.motion);
    warn_synthesized(out, result);
    return out;
  });
}

// motionmap.edit_path: the take along previous_xy re-made only where path_xy differs from it
// (synth::edit_path from the previous path). Returns (Clip, window).
py::tuple edit_path(const ClipMapState& s, const InputArray& previous_xy,
                    const py::object& previous_times, const InputArray& path_xy,
                    const py::object& times, double speed, double fps, double smooth,
                    const std::string& mode, int neighbors, double reach, bool clean_feet,
                    py::object progress) {
  const synth::MapPath previous =
      map_path(previous_xy, previous_times, "previous_xy", "previous_times");
  const synth::MapPath path = map_path(path_xy, times, "path_xy", "times");
  const synth::SynthOptions options = synth_options(speed, fps, smooth, clean_feet);
  Clip out;
  synth::PathEditResult edit = run_released(std::move(progress), [&](const Control& control) {
    const synth::MapBlender blender = make_blender(s, blend_options(mode, neighbors, reach),
                                                   mode.empty(), control.part(0.0, 0.3));
    out.skeleton = blender.skeleton();
    return synth::edit_path(blender, previous, path, options, {}, control.part(0.3, 1.0));
  });
  out.path = "<motion along an edited path of " + std::to_string(path.points.size()) + " points>";
  out.motion = std::move(edit.result.motion);
  warn_synthesized(out, edit.result);
  py::dict window;
  window["first"] = edit.first;
  window["end"] = edit.end;
  window["blend_first"] = edit.blend_first;
  window["blend_end"] = edit.blend_end;
  window["whole"] = edit.whole;
  window["feet_frames_changed"] = edit.result.feet_frames_changed;
  return py::make_tuple(std::move(out), std::move(window));
}

// ---- in-betweening (motionmap.inbetween) -----------------------------------------------------

// A key as Python gives it: (clip, frame) with a clip path or Clip, or (x, y) a map point.
struct PyKey {
  std::optional<Clip> clip;
  int frame = 0;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  std::string label;
};

// `map_clips`: the map's clip paths, which a key's clip path that is no file names
// (mapfile::map_clip_named: "walk.bvh" for takes/walk.bvh).
std::vector<PyKey> keys_from_python(const py::sequence& keys, const std::string& asf, double fps,
                                    const std::vector<std::string>& map_clips) {
  std::vector<PyKey> out;
  const py::module_ os = py::module_::import("os");
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const py::object item = keys[i];
    const std::string where = "keys[" + std::to_string(i) + "]";
    if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) ||
        py::len(item) != 2) {
      throw ParameterError(where +
                           ": a key is (clip, frame) — a clip path or Clip and a frame "
                           "from 0 — or (x, y), a map point");
    }
    const py::sequence pair = item.cast<py::sequence>();
    const py::object first = pair[0];
    PyKey key;
    if (py::isinstance<py::str>(first) || py::hasattr(first, "__fspath__") ||
        py::isinstance<Clip>(first)) {
      py::list one;
      one.append(first);
      if (!py::isinstance<Clip>(first)) {
        const std::string path = os.attr("fspath")(first).cast<std::string>();
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) {  // as the CLI's --keys
          try {
            one[0] = py::str(mapfile::map_clip_named(map_clips, path));
          } catch (const ParameterError& e) {
            throw ParameterError(where + ": " + e.what());
          }
        }
      }
      std::vector<Clip> loaded = clips_from_python(one, asf, fps);
      key.clip = std::move(loaded.front());
      key.frame = pair[1].cast<int>();
      key.label = key.clip->path + ":" + std::to_string(key.frame);
    } else {
      key.point = Eigen::Vector2d(pair[0].cast<double>(), pair[1].cast<double>());
      key.label = where;
    }
    out.push_back(std::move(key));
  }
  return out;
}

struct InbetweenOut {
  Clip clip;
  synth::InbetweenResult result;
};

py::tuple inbetween_keys(ClipMapState& s, const py::sequence& key_items, const py::object& times,
                         int frames_between, const std::string& route, int grid, bool smooth,
                         const std::string& mode, int neighbors, double reach,
                         const std::string& asf, double fps, bool clean_feet, bool free_roots,
                         py::object progress) {
  std::vector<PyKey> keys = keys_from_python(key_items, asf, fps, s.paths);
  std::vector<double> key_times;
  if (!times.is_none()) {
    key_times = times.cast<std::vector<double>>();
    if (key_times.size() != keys.size()) {
      throw ParameterError("times: " + std::to_string(key_times.size()) + " times for " +
                           std::to_string(keys.size()) + " keys");
    }
  }
  synth::InbetweenOptions options;
  options.frames_between = frames_between;
  options.route.mode = synth::parse_route_mode(route);
  options.route.grid = grid;
  options.route.smooth = smooth;
  options.clean_feet = clean_feet;
  options.free_roots = free_roots;
  options.validate();
  InbetweenOut out = run_released(std::move(progress), [&](const Control& control) {
    features::FeatureSet samples;
    const synth::MapBlender blender = make_blender(s, blend_options(mode, neighbors, reach),
                                                   mode.empty(), control.part(0.0, 0.2), &samples);
    Clip reference;
    reference.path = s.paths.empty() ? std::string("the map") : s.paths.front();
    reference.skeleton = blender.skeleton();
    mapfile::KeyMap on;
    on.blender = &blender;
    on.samples = &samples;
    on.clip_files = s.paths;
    on.reference = &reference;
    on.map_file = [&s]() -> const mapfile::MapFile& { return s.file; };
    on.search = [&s] { return s.search.get(s.file.model, Control()); };
    std::vector<synth::Key> resolved;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      PyKey& k = keys[i];
      synth::Key key;
      if (k.clip) {
        try {
          key = mapfile::frame_key(on, *k.clip, k.frame).key;
        } catch (const ParameterError& e) {
          throw ParameterError("keys[" + std::to_string(i) + "] (" + k.label + "): " + e.what());
        }
      } else {
        key.point = k.point;
      }
      key.label = k.label;
      if (!key_times.empty()) key.time = key_times[i];
      resolved.push_back(std::move(key));
    }
    InbetweenOut o;
    o.result = synth::inbetween(blender, samples, resolved, options, control.part(0.2, 1.0));
    o.clip.path = "<in-between of " + std::to_string(keys.size()) + " keys>";
    o.clip.skeleton = blender.skeleton();
    o.clip.motion = o.result.motion;
    if (o.result.outside_frames > 0) {
      o.clip.warnings.push_back(std::to_string(o.result.outside_frames) +
                                " frames lie outside the map's data (a key outside it)");
    }
    o.clip.warnings.insert(o.clip.warnings.end(), o.result.notes.begin(), o.result.notes.end());
    return o;
  });
  const synth::InbetweenResult& r = out.result;
  Eigen::MatrixXd points(static_cast<Eigen::Index>(r.points.size()), 2);
  std::vector<bool> valid;
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    points.row(static_cast<Eigen::Index>(k)) = r.points[k].transpose();
    valid.push_back(!r.validity[k].clamped);
  }
  std::vector<Eigen::MatrixXd> routes;
  for (const auto& route : r.routes) {
    Eigen::MatrixXd m(static_cast<Eigen::Index>(route.size()), 2);
    for (std::size_t i = 0; i < route.size(); ++i)
      m.row(static_cast<Eigen::Index>(i)) = route[i].transpose();
    routes.push_back(std::move(m));
  }
  py::dict info;
  info["points"] = points;
  info["key_frames"] = r.key_frames;
  info["routes"] = routes;
  info["valid"] = valid;
  info["grid"] = py::make_tuple(r.grid.nx, r.grid.ny);
  return py::make_tuple(std::move(out.clip), info);
}

// `loaded` placed on the map, the frames chosen by the estimator's frame options.
mapfile::Placement place_loaded(ClipMapState& s, const std::vector<Clip>& loaded,
                                const py::dict& options, py::object progress) {
  const features::FeatureOptions f = feature_options(options);
  mapfile::PlaceOptions place;
  place.first_frame = f.first_frame;
  place.end_frame = f.end_frame;
  place.stride = f.stride;
  place.keep_first = f.keep_first;
  return run_released(std::move(progress), [&](const Control& control) {
    const embed::SampleSearch* search =
        s.search.get(s.file.model, control.stage("search", 0.0, 0.3));
    return mapfile::place_clips(loaded, s.file, place, control.part(0.3, 1.0), search);
  });
}

Eigen::MatrixXd transform_clips(ClipMapState& s, const py::object& clips, const py::dict& options,
                                const std::string& asf, double fps, py::object progress) {
  const std::vector<Clip> loaded = clips_from_python(clips, asf, fps);
  return place_loaded(s, loaded, options, std::move(progress)).coordinates;
}

// The clips placed, with their records (path, SHA-256, frames): what a Dask task sends back for
// the map file of the whole library (write_placed_map).
std::vector<mapfile::PlacedClip> place_clip_records(ClipMapState& s, const py::object& clips,
                                                    const py::dict& options, const std::string& asf,
                                                    double fps, py::object progress) {
  const std::vector<Clip> loaded = clips_from_python(clips, asf, fps, /*sha256=*/true);
  const mapfile::Placement placed = place_loaded(s, loaded, options, std::move(progress));
  py::gil_scoped_release release;
  return mapfile::placed_clips(loaded, placed);
}

void write_csv(const ClipMapState& s, const py::object& path) {
  if (!s.map) {
    throw Error(
        "write_csv: this map was read from a map file or unpickled; the CSV is written by the "
        "process that fitted it (the map file holds the coordinates: coordinates, write_map)");
  }
  const std::string out = py::str(py::module_::import("os").attr("fspath")(path));
  py::gil_scoped_release release;
  std::ofstream file(out);
  if (!file) throw Error(out + ": error: cannot open for writing");
  pipeline::write_map_csv(file, *s.map, s.file.options, s.paths,
                          s.file.labels.empty() ? nullptr : &s.file.labels);
  if (!file.flush()) throw Error(out + ": error: write failed");
}

// The labels as a dict of label name → numpy array of str objects, one per map row (what
// pandas.DataFrame(labels) takes as columns).
py::dict labels_dict(const pipeline::Labels& labels) {
  py::dict out;
  const py::module_ np = py::module_::import("numpy");
  for (const pipeline::LabelColumn& column : labels.columns) {
    std::vector<py::str> values;
    for (const std::string& v : column.categories) values.emplace_back(v);
    py::list rows(column.codes.size());
    for (std::size_t i = 0; i < column.codes.size(); ++i) {
      rows[i] = values[std::size_t(column.codes[i])];
    }
    out[py::str(column.name)] = np.attr("array")(rows, py::arg("dtype") = "object");
  }
  return out;
}

// The label accuracy of the fitted map (pipeline::label_accuracy): {label: {"map": …,
// "features": …, "queries": …, "k": …}}.
py::dict label_accuracy_dict(const ClipMapState& s, int k, int sample) {
  if (!s.map) {
    throw Error(
        "label_accuracy: this map was read from a map file or unpickled; the feature space it "
        "compares with is in the process that fitted it");
  }
  std::vector<pipeline::LabelAccuracy> accuracy;
  {
    py::gil_scoped_release release;
    std::shared_ptr<const features::FeatureSet> set = s.map->features;
    if (!set->has_distances() && set->distance_input.rows() != set->num_samples()) {
      throw Error("label_accuracy: the map's features were not kept");
    }
    accuracy =
        pipeline::label_accuracy(*set, s.map->embedding.coordinates, s.file.labels, k, sample);
  }
  py::dict out;
  for (const pipeline::LabelAccuracy& a : accuracy) {
    py::dict entry;
    entry["map"] = a.map;
    entry["features"] = a.features;
    entry["queries"] = a.queries;
    entry["k"] = a.k;
    out[py::str(a.label)] = entry;
  }
  return out;
}

py::bytes map_file_bytes(const ClipMapState& s) {
  std::string bytes;
  {
    py::gil_scoped_release release;
    TempFile tmp;
    mapfile::write_map_file(tmp.path, s.file);
    bytes = read_text_file(tmp.path);
  }
  return py::bytes(bytes);
}

std::shared_ptr<ClipMapState> state_from_bytes(const std::string& bytes, const std::string& path) {
  auto s = std::make_shared<ClipMapState>();
  {
    py::gil_scoped_release release;
    TempFile tmp;
    {
      std::ofstream out(tmp.path, std::ios::binary);
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      if (!out.flush()) throw Error(tmp.path + ": error: write failed");
    }
    s->file = mapfile::read_map_file(tmp.path);
  }
  s->file.path = path;
  for (const auto& c : s->file.clips) s->paths.push_back(c.path);
  return s;
}

// ---- maps of matrices -------------------------------------------------------------------------

struct MatrixMapState {
  embed::EmbedOptions options;
  embed::Embedding embedding;
  bool precomputed = false;  ///< fitted from D: nothing to place new frames with
  embed::MapModel model;
  int columns = 0;    ///< of X
  SearchOnce search;  ///< over model's samples
};

std::shared_ptr<MatrixMapState> fit_matrix(const InputArray& array, bool precomputed,
                                           const py::dict& options, py::object progress) {
  const pipeline::ClipMapOptions opts = clip_map_options(options);
  const RowMatrix rows = to_row_matrix(array, precomputed ? "D" : "X");
  auto s = std::make_shared<MatrixMapState>();
  s->options = opts.embed;
  s->precomputed = precomputed;
  s->columns = static_cast<int>(rows.cols());
  if (opts.embed.method == embed::Method::Gplvm && opts.embed.inducing > rows.rows()) {
    throw ParameterError("n_inducing: " + std::to_string(opts.embed.inducing) +
                         " is out of range; it must be in [1, " + std::to_string(rows.rows()) +
                         "] (the number of frames), or None for the default");
  }
  run_released(std::move(progress), [&](const Control& control) {
    if (precomputed) {
      if (!embed::reads_distances(opts.embed.method)) {
        throw ParameterError(std::string(embed::method_name(opts.embed.method)) +
                             " reads X, not distances: metric='precomputed' is for mds, isomap "
                             "and le");
      }
      if (opts.embed.method == embed::Method::Lle) {
        throw ParameterError(
            "lle reads X for its weights: metric='precomputed' is for mds, "
            "isomap and le");
      }
      const Eigen::MatrixXd D = rows;
      s->embedding = embed::embed({.distances = &D}, opts.embed, control);
      return 0;
    }
    const Eigen::MatrixXd X = rows;
    const bool dense = opts.path == pipeline::MapPath::Dense ||
                       (opts.path == pipeline::MapPath::Auto && rows.rows() <= opts.dense_limit);
    embed::EmbedInput input{.features = &X, .points = &rows};
    Eigen::MatrixXd D;
    if (dense && embed::reads_distances(opts.embed.method)) {
      if (!rows.allFinite()) throw ParameterError("X holds NaN or infinite values");
      D = features::pairwise_distances(rows, control.stage("pose distances", 0.0, 0.2));
      input.distances = &D;
    }
    s->embedding = embed::embed(input, opts.embed, control.part(0.2, 1.0));
    s->model = embed::make_model(input, opts.embed, s->embedding);
    return 0;
  });
  return s;
}

Eigen::MatrixXd transform_matrix(MatrixMapState& s, const InputArray& array, py::object progress) {
  if (s.precomputed) {
    throw ParameterError(
        "transform: a map fitted from precomputed distances cannot place new frames (it has no "
        "points to measure them against); fit it from X or from clips");
  }
  const RowMatrix rows = to_row_matrix(array, "X");
  if (rows.cols() != s.columns) {
    throw ParameterError("X has " + std::to_string(rows.cols()) +
                         " columns; the map was fitted on " + std::to_string(s.columns));
  }
  return run_released(std::move(progress), [&](const Control& control) {
    const Eigen::MatrixXd X = rows;
    const embed::SampleSearch* search = s.search.get(s.model, control.stage("search", 0.0, 0.3));
    return embed::place(s.model, {.features = &X, .points = &rows}, control.part(0.3, 1.0), search);
  });
}

// The pickled state of a matrix map: plain Python values and numpy arrays.
py::dict landmark_state(const embed::LandmarkFit& l) {
  py::dict d;
  d["frames"] = l.frames;
  d["projection"] = l.projection;
  d["mean_squared"] = l.mean_squared;
  d["offset"] = l.offset;
  d["geodesic"] = l.geodesic;
  return d;
}

embed::LandmarkFit landmark_from(const py::dict& d) {
  embed::LandmarkFit l;
  l.frames = d["frames"].cast<std::vector<int>>();
  l.projection = d["projection"].cast<Eigen::MatrixXd>();
  l.mean_squared = d["mean_squared"].cast<Eigen::VectorXd>();
  l.offset = d["offset"].cast<Eigen::VectorXd>();
  l.geodesic = d["geodesic"].cast<Eigen::MatrixXd>();
  return l;
}

py::tuple matrix_state(const MatrixMapState& s) {
  py::dict o;
  o["method"] = std::string(embed::method_name(s.options.method));
  o["n_components"] = s.options.dimensions;
  o["n_neighbors"] = s.options.k;
  o["heat"] = s.options.heat ? py::cast(*s.options.heat) : py::none();
  o["reg"] = s.options.reg;
  o["min_dist"] = s.options.min_dist;
  o["n_epochs"] = s.options.epochs > 0 ? py::cast(s.options.epochs) : py::none();
  o["random_state"] = s.options.seed;
  o["max_iter"] = s.options.max_iterations;
  o["n_inducing"] = s.options.inducing > 0 ? py::cast(s.options.inducing) : py::none();
  o["lengthscale"] = s.options.lengthscale;
  o["standardize"] = s.options.standardize;
  o["strict"] = s.options.strict;
  o["n_landmarks"] = s.options.landmarks;
  py::dict e;
  e["coordinates"] = s.embedding.coordinates;
  e["eigenvalues"] = s.embedding.eigenvalues;
  e["k_used"] = s.embedding.k_used;
  e["heat_used"] = s.embedding.heat_used;
  e["warnings"] = s.embedding.warnings;
  e["from_points"] = s.embedding.from_points;
  py::dict m;
  const embed::MapModel& mm = s.model;
  m["method"] = std::string(embed::method_name(mm.method));
  m["dimensions"] = mm.dimensions;
  m["coordinates"] = mm.coordinates;
  m["mean"] = Eigen::VectorXd(mm.mean.transpose());
  m["scale"] = Eigen::VectorXd(mm.scale.transpose());
  m["axes"] = mm.axes;
  m["points"] = Eigen::MatrixXd(mm.points);
  m["metric"] = mm.metric == Metric::Euclidean ? 0 : 1;
  m["points_are_landmarks"] = mm.points_are_landmarks;
  m["k"] = mm.k;
  m["landmarks"] = mm.landmarks ? py::object(landmark_state(*mm.landmarks)) : py::none();
  m["graph"] = py::make_tuple(mm.graph.offsets, mm.graph.targets, mm.graph.weights);
  m["heat"] = mm.heat;
  m["eigenvalues"] = mm.eigenvalues;
  m["features"] = Eigen::MatrixXd(mm.features);
  m["reg"] = mm.reg;
  if (mm.method == embed::Method::Gplvm) {
    const embed::GplvmPredictive& p = mm.gplvm;
    py::dict g;
    g["basis"] = p.basis;
    g["alpha"] = p.alpha;
    g["C"] = p.C;
    g["rbf_variance"] = p.rbf_variance;
    g["lengthscale"] = p.lengthscale;
    g["bias_variance"] = p.bias_variance;
    g["prior_variance"] = p.prior_variance;
    m["gplvm"] = g;
  }
  return py::make_tuple(1, o, e, m, s.precomputed, s.columns);
}

std::shared_ptr<MatrixMapState> matrix_from_state(const py::tuple& t) {
  if (t.size() != 6 || t[0].cast<int>() != 1)
    throw Error("unpickling a matrix map: unknown state layout");
  auto s = std::make_shared<MatrixMapState>();
  py::dict o = t[1];
  s->options = clip_map_options(o).embed;
  py::dict e = t[2];
  s->embedding.method = s->options.method;
  s->embedding.coordinates = e["coordinates"].cast<Eigen::MatrixXd>();
  s->embedding.eigenvalues = e["eigenvalues"].cast<Eigen::VectorXd>();
  s->embedding.k_used = e["k_used"].cast<int>();
  s->embedding.heat_used = e["heat_used"].cast<double>();
  s->embedding.warnings = e["warnings"].cast<std::vector<std::string>>();
  s->embedding.from_points = e["from_points"].cast<bool>();
  py::dict m = t[3];
  embed::MapModel& mm = s->model;
  mm.method = *embed::parse_method(m["method"].cast<std::string>());
  mm.dimensions = m["dimensions"].cast<int>();
  mm.coordinates = m["coordinates"].cast<Eigen::MatrixXd>();
  mm.mean = m["mean"].cast<Eigen::VectorXd>().transpose();
  mm.scale = m["scale"].cast<Eigen::VectorXd>().transpose();
  mm.axes = m["axes"].cast<Eigen::MatrixXd>();
  mm.points = m["points"].cast<Eigen::MatrixXd>();
  mm.metric = m["metric"].cast<int>() == 0 ? Metric::Euclidean : Metric::QuaternionAngles;
  mm.points_are_landmarks = m["points_are_landmarks"].cast<bool>();
  mm.k = m["k"].cast<int>();
  if (!m["landmarks"].is_none()) mm.landmarks = landmark_from(m["landmarks"]);
  const py::tuple g = m["graph"];
  mm.graph.offsets = g[0].cast<std::vector<int>>();
  mm.graph.targets = g[1].cast<std::vector<int>>();
  mm.graph.weights = g[2].cast<std::vector<double>>();
  mm.heat = m["heat"].cast<double>();
  mm.eigenvalues = m["eigenvalues"].cast<Eigen::VectorXd>();
  mm.features = m["features"].cast<Eigen::MatrixXd>();
  mm.reg = m["reg"].cast<double>();
  if (m.contains("gplvm")) {
    const py::dict g = m["gplvm"];
    embed::GplvmPredictive& p = mm.gplvm;
    p.basis = g["basis"].cast<Eigen::MatrixXd>();
    p.alpha = g["alpha"].cast<Eigen::MatrixXd>();
    p.C = g["C"].cast<Eigen::MatrixXd>();
    p.rbf_variance = g["rbf_variance"].cast<double>();
    p.lengthscale = g["lengthscale"].cast<double>();
    p.bias_variance = g["bias_variance"].cast<double>();
    p.prior_variance = g["prior_variance"].cast<double>();
  } else if (mm.method == embed::Method::Gplvm) {
    throw Error("unpickling a matrix map: a gplvm map without its GP's predictive");
  }
  s->precomputed = t[4].cast<bool>();
  s->columns = t[5].cast<int>();
  return s;
}

}  // namespace

void bind_maps(py::module_& m) {
  // The default of synthesize()/edit_path()'s smooth=, one definition with the library's.
  m.attr("default_smooth_seconds") = synth::kDefaultSmoothSeconds;
  py::class_<ClipMapState, std::shared_ptr<ClipMapState>>(
      m, "_ClipMap", "A fitted map of clips (the state of a fitted estimator).")
      .def_property_readonly("coordinates",
                             [](const ClipMapState& s) { return s.file.coordinates; })
      .def_property_readonly("eigenvalues",
                             [](const ClipMapState& s) {
                               return s.map ? s.map->embedding.eigenvalues : Eigen::VectorXd();
                             })
      .def_property_readonly("clip_of", [](const ClipMapState& s) { return s.file.clip_of; })
      .def_property_readonly("frame_of", [](const ClipMapState& s) { return s.file.frame_of; })
      .def_property_readonly("paths", [](const ClipMapState& s) { return s.paths; })
      .def_property_readonly("labels",
                             [](const ClipMapState& s) { return labels_dict(s.file.labels); })
      .def("label_accuracy", &label_accuracy_dict, py::arg("k"), py::arg("sample"))
      .def_property_readonly("parameters", [](const ClipMapState& s) { return s.file.parameters; })
      .def_property_readonly("notes", [](const ClipMapState& s) { return s.file.notes; })
      .def_property_readonly("read_notes", [](const ClipMapState& s) { return s.file.read_notes; })
      .def_property_readonly("warnings", [](const ClipMapState& s) { return s.file.warnings; })
      .def_property_readonly("k_used", [](const ClipMapState& s) { return s.file.k_used; })
      .def_property_readonly("heat_used", [](const ClipMapState& s) { return s.file.heat_used; })
      .def_property_readonly("x_columns", [](const ClipMapState& s) { return s.file.x_columns; })
      .def_property_readonly("options",
                             [](const ClipMapState& s) { return option_dict(s.file.options); })
      .def("transform", &transform_clips, py::arg("clips"), py::arg("options"), py::arg("asf"),
           py::arg("fps"), py::arg("progress"))
      .def("place_clips", &place_clip_records, py::arg("clips"), py::arg("options"), py::arg("asf"),
           py::arg("fps"), py::arg("progress"))
      .def(
          "write_placed_map",
          [](const ClipMapState& s, const std::vector<mapfile::PlacedClip>& placed,
             const py::object& path, const std::string& fitted_name) {
            const std::string out = py::str(py::module_::import("os").attr("fspath")(path));
            py::gil_scoped_release release;
            mapfile::write_map_file(out, mapfile::placed_map_file(s.file, placed, fitted_name));
          },
          py::arg("placed"), py::arg("path"), py::arg("fitted_name"))
      .def("write_csv", &write_csv, py::arg("path"))
      .def("poses_at", &poses_at, py::arg("Y"), py::arg("blend"), py::arg("neighbors"),
           py::arg("reach"), py::arg("progress"))
      .def("inbetween", &inbetween_keys, py::arg("keys"), py::arg("times"),
           py::arg("frames_between"), py::arg("route"), py::arg("grid"), py::arg("smooth"),
           py::arg("blend"), py::arg("neighbors"), py::arg("reach"), py::arg("asf"), py::arg("fps"),
           py::arg("clean_feet"), py::arg("free_roots"), py::arg("progress"))
      .def("synthesize", &synthesize_path, py::arg("path_xy"), py::arg("times"), py::arg("speed"),
           py::arg("fps"), py::arg("smooth"), py::arg("blend"), py::arg("neighbors"),
           py::arg("reach"), py::arg("clean_feet"), py::arg("progress"))
      .def("edit_path", &edit_path, py::arg("previous_xy"), py::arg("previous_times"),
           py::arg("path_xy"), py::arg("times"), py::arg("speed"), py::arg("fps"),
           py::arg("smooth"), py::arg("blend"), py::arg("neighbors"), py::arg("reach"),
           py::arg("clean_feet"), py::arg("progress"))
      .def(
          "write_map",
          [](const ClipMapState& s, const py::object& path) {
            const std::string out = py::str(py::module_::import("os").attr("fspath")(path));
            py::gil_scoped_release release;
            mapfile::write_map_file(out, s.file);
          },
          py::arg("path"))
      .def(py::pickle(
          [](const ClipMapState& s) {
            return py::make_tuple(1, map_file_bytes(s), s.file.path, s.paths);
          },
          [](const py::tuple& t) {
            if (t.size() != 4 || t[0].cast<int>() != 1)
              throw Error("unpickling a clip map: unknown state layout");
            auto s = state_from_bytes(t[1].cast<std::string>(), t[2].cast<std::string>());
            s->paths = t[3].cast<std::vector<std::string>>();
            return s;
          }));

  py::class_<mapfile::PlacedClip>(m, "_PlacedClip",
                                  "A clip placed on a map, with its record (map_library's tasks).")
      .def_property_readonly("path", [](const mapfile::PlacedClip& p) { return p.record.path; })
      .def_property_readonly("frames", [](const mapfile::PlacedClip& p) { return p.frames; })
      .def_property_readonly("coordinates",
                             [](const mapfile::PlacedClip& p) { return p.coordinates; })
      .def(py::pickle(
          [](const mapfile::PlacedClip& p) {
            return py::make_tuple(1, p.record.path, p.record.sha256, p.record.frames,
                                  p.record.frame_time, p.frames, p.coordinates);
          },
          [](const py::tuple& t) {
            if (t.size() != 7 || t[0].cast<int>() != 1)
              throw Error("unpickling a placed clip: unknown state layout");
            mapfile::PlacedClip p;
            p.record.path = t[1].cast<std::string>();
            p.record.sha256 = t[2].cast<std::string>();
            p.record.frames = t[3].cast<int>();
            p.record.frame_time = t[4].cast<double>();
            p.frames = t[5].cast<std::vector<int>>();
            p.coordinates = t[6].cast<Eigen::MatrixXd>();
            return p;
          }));

  py::class_<MatrixMapState, std::shared_ptr<MatrixMapState>>(
      m, "_MatrixMap", "A fitted map of a matrix (the state of a fitted estimator).")
      .def_property_readonly("coordinates",
                             [](const MatrixMapState& s) { return s.embedding.coordinates; })
      .def_property_readonly("eigenvalues",
                             [](const MatrixMapState& s) { return s.embedding.eigenvalues; })
      .def_property_readonly("warnings",
                             [](const MatrixMapState& s) { return s.embedding.warnings; })
      .def_property_readonly("k_used", [](const MatrixMapState& s) { return s.embedding.k_used; })
      .def_property_readonly("heat_used",
                             [](const MatrixMapState& s) { return s.embedding.heat_used; })
      .def_property_readonly("x_columns", [](const MatrixMapState& s) { return s.columns; })
      .def_property_readonly("precomputed", [](const MatrixMapState& s) { return s.precomputed; })
      .def("transform", &transform_matrix, py::arg("X"), py::arg("progress"))
      .def(py::pickle(&matrix_state, &matrix_from_state));

  m.def("_fit_clips", &fit_clips, py::arg("clips"), py::arg("options"), py::arg("asf"),
        py::arg("fps"), py::arg("progress"), py::arg("labels_from_name") = "",
        py::arg("labels") = "");
  m.def("_fit_matrix", &fit_matrix, py::arg("X"), py::arg("precomputed"), py::arg("options"),
        py::arg("progress"));
  m.def(
      "_read_map",
      [](const py::object& path) {
        const std::string in = py::str(py::module_::import("os").attr("fspath")(path));
        auto s = std::make_shared<ClipMapState>();
        {
          py::gil_scoped_release release;
          s->file = mapfile::read_map_file(in);
        }
        for (const auto& c : s->file.clips) s->paths.push_back(c.path);
        return s;
      },
      py::arg("path"));
}

}  // namespace motionmap::python
