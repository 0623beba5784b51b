// The map file's layout: the record of a map (make_map_file) and what is written where
// (write_map_file). Reading it back is read_map_file.cpp; placing clips on it, place_clips.cpp.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/core/sha256.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/mapfile/detail/hdf5.h"
#include "motionmap/mapfile/detail/layout.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/synth/blender.h"

namespace motionmap::mapfile {

namespace {

// Row-major copies for the file (HDF5 and numpy order), and back.
std::vector<double> row_major(const Eigen::MatrixXd& m) {
  std::vector<double> out(static_cast<std::size_t>(m.size()));
  Eigen::Map<RowMatrix>(out.data(), m.rows(), m.cols()) = m;
  return out;
}

std::vector<std::int32_t> int32s(const std::vector<int>& v) {
  return std::vector<std::int32_t>(v.begin(), v.end());
}

bool bit_equal(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 ||
          std::equal(a.data(), a.data() + a.size(), b.data(),
                     [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }));
}

// ---- Writing --------------------------------------------------------------------------------

void write_matrix(detail::Writer& w, const std::string& name, const Eigen::MatrixXd& m) {
  if (m.size() == 0) return;
  const std::vector<double> values = row_major(m);
  w.doubles(name, values.data(), std::uint64_t(m.rows()), std::uint64_t(m.cols()));
}

void write_matrix(detail::Writer& w, const std::string& name, const RowMatrix& m) {
  if (m.size() == 0) return;
  w.doubles(name, m.data(), std::uint64_t(m.rows()), std::uint64_t(m.cols()));
}

template <class Vector>
void write_vector(detail::Writer& w, const std::string& name, const Vector& v) {
  if (v.size() == 0) return;
  const Eigen::VectorXd copy = v.transpose();
  w.doubles(name, copy.data(), std::uint64_t(copy.size()));
}

void write_ints(detail::Writer& w, const std::string& name, const std::vector<int>& v) {
  const std::vector<std::int32_t> values = int32s(v);
  w.ints(name, values.data(), values.size());
}
}  // namespace

// ---- make_map_file --------------------------------------------------------------------------

std::optional<BlendRecord> blend_record(std::span<const Clip> clips,
                                        const features::FeatureSet& samples) {
  if (clips.empty() || samples.num_samples() < 1) return std::nullopt;
  const Skeleton& skeleton = clips.front().skeleton;
  for (const Clip& c : clips) {
    const auto values = std::size_t(c.motion.num_frames) * std::size_t(c.skeleton.num_joints());
    if (!c.skeleton.same_hierarchy(skeleton) || c.motion.rotations.size() != values ||
        c.motion.translations.size() != values)
      return std::nullopt;
  }
  for (int i = 0; i < samples.num_samples(); ++i) {
    const int c = samples.clip_of[std::size_t(i)], f = samples.frame_of[std::size_t(i)];
    if (c < 0 || c >= int(clips.size()) || f < 0 || f >= clips[std::size_t(c)].motion.num_frames)
      throw ParameterError("blend_record: sample " + std::to_string(i) + " is not a frame of the " +
                           std::to_string(clips.size()) + " clips");
  }
  const synth::ClipsSummary summary = synth::summarize_clips(clips, samples);
  return BlendRecord{summary.motion_root, summary.moving};
}

std::string recorded_sha256(const Clip& clip) {
  return clip.sha256.empty() ? sha256_file(clip.path) : clip.sha256;
}

MapFile make_map_file(std::span<const Clip> clips, pipeline::ClipMap map,
                      const pipeline::ClipMapOptions& options) {
  if (!map.features) throw ParameterError("make_map_file: the map has no feature set");
  const features::FeatureSet& set = *map.features;
  const embed::Embedding& e = map.embedding;
  if (clips.size() != set.segment_starts.size() || e.coordinates.rows() != set.num_samples()) {
    throw ParameterError("make_map_file: the map is not a map of these " +
                         std::to_string(clips.size()) + " clips (it has " +
                         std::to_string(set.segment_starts.size()) + " clips and " +
                         std::to_string(e.coordinates.rows()) + " rows)");
  }
  MapFile file;
  // Files not hashed when loaded are hashed a file per thread (10^6 frames: ~1 GB).
  std::vector<std::string> hashes(clips.size());
  parallel_for(static_cast<int>(clips.size()),
               [&](int c) { hashes[std::size_t(c)] = recorded_sha256(clips[std::size_t(c)]); });
  for (std::size_t c = 0; c < clips.size(); ++c) {
    ClipRecord record;
    record.path = clips[c].path;
    record.sha256 = std::move(hashes[c]);
    record.frames = clips[c].motion.num_frames;
    record.frame_time = clips[c].motion.frame_time;
    record.first_sample = set.segment_starts[c];
    const int end = c + 1 < clips.size() ? set.segment_starts[c + 1] : set.num_samples();
    record.samples = end - record.first_sample;
    file.clips.push_back(std::move(record));
  }
  file.clip_of = set.clip_of;
  file.frame_of = set.frame_of;

  file.parameters = pipeline::describe_parameters(e, options);
  file.options = options;
  file.options.metrics = false;  // what the map was made with, not what was measured of it
  file.dense = map.dense;
  file.k_used = e.k_used;
  file.heat_used = e.heat_used;
  file.landmarks_used = e.from_points && e.landmarks ? int(e.landmarks->frames.size()) : 0;
  file.neighbor_search = e.neighbor_search;
  file.graph_components = e.graph_components;
  file.connecting_edges = e.connecting_edges;
  file.notes = set.notes;
  file.warnings = e.warnings;

  const Skeleton& skeleton = clips.front().skeleton;
  for (const Joint& j : skeleton.joints) {
    file.skeleton.names.push_back(j.name);
    file.skeleton.parents.push_back(j.parent);
    file.skeleton.end_sites.push_back(static_cast<int>(j.end_sites.size()));
  }
  for (const int j : set.joints) file.joints.push_back(skeleton.joints[std::size_t(j)].name);
  file.blend = blend_record(clips, set);
  if (options.features.joints == features::JointSelection::Common) {
    file.shared_joints = features::common_joint_names(clips);
  }
  file.x_columns = static_cast<int>(set.X.cols());
  file.point_columns = static_cast<int>(set.distance_input.cols());

  file.coordinates = e.coordinates;
  file.model = pipeline::map_model(std::move(map), options);
  return file;
}

// ---- write_map_file -------------------------------------------------------------------------

void write_map_file(const std::string& path, const MapFile& f) {
  const int n = f.num_samples();
  if (f.clips.empty() || n == 0 || f.coordinates.rows() != n ||
      f.frame_of.size() != f.clip_of.size()) {
    throw ParameterError(path + ": error: cannot write an empty or inconsistent map (" +
                         std::to_string(f.clips.size()) + " clips, " + std::to_string(n) +
                         " samples, " + std::to_string(f.coordinates.rows()) + " coordinates)");
  }
  detail::Writer w(path);
  w.attribute("/", "format", std::string(kFormatName));
  // Layout 3 always: its checksums are what a reader trusts the file by.
  w.attribute("/", "format_version", kFormatVersion);
  w.attribute("/", "generator", detail::generator_name());

  w.group("/clips");
  std::vector<std::string> paths, hashes;
  std::vector<int> frames, firsts, counts;
  std::vector<double> frame_times;
  for (const ClipRecord& c : f.clips) {
    paths.push_back(c.path);
    hashes.push_back(c.sha256);
    frames.push_back(c.frames);
    frame_times.push_back(c.frame_time);
    firsts.push_back(c.first_sample);
    counts.push_back(c.samples);
  }
  w.strings("/clips/path", paths);
  w.strings("/clips/sha256", hashes);
  write_ints(w, "/clips/frames", frames);
  w.doubles("/clips/frame_time", frame_times.data(), frame_times.size());
  write_ints(w, "/clips/first_sample", firsts);
  write_ints(w, "/clips/samples", counts);

  w.group("/samples");
  write_ints(w, "/samples/clip", f.clip_of);
  write_ints(w, "/samples/frame", f.frame_of);

  const std::string p = "/parameters";
  const features::FeatureOptions& fo = f.options.features;
  const embed::EmbedOptions& eo = f.options.embed;
  w.group(p);
  w.attribute(p, "description", f.parameters);
  w.attribute(p, "features", std::string(features::feature_kind_name(fo.features)));
  w.attribute(p, "distance", std::string(features::distance_kind_name(fo.distance)));
  w.attribute(p, "up", std::string(enum_name(kAxisNames, fo.up)));
  w.attribute(p, "exclude", fo.exclude);
  w.attribute(p, "first_frame", fo.first_frame);
  w.attribute(p, "end_frame", fo.end_frame);
  w.attribute(p, "stride", fo.stride);
  w.attribute(p, "keep_first", fo.keep_first);
  w.attribute(p, "joints", std::string(features::joint_selection_name(fo.joints)));
  w.attribute(p, "method", std::string(embed::method_name(eo.method)));
  w.attribute(p, "dims", eo.dimensions);
  w.attribute(p, "k", eo.k);
  w.attribute(p, "k_used", f.k_used);
  w.attribute(p, "heat_auto", !eo.heat.has_value());
  w.attribute(p, "heat", eo.heat ? *eo.heat : f.heat_used);
  w.attribute(p, "heat_used", f.heat_used);
  w.attribute(p, "reg", eo.reg);
  if (eo.method == embed::Method::Umap) {  // only umap maps have them: other files unchanged
    w.attribute(p, "min_dist", eo.min_dist);
    w.attribute(p, "epochs", eo.epochs);
    w.attribute(p, "seed", eo.seed);
  }
  if (eo.method == embed::Method::Gplvm) {  // likewise only gplvm maps
    w.attribute(p, "max_iterations", eo.max_iterations);
    w.attribute(p, "inducing", eo.inducing);
    w.attribute(p, "lengthscale", eo.lengthscale);
  }
  w.attribute(p, "standardize", eo.standardize);
  w.attribute(p, "strict", eo.strict);
  w.attribute(p, "landmarks", eo.landmarks);
  w.attribute(p, "landmarks_used", f.landmarks_used);
  w.attribute(p, "search", std::string(enum_name(embed::kSearchNames, eo.search)));
  w.attribute(p, "path", std::string(enum_name(pipeline::kMapPathNames, f.options.path)));
  w.attribute(p, "dense_limit", f.options.dense_limit);
  w.attribute(p, "path_taken", std::string(f.dense ? "dense" : "points"));
  w.attribute(p, "neighbor_search", f.neighbor_search);
  w.attribute(p, "graph_components", f.graph_components);
  w.attribute(p, "connecting_edges", f.connecting_edges);
  if (!f.notes.empty()) w.strings("/notes", f.notes);
  if (!f.warnings.empty()) w.strings("/warnings", f.warnings);

  w.group("/skeleton");
  w.strings("/skeleton/names", f.skeleton.names);
  write_ints(w, "/skeleton/parents", f.skeleton.parents);
  write_ints(w, "/skeleton/end_sites", f.skeleton.end_sites);
  if (f.blend) {
    w.group("/blend");
    w.attribute("/blend", "motion_root", f.blend->motion_root);
    if (!f.blend->moving.empty()) write_ints(w, "/blend/moving_joints", f.blend->moving);
  }
  w.group("/joints");
  w.strings("/joints/used", f.joints);
  if (!f.shared_joints.empty()) w.strings("/joints/shared", f.shared_joints);
  w.attribute("/joints", "x_columns", f.x_columns);
  w.attribute("/joints", "point_columns", f.point_columns);

  write_matrix(w, "/coordinates", f.coordinates);
  if (!f.labels.empty()) {
    // Names and values as fixed-length strings, each sample's value as an index into them.
    pipeline::check_labels(f.labels, n);
    w.group("/labels");
    std::vector<std::string> names;
    for (const pipeline::LabelColumn& column : f.labels.columns) names.push_back(column.name);
    w.strings("/labels/names", names);
    for (std::size_t l = 0; l < f.labels.columns.size(); ++l) {
      const pipeline::LabelColumn& column = f.labels.columns[l];
      const std::string g = "/labels/" + std::to_string(l);
      w.group(g);
      w.strings(g + "/values", column.categories);
      w.ints(g + "/codes", column.codes.data(), column.codes.size());
    }
  }

  const embed::MapModel& m = f.model;
  w.group("/model");
  w.attribute("/model", "method", std::string(embed::method_name(m.method)));
  w.attribute("/model", "dimensions", m.dimensions);
  w.attribute("/model", "metric", std::string(enum_name(kMetricNames, m.metric)));
  w.attribute("/model", "points_are_landmarks", m.points_are_landmarks);
  w.attribute("/model", "k", m.k);
  w.attribute("/model", "heat", m.heat);
  w.attribute("/model", "reg", m.reg);
  // The model's coordinates are the map's: one copy, two names, unless they differ.
  if (m.coordinates.size() > 0 && bit_equal(m.coordinates, f.coordinates)) {
    w.link("/coordinates", "/model/coordinates");
  } else {
    write_matrix(w, "/model/coordinates", m.coordinates);
  }
  write_vector(w, "/model/mean", m.mean);
  write_vector(w, "/model/scale", m.scale);
  write_matrix(w, "/model/axes", m.axes);
  write_matrix(w, "/model/points", m.points);
  write_vector(w, "/model/eigenvalues", m.eigenvalues);
  write_matrix(w, "/model/features", m.features);
  if (m.landmarks) {
    const embed::LandmarkFit& fit = *m.landmarks;
    w.group("/model/landmarks");
    write_ints(w, "/model/landmarks/frames", fit.frames);
    write_matrix(w, "/model/landmarks/projection", fit.projection);
    write_vector(w, "/model/landmarks/mean_squared", fit.mean_squared);
    write_vector(w, "/model/landmarks/offset", fit.offset);
    write_matrix(w, "/model/landmarks/geodesic", fit.geodesic);
  }
  if (!m.graph.offsets.empty()) {
    w.group("/model/graph");
    write_ints(w, "/model/graph/offsets", m.graph.offsets);
    write_ints(w, "/model/graph/targets", m.graph.targets);
    w.doubles("/model/graph/weights", m.graph.weights.data(), m.graph.weights.size());
  }
  if (m.method == embed::Method::Gplvm) {  // the GP's predictive (embed::GplvmPredictive)
    const embed::GplvmPredictive& p = m.gplvm;
    w.group("/model/gplvm");
    w.attribute("/model/gplvm", "rbf_variance", p.rbf_variance);
    w.attribute("/model/gplvm", "lengthscale", p.lengthscale);
    w.attribute("/model/gplvm", "bias_variance", p.bias_variance);
    w.attribute("/model/gplvm", "prior_variance", p.prior_variance);
    write_matrix(w, "/model/gplvm/basis", p.basis);
    write_matrix(w, "/model/gplvm/alpha", p.alpha);
    write_matrix(w, "/model/gplvm/C", p.C);
  }
  w.close();
}

}  // namespace motionmap::mapfile
