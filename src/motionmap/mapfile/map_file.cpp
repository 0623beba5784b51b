#include "motionmap/mapfile/map_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/core/sha256.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/mapfile/detail/hdf5.h"
#include "motionmap/synth/blender.h"

namespace motionmap::mapfile {

using detail::DatasetInfo;
using embed::Method;

namespace {

constexpr EnumName<Metric> kMetrics[] = {{Metric::Euclidean, "euclidean"},
                                         {Metric::QuaternionAngles, "quaternion-angles"}};
constexpr EnumName<embed::EmbedOptions::Search> kSearches[] = {
    {embed::EmbedOptions::Search::Auto, "auto"},
    {embed::EmbedOptions::Search::Exact, "exact"},
    {embed::EmbedOptions::Search::Approximate, "approximate"}};
constexpr EnumName<pipeline::MapPath> kPaths[] = {{pipeline::MapPath::Auto, "auto"},
                                                  {pipeline::MapPath::Dense, "dense"},
                                                  {pipeline::MapPath::Landmarks, "landmarks"}};
constexpr EnumName<Axis> kAxes[] = {{Axis::X, "x"}, {Axis::Y, "y"}, {Axis::Z, "z"}};

bool uses_graph_method(Method method) {
  return embed::uses_graph(method);
}

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

// ---- Reading --------------------------------------------------------------------------------

// "364×2", "31".
std::string shape_text(const std::vector<std::uint64_t>& shape) {
  if (shape.empty()) return "a scalar";
  std::string s;
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? "×" : "") + std::to_string(shape[i]);
  return s;
}

// A read with every check, every failure an Error "path: error: …" naming the item and what was
// expected of it. A size of −1 accepts any size (and is then fixed by what was read).
class Input {
 public:
  explicit Input(const detail::Reader& reader) : m_r(reader) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(m_r.path() + ": error: " + what);
  }

  bool has(const std::string& name) const { return m_r.has(name); }

  void require_group(const std::string& name, const std::string& meaning) const {
    if (!m_r.has(name)) fail("missing group " + name + " (" + meaning + ")");
  }

  std::string text(const std::string& object, const std::string& name,
                   const std::string& meaning) const {
    const std::optional<std::string> v = m_r.text_attribute(object, name);
    if (!v) fail(missing_attribute(object, name, "a string: " + meaning));
    return *v;
  }
  std::int64_t integer(const std::string& object, const std::string& name, std::int64_t lo,
                       std::int64_t hi, const std::string& meaning) const {
    const std::optional<std::int64_t> v = m_r.int_attribute(object, name);
    if (!v) fail(missing_attribute(object, name, "an integer: " + meaning));
    if (*v < lo || *v > hi) {
      fail("attribute " + name + " of " + object + " is " + std::to_string(*v) + ", expected " +
           meaning + " in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return *v;
  }
  int integer32(const std::string& object, const std::string& name, std::int64_t lo,
                const std::string& meaning) const {
    return static_cast<int>(integer(object, name, lo, INT32_MAX, meaning));
  }
  bool flag(const std::string& object, const std::string& name, const std::string& meaning) const {
    return integer(object, name, 0, 1, meaning + " (0 or 1)") != 0;
  }
  double real(const std::string& object, const std::string& name,
              const std::string& meaning) const {
    const std::optional<double> v = m_r.real_attribute(object, name);
    if (!v) fail(missing_attribute(object, name, "a number: " + meaning));
    if (!std::isfinite(*v)) {
      fail("attribute " + name + " of " + object + " is not a finite number (" + meaning + ")");
    }
    return *v;
  }
  template <class E, std::size_t N>
  E name_of(const EnumName<E> (&table)[N], const std::string& object, const std::string& name,
            const std::string& meaning) const {
    const std::string v = text(object, name, meaning);
    if (const std::optional<E> e = parse_enum(table, v)) return *e;
    fail("attribute " + name + " of " + object + " is '" + v + "', expected " + meaning + ": " +
         choices(table));
  }
  template <class E, std::size_t N>
  static std::string choices(const EnumName<E> (&table)[N]) {
    std::string s;
    for (std::size_t i = 0; i < N; ++i) s += (i ? ", " : "") + std::string(table[i].name);
    return s;
  }

  // The dataset's info after checking it exists, has the expected rank and sizes and element
  // class. `shape` holds the expected sizes, −1 for any.
  DatasetInfo dataset(const std::string& name, DatasetInfo::Kind kind,
                      const std::vector<std::int64_t>& shape, const std::string& meaning) const {
    const std::string element = kind == DatasetInfo::Kind::Float     ? "float64"
                                : kind == DatasetInfo::Kind::Integer ? "integer"
                                                                     : "string";
    if (!m_r.has(name)) fail("missing dataset " + name + " (" + meaning + ", " + element + ")");
    const DatasetInfo info = m_r.info(name);
    if (info.kind != kind || (kind == DatasetInfo::Kind::Float && info.element_bytes != 8) ||
        (kind == DatasetInfo::Kind::Integer && info.element_bytes > 8)) {
      fail(name + " holds " + detail::describe_element(info) + " values, expected " + element +
           " (" + meaning + ")");
    }
    bool same = info.shape.size() == shape.size();
    for (std::size_t i = 0; same && i < shape.size(); ++i) {
      same = shape[i] < 0 || info.shape[i] == std::uint64_t(shape[i]);
    }
    if (!same) {
      std::string want;
      for (std::size_t i = 0; i < shape.size(); ++i) {
        want += (i ? "×" : "") + (shape[i] < 0 ? std::string("any") : std::to_string(shape[i]));
      }
      fail(name + " has shape " + shape_text(info.shape) + ", expected " + want + " (" + meaning +
           ")");
    }
    return info;
  }

  // A float64 matrix of rows × cols (−1: any), every value finite, read a slab of rows at a time
  // into its column-major storage (no whole row-major copy beside it: 2 GB for the geodesic
  // distances of a 10⁶-sample Isomap model).
  Eigen::MatrixXd matrix(const std::string& name, std::int64_t rows, std::int64_t cols,
                         const std::string& meaning) const {
    const DatasetInfo info = dataset(name, DatasetInfo::Kind::Float, {rows, cols}, meaning);
    const std::uint64_t R = info.shape[0], C = info.shape[1];
    Eigen::MatrixXd out(static_cast<Eigen::Index>(R), static_cast<Eigen::Index>(C));
    // 8 rows of 10⁶ values, 64 MB: a cache line of each column per slab.
    constexpr std::uint64_t kSlabValues = std::uint64_t(1) << 23;
    constexpr Eigen::Index kColumnsPerBlock = 8192;
    const std::uint64_t slab =
        std::max<std::uint64_t>(1, kSlabValues / std::max<std::uint64_t>(1, C));
    std::vector<double> buffer;
    for (std::uint64_t r = 0; r < R; r += slab) {
      const std::uint64_t n = std::min(slab, R - r);
      buffer.resize(n * C);
      m_r.double_rows(name, r, n, buffer.data());
      check_finite(name, buffer.data(), n * C, C, r);
      const Eigen::Map<const RowMatrix> rows(buffer.data(), Eigen::Index(n), Eigen::Index(C));
      // Column blocks in parallel (the scattered writes, and the first touch of out's pages).
      const int blocks = static_cast<int>((C + kColumnsPerBlock - 1) / kColumnsPerBlock);
      parallel_chunks(blocks, [&](int b, int) {
        const Eigen::Index c0 = Eigen::Index(b) * kColumnsPerBlock;
        const Eigen::Index width = std::min<Eigen::Index>(kColumnsPerBlock, Eigen::Index(C) - c0);
        out.block(Eigen::Index(r), c0, Eigen::Index(n), width) = rows.middleCols(c0, width);
      });
    }
    return out;
  }
  RowMatrix row_matrix(const std::string& name, std::int64_t rows, std::int64_t cols,
                       const std::string& meaning) const {
    const DatasetInfo info = dataset(name, DatasetInfo::Kind::Float, {rows, cols}, meaning);
    RowMatrix out(static_cast<Eigen::Index>(info.shape[0]),
                  static_cast<Eigen::Index>(info.shape[1]));
    m_r.double_rows(name, 0, info.shape[0], out.data());
    check_finite(name, out.data(), std::uint64_t(out.size()), info.shape[1], 0);
    return out;
  }
  Eigen::VectorXd vector(const std::string& name, std::int64_t size,
                         const std::string& meaning) const {
    dataset(name, DatasetInfo::Kind::Float, {size}, meaning);
    const std::vector<double> values = m_r.doubles(name);
    check_finite(name, values.data(), values.size(), 1, 0);
    return Eigen::Map<const Eigen::VectorXd>(values.data(), Eigen::Index(values.size()));
  }
  // Integers in [lo, hi).
  std::vector<int> ints(const std::string& name, std::int64_t size, std::int64_t lo,
                        std::int64_t hi, const std::string& meaning) const {
    dataset(name, DatasetInfo::Kind::Integer, {size}, meaning);
    const std::vector<std::int64_t> values = m_r.ints(name);
    std::vector<int> out;
    out.reserve(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (values[i] < lo || values[i] >= hi) {
        fail(name + " holds " + std::to_string(values[i]) + " at index " + std::to_string(i) +
             ", expected " + meaning + " in [" + std::to_string(lo) + ", " + std::to_string(hi) +
             ")");
      }
      out.push_back(static_cast<int>(values[i]));
    }
    return out;
  }
  std::vector<std::string> strings(const std::string& name, std::int64_t size,
                                   const std::string& meaning) const {
    dataset(name, DatasetInfo::Kind::String, {size}, meaning);
    return m_r.strings(name);
  }

 private:
  static std::string missing_attribute(const std::string& object, const std::string& name,
                                       const std::string& meaning) {
    return "missing attribute " + name + " of " + object + " (" + meaning + ")";
  }
  // Fails naming the first non-finite of `count` values, which start at row `first_row` of a
  // dataset of `cols` values per row. In parallel: a model's 3 GB are read at a time.
  void check_finite(const std::string& name, const double* values, std::uint64_t count,
                    std::uint64_t cols, std::uint64_t first_row) const {
    constexpr std::uint64_t kValuesPerBlock = std::uint64_t(1) << 16;
    const int blocks = static_cast<int>((count + kValuesPerBlock - 1) / kValuesPerBlock);
    std::vector<std::uint64_t> first(std::size_t(blocks), count);
    parallel_chunks(blocks, [&](int b, int) {
      const std::uint64_t end = std::min(count, (std::uint64_t(b) + 1) * kValuesPerBlock);
      for (std::uint64_t i = std::uint64_t(b) * kValuesPerBlock; i < end; ++i) {
        if (!std::isfinite(values[i])) {
          first[std::size_t(b)] = i;
          return;
        }
      }
    });
    if (blocks == 0) return;
    const std::uint64_t i = *std::min_element(first.begin(), first.end());
    if (i == count) return;
    const std::string at = cols > 1 ? "row " + std::to_string(first_row + i / cols) + ", column " +
                                          std::to_string(i % cols)
                                    : "index " + std::to_string(first_row + i);
    fail(name + " holds a non-finite value (" + std::to_string(values[i]) + ") at " + at);
  }

  const detail::Reader& m_r;
};

std::string generator_name() {
#ifdef MOTIONMAP_VERSION
  return std::string("MotionMap ") + MOTIONMAP_VERSION;
#else
  return "MotionMap";
#endif
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
  // A library's files are hashed a file per thread (10^6 frames: ~1 GB, 4 s on one core).
  std::vector<std::string> hashes(clips.size());
  parallel_for(static_cast<int>(clips.size()),
               [&](int c) { hashes[std::size_t(c)] = sha256_file(clips[std::size_t(c)].path); });
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
  // Layout 1 unless the file needs 2 (a model of other samples than its rows), so that a
  // MotionMap that reads only layout 1 still reads every map it could read before.
  const bool placed = f.model.coordinates.rows() > 0 && f.model.coordinates.rows() != n;
  w.attribute("/", "format_version", placed ? kFormatVersion : 1);
  w.attribute("/", "generator", generator_name());

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
  w.attribute(p, "up", std::string(enum_name(kAxes, fo.up)));
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
  w.attribute(p, "standardize", eo.standardize);
  w.attribute(p, "strict", eo.strict);
  w.attribute(p, "landmarks", eo.landmarks);
  w.attribute(p, "landmarks_used", f.landmarks_used);
  w.attribute(p, "search", std::string(enum_name(kSearches, eo.search)));
  w.attribute(p, "path", std::string(enum_name(kPaths, f.options.path)));
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

  const embed::MapModel& m = f.model;
  w.group("/model");
  w.attribute("/model", "method", std::string(embed::method_name(m.method)));
  w.attribute("/model", "dimensions", m.dimensions);
  w.attribute("/model", "metric", std::string(enum_name(kMetrics, m.metric)));
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
  w.close();
}

// ---- read_map_file --------------------------------------------------------------------------

MapFile read_map_file(const std::string& path, const ReadOptions& options) {
  const detail::Reader reader(path);
  const Input in(reader);

  // What the file is, before anything else is trusted.
  const std::optional<std::string> format = reader.text_attribute("/", "format");
  if (!format) {
    in.fail("not a MotionMap map file: the root has no 'format' attribute (expected format = " +
            std::string(kFormatName) + ", as `motionmap map --save` writes)");
  }
  if (*format != kFormatName) {
    in.fail("not a MotionMap map file: its format is '" + *format + "', expected '" +
            std::string(kFormatName) + "'");
  }
  const std::optional<std::int64_t> version = reader.int_attribute("/", "format_version");
  if (!version)
    in.fail("missing root attribute format_version (an integer; this MotionMap reads 1 to " +
            std::to_string(kFormatVersion) + ")");
  if (*version > kFormatVersion) {
    in.fail("map file layout version " + std::to_string(*version) +
            " is newer than this MotionMap reads (" + std::to_string(kFormatVersion) +
            "); read it with a newer MotionMap");
  }
  if (*version < 1) {
    in.fail("unknown map file layout version " + std::to_string(*version) +
            " (this MotionMap reads versions 1 to " + std::to_string(kFormatVersion) + ")");
  }

  MapFile f;
  f.path = path;

  // Clips and samples.
  in.require_group("/clips", "the clips the map was made from");
  const std::vector<std::string> paths = in.strings("/clips/path", -1, "the clips' paths");
  const auto C = static_cast<std::int64_t>(paths.size());
  if (C == 0) in.fail("/clips/path is empty: a map has at least one clip");
  const std::vector<std::string> hashes = in.strings("/clips/sha256", C, "one hash per clip");
  const std::vector<int> frames =
      in.ints("/clips/frames", C, 1, INT32_MAX, "the frames in each clip's file");
  const Eigen::VectorXd frame_times = in.vector("/clips/frame_time", C, "seconds per frame");
  in.require_group("/samples", "the clip and frame of every map row");
  const std::vector<int> clip_of = in.ints("/samples/clip", -1, 0, C, "a clip index");
  const auto N = static_cast<std::int64_t>(clip_of.size());
  if (N == 0) in.fail("/samples/clip is empty: a map has at least one sample");
  const std::vector<int> firsts = in.ints("/clips/first_sample", C, 0, N, "a map row");
  const std::vector<int> counts = in.ints("/clips/samples", C, 1, N + 1, "a number of rows");
  const std::vector<int> frame_of = in.ints("/samples/frame", N, 0, INT32_MAX, "a frame index");
  for (std::int64_t c = 0, row = 0; c < C; ++c) {
    if (hashes[c].size() != 64 ||
        hashes[c].find_first_not_of("0123456789abcdef") != std::string::npos) {
      in.fail("/clips/sha256[" + std::to_string(c) + "] is '" + hashes[c] +
              "', expected 64 lowercase hexadecimal digits");
    }
    if (!(frame_times[c] > 0)) {
      in.fail("/clips/frame_time[" + std::to_string(c) + "] is not a positive number of seconds");
    }
    if (firsts[c] != row) {
      in.fail("/clips/first_sample[" + std::to_string(c) + "] is " + std::to_string(firsts[c]) +
              ", expected " + std::to_string(row) + " (clips' rows follow each other)");
    }
    for (std::int64_t i = row; i < row + counts[c]; ++i) {
      if (i >= N || clip_of[i] != c) {
        in.fail("/samples/clip does not hold clip " + std::to_string(c) + " in rows " +
                std::to_string(row) + " to " + std::to_string(row + counts[c] - 1) +
                " as /clips/first_sample and /clips/samples say");
      }
      if (frame_of[i] >= frames[c]) {
        in.fail("/samples/frame holds " + std::to_string(frame_of[i]) + " at row " +
                std::to_string(i) + ", but clip " + std::to_string(c) + " has " +
                std::to_string(frames[c]) + " frames");
      }
    }
    row += counts[c];
    if (c + 1 == C && row != N) {
      in.fail("/clips/samples adds up to " + std::to_string(row) + " rows, but the map has " +
              std::to_string(N));
    }
  }
  for (std::int64_t c = 0; c < C; ++c) {
    f.clips.push_back({paths[c], hashes[c], frames[c], frame_times[c], firsts[c], counts[c]});
  }
  f.clip_of = clip_of;
  f.frame_of = frame_of;

  // Parameters.
  const std::string p = "/parameters";
  in.require_group(p, "the effective parameters");
  f.parameters = in.text(p, "description", "the parameters line");
  features::FeatureOptions& fo = f.options.features;
  embed::EmbedOptions& eo = f.options.embed;
  auto named_on = [&](const std::string& object, const std::string& name, auto parse,
                      const std::string& meaning) {
    const std::string v = in.text(object, name, meaning);
    const auto e = parse(v);
    if (!e) in.fail("attribute " + name + " of " + object + " is '" + v + "', expected " + meaning);
    return *e;
  };
  auto named = [&](const std::string& name, auto parse, const std::string& meaning) {
    return named_on(p, name, parse, meaning);
  };
  fo.features = named("features", features::parse_feature_kind, "a feature kind (quat, positions)");
  fo.distance = named("distance", features::parse_distance_kind,
                      "a distance kind (pointcloud, geodesic, features)");
  fo.up = in.name_of(kAxes, p, "up", "an up axis");
  fo.exclude = in.text(p, "exclude", "the excluded joints' pattern");
  fo.first_frame = in.integer32(p, "first_frame", 0, "the first frame");
  fo.end_frame = in.integer32(p, "end_frame", -1, "one past the last frame (−1: the end)");
  fo.stride = in.integer32(p, "stride", 1, "the stride");
  fo.keep_first = in.flag(p, "keep_first", "keep a bind pose");
  fo.joints = named("joints", features::parse_joint_selection, "a joint selection (all, common)");
  eo.method = named("method", embed::parse_method, "a method (pca, svd, mds, isomap, le, lle)");
  eo.dimensions = int(in.integer(p, "dims", 2, 3, "the map's dimensions"));
  eo.k = in.integer32(p, "k", 1, "neighbours per frame");
  f.k_used = in.integer32(p, "k_used", 0, "neighbours per frame used");
  f.heat_used = in.real(p, "heat_used", "the heat-kernel width used");
  if (!in.flag(p, "heat_auto", "whether the heat was automatic")) {
    eo.heat = in.real(p, "heat", "the heat-kernel width asked for");
  }
  eo.reg = in.real(p, "reg", "LLE's regularisation");
  eo.standardize = in.flag(p, "standardize", "standardised PCA");
  eo.strict = in.flag(p, "strict", "strict neighbour graphs");
  eo.landmarks = in.integer32(p, "landmarks", 0, "landmarks asked for (0: the default)");
  f.landmarks_used = in.integer32(p, "landmarks_used", 0, "landmarks chosen");
  eo.search = in.name_of(kSearches, p, "search", "a neighbour search");
  f.options.path = in.name_of(kPaths, p, "path", "a map path asked for");
  f.options.dense_limit = in.integer32(p, "dense_limit", 0, "the dense path's frame limit");
  const std::string taken = in.text(p, "path_taken", "the path taken (dense, points)");
  if (taken != "dense" && taken != "points") {
    in.fail("attribute path_taken of " + p + " is '" + taken + "', expected dense or points");
  }
  f.dense = taken == "dense";
  f.neighbor_search = in.text(p, "neighbor_search", "how neighbours were found");
  f.graph_components = in.integer32(p, "graph_components", 0, "the graph's components");
  f.connecting_edges = in.integer32(p, "connecting_edges", 0, "the edges joining them");
  if (in.has("/notes")) f.notes = in.strings("/notes", -1, "the features' notes");
  if (in.has("/warnings")) f.warnings = in.strings("/warnings", -1, "the map's warnings");

  // Joints.
  in.require_group("/skeleton", "the first clip's joint hierarchy");
  f.skeleton.names = in.strings("/skeleton/names", -1, "joint names");
  const auto J = static_cast<std::int64_t>(f.skeleton.names.size());
  if (J == 0) in.fail("/skeleton/names is empty: a skeleton has at least one joint");
  f.skeleton.parents = in.ints("/skeleton/parents", J, -1, J, "a parent joint index (−1: root)");
  for (std::int64_t j = 0; j < J; ++j) {
    if (f.skeleton.parents[j] >= j) {
      in.fail("/skeleton/parents[" + std::to_string(j) + "] is " +
              std::to_string(f.skeleton.parents[j]) + ", expected an earlier joint or −1");
    }
  }
  f.skeleton.end_sites = in.ints("/skeleton/end_sites", J, 0, INT32_MAX, "End Sites per joint");
  if (in.has("/blend")) {
    BlendRecord b;
    b.motion_root = static_cast<int>(
        in.integer("/blend", "motion_root", 0, J - 1, "the joint carrying the root motion"));
    if (in.has("/blend/moving_joints")) {
      b.moving = in.ints("/blend/moving_joints", -1, 0, J, "a joint the blend averages");
      for (std::size_t k = 0; k < b.moving.size(); ++k) {
        if (b.moving[k] == b.motion_root || (k > 0 && b.moving[k] <= b.moving[k - 1]))
          in.fail("/blend/moving_joints is not increasing or names the motion root " +
                  std::to_string(b.motion_root));
      }
    }
    f.blend = std::move(b);
  }
  in.require_group("/joints", "the joints the features use");
  f.joints = in.strings("/joints/used", -1, "the joints the features use");
  if (in.has("/joints/shared")) f.shared_joints = in.strings("/joints/shared", -1, "shared joints");
  if (fo.joints == features::JointSelection::Common && f.shared_joints.empty()) {
    in.fail("missing dataset /joints/shared (the joint names a --joints common map compares by)");
  }
  f.x_columns = in.integer32("/joints", "x_columns", 1, "the columns of X");
  f.point_columns = in.integer32("/joints", "point_columns", 1, "the columns of the points");

  // The map.
  const int dims = eo.dimensions;
  f.coordinates = in.matrix("/coordinates", N, dims, "#samples by dims");
  if (!options.model) return f;  // showing or blending the map: the model is not needed

  // The model: every item whose method uses it, each checked against the others' sizes, so
  // that embed::place() reads only what is there.
  in.require_group("/model", "what placing new frames needs");
  embed::MapModel& m = f.model;
  const std::string g = "/model";
  m.method = named_on(g, "method", embed::parse_method, "a method");
  if (m.method != eo.method) {
    in.fail("the model's method (" + std::string(embed::method_name(m.method)) +
            ") is not the map's (" + std::string(embed::method_name(eo.method)) + ")");
  }
  m.dimensions = int(in.integer(g, "dimensions", dims, dims, "the map's dimensions"));
  m.metric = in.name_of(kMetrics, g, "metric", "a pose metric");
  m.points_are_landmarks = in.flag(g, "points_are_landmarks", "points hold the landmarks only");
  m.k = in.integer32(g, "k", 0, "neighbours a new frame joins through");
  m.heat = in.real(g, "heat", "the heat-kernel width");
  m.reg = in.real(g, "reg", "LLE's regularisation");
  // The model's samples: the map's rows (layout 1), or — a map of clips placed on a model fitted
  // on other frames (layout 2, placed_map_file) — as many as /model/coordinates has.
  m.coordinates =
      in.matrix(g + "/coordinates", *version >= 2 ? -1 : N, dims, "#model samples by dims");
  const std::int64_t M = m.coordinates.rows();
  if (M == 0) in.fail(g + "/coordinates has no rows (a model has at least one sample)");

  const Method method = m.method;
  const bool projection = method == Method::Pca || method == Method::Svd;
  const std::string who = "the " + std::string(embed::method_name(method)) + " map";
  // An item the method needs must be there; one it does not need is read when present.
  auto need = [&](const std::string& name, bool needed) {
    if (needed && !in.has(name)) {
      in.fail("missing dataset " + name + " (" + who + " places new frames with it)");
    }
    return in.has(name);
  };
  const std::int64_t X = f.x_columns, V = f.point_columns;
  if (need(g + "/mean", method == Method::Pca)) m.mean = in.vector(g + "/mean", X, "#features");
  if (need(g + "/scale", method == Method::Pca && eo.standardize)) {
    m.scale = in.vector(g + "/scale", X, "#features");
    if ((m.scale.array() <= 0).any()) in.fail(g + "/scale holds a value ≤ 0");
  }
  if (need(g + "/axes", projection)) m.axes = in.matrix(g + "/axes", X, dims, "#features by dims");
  if (need(g + "/points", !projection)) {
    // A landmark mds map keeps the landmarks' rows; the others every sample's.
    m.points = in.row_matrix(
        g + "/points", m.points_are_landmarks ? -1 : M, V,
        m.points_are_landmarks ? "#landmarks by #point values" : "#model samples by #point values");
  }
  if (need(g + "/eigenvalues", method == Method::LaplacianEigenmap)) {
    m.eigenvalues = in.vector(g + "/eigenvalues", dims, "one per axis");
    if (method == Method::LaplacianEigenmap && (m.eigenvalues.array() == 1.0).any()) {
      in.fail(g + "/eigenvalues holds 1 (the Nyström extension divides by 1 − λ)");
    }
  }
  if (need(g + "/features", method == Method::Lle)) {
    m.features = in.row_matrix(g + "/features", M, X, "#model samples by #features");
  }
  if (uses_graph_method(method) && (m.k < 1 || m.k > M)) {
    in.fail("attribute k of " + g + " is " + std::to_string(m.k) + ", expected 1 to " +
            std::to_string(M) + " for " + who);
  }
  if (m.points_are_landmarks && method != Method::Mds) {
    in.fail("attribute points_are_landmarks of " + g +
            " is 1, but only an mds map keeps the "
            "landmarks' points alone");
  }
  const std::string l = g + "/landmarks";
  if (need(l, method == Method::Mds || method == Method::Isomap)) {
    embed::LandmarkFit fit;
    // Landmarks index the rows of /model/points (a landmark mds map: its own rows, in order).
    fit.frames = in.ints(l + "/frames", -1, 0, M, "a model sample index");
    const auto L = static_cast<std::int64_t>(fit.frames.size());
    if (L == 0) in.fail(l + "/frames is empty");
    if (m.points_are_landmarks && m.points.rows() != L) {
      in.fail(g + "/points has " + std::to_string(m.points.rows()) + " rows, but there are " +
              std::to_string(L) + " landmarks");
    }
    fit.projection = in.matrix(l + "/projection", dims, L, "dims by #landmarks");
    fit.mean_squared = in.vector(l + "/mean_squared", L, "#landmarks");
    fit.offset = in.vector(l + "/offset", dims, "dims");
    if (in.has(l + "/geodesic")) {
      fit.geodesic = in.matrix(l + "/geodesic", L, M, "#landmarks by #model samples");
    }
    m.landmarks = std::move(fit);
  }
  const std::string gr = g + "/graph";
  const bool dense_isomap =
      method == Method::Isomap && m.landmarks && m.landmarks->geodesic.size() == 0;
  if (need(gr, dense_isomap)) {
    embed::Graph& graph = m.graph;
    graph.offsets = in.ints(gr + "/offsets", M + 1, 0, INT32_MAX, "an offset into targets");
    graph.targets = in.ints(gr + "/targets", -1, 0, M, "a model sample index");
    const auto E = static_cast<std::int64_t>(graph.targets.size());
    const Eigen::VectorXd weights = in.vector(gr + "/weights", E, "one per target");
    graph.weights.assign(weights.data(), weights.data() + weights.size());
    if (graph.offsets.front() != 0 || graph.offsets.back() != E ||
        !std::is_sorted(graph.offsets.begin(), graph.offsets.end())) {
      in.fail(gr + "/offsets is not a CSR offset list (from 0, never decreasing, to the " +
              std::to_string(E) + " targets)");
    }
    if (std::any_of(graph.weights.begin(), graph.weights.end(), [](double w) { return w < 0; })) {
      in.fail(gr + "/weights holds a negative edge length");
    }
  }
  return f;
}

// ---- place_clips ----------------------------------------------------------------------------

namespace {

// `name` as a regular expression that matches exactly it.
std::string regex_literal(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (std::string_view("\\^$.|?*+()[]{}").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

std::string name_list(const std::vector<std::string>& names, std::size_t most = 8) {
  std::string out;
  for (std::size_t i = 0; i < std::min(names.size(), most); ++i) {
    out += (i ? ", " : "") + names[i];
  }
  if (names.size() > most) out += " and " + std::to_string(names.size() - most) + " more";
  return out;
}

}  // namespace

Placement place_clips(std::span<const Clip> clips, const MapFile& map, const PlaceOptions& options,
                      const Control& control, const embed::SampleSearch* search) {
  if (clips.empty()) throw ParameterError("place_clips: no clip given");
  const std::string onto = map.path.empty() ? std::string("the map") : map.path;
  const std::string first_clip = base_name(map.clips.front().path);
  features::FeatureOptions f = map.options.features;
  f.first_frame = options.first_frame;
  f.end_frame = options.end_frame;
  f.stride = options.stride;
  f.keep_first = options.keep_first;

  if (f.joints == features::JointSelection::All) {
    // The map's skeleton: its clips share one hierarchy, recorded from the first.
    Clip reference;
    reference.path = map.clips.front().path;
    for (std::size_t j = 0; j < map.skeleton.names.size(); ++j) {
      Joint joint;
      joint.name = map.skeleton.names[j];
      joint.parent = map.skeleton.parents[j];
      // End Site counts are part of the hierarchy (the point cloud holds their points); their
      // offsets are the new clip's own business.
      joint.end_sites.assign(std::size_t(map.skeleton.end_sites[j]), Eigen::Vector3d::Zero());
      reference.skeleton.joints.push_back(std::move(joint));
    }
    for (const Clip& clip : clips) {
      const std::string difference = features::hierarchy_difference(reference, clip);
      if (!difference.empty()) {
        throw ParameterError(clip.path + ": cannot be placed on " + onto +
                             ": its joint hierarchy differs from the map's (" + difference +
                             "); a clip placed on a map must have the skeleton of the map's "
                             "clips (joint names, parents and End Sites)");
      }
    }
  } else {
    // A --joints common map: each new clip must have every joint the map compares by; its other
    // joints are left out (added to the exclude pattern) so that the features are the map's.
    std::set<std::string> shared(map.shared_joints.begin(), map.shared_joints.end());
    std::set<std::string> extra;
    for (const Clip& clip : clips) {
      std::vector<std::string> missing;
      for (const std::string& name : map.shared_joints) {
        if (clip.skeleton.find(name) < 0) missing.push_back(name);
      }
      if (!missing.empty()) {
        throw ParameterError(
            clip.path + ": cannot be placed on " + onto + ": it lacks " +
            std::to_string(missing.size()) + " of the " + std::to_string(shared.size()) +
            " joints the map compares by (--joints common): " + name_list(missing));
      }
      for (const Joint& j : clip.skeleton.joints) {
        if (!shared.count(j.name)) extra.insert(j.name);
      }
    }
    std::string pattern;
    for (const std::string& name : extra)
      pattern += (pattern.empty() ? "" : "|") + regex_literal(name);
    if (!f.exclude.empty()) {
      f.exclude = pattern.empty() ? f.exclude : "(?:" + f.exclude + ")|" + pattern;
    } else {
      f.exclude = pattern;
    }
  }

  Placement out;
  out.features = features::build_features(clips, f, control.stage("features", 0.0, 0.2),
                                          features::Distances::Later);
  const features::FeatureSet& set = out.features;
  if (map.options.features.joints == features::JointSelection::Common) {
    // Its own "joints common" notes describe the exclusion above, not the map: replace them.
    std::erase_if(out.features.notes,
                  [](const std::string& n) { return n.rfind("joints common:", 0) == 0; });
    out.features.notes.push_back("joints common: placed by the " +
                                 std::to_string(map.shared_joints.size()) +
                                 " joints the map compares by");
  }

  // The features must be the map's, column for column.
  std::vector<std::string> used;
  for (const int j : set.joints) used.push_back(clips.front().skeleton.joints[std::size_t(j)].name);
  const std::string who = clips.front().path + ": cannot be placed on " + onto + ": ";
  if (used != map.joints) {
    throw ParameterError(who + "its features use the joints " + name_list(used, 6) +
                         " where the map's use " + name_list(map.joints, 6) +
                         (used.size() == map.joints.size() ? " (another order)" : ""));
  }
  if (set.X.cols() != map.x_columns || set.distance_input.cols() != map.point_columns) {
    throw ParameterError(who + "its features have " + std::to_string(set.X.cols()) +
                         " columns and its points " + std::to_string(set.distance_input.cols()) +
                         ", where the map's have " + std::to_string(map.x_columns) + " and " +
                         std::to_string(map.point_columns) + " (End Sites or roots differ)");
  }
  const embed::PlaceInput input{&set.X, &set.distance_input};
  out.coordinates = embed::place(map.model, input, control.stage("placing", 0.2, 1.0), search);
  control.finish();
  return out;
}

std::vector<PlacedClip> placed_clips(std::span<const Clip> clips, const Placement& placement) {
  const features::FeatureSet& set = placement.features;
  if (clips.size() != set.segment_starts.size() ||
      placement.coordinates.rows() != set.num_samples()) {
    throw ParameterError("placed_clips: the placement is not of these " +
                         std::to_string(clips.size()) + " clips");
  }
  std::vector<PlacedClip> out(clips.size());
  for (std::size_t c = 0; c < clips.size(); ++c) {
    PlacedClip& p = out[c];
    p.record.path = clips[c].path;
    p.record.sha256 = sha256_file(clips[c].path);
    p.record.frames = clips[c].motion.num_frames;
    p.record.frame_time = clips[c].motion.frame_time;
    const int first = set.segment_starts[c];
    const int end = c + 1 < clips.size() ? set.segment_starts[c + 1] : set.num_samples();
    p.frames.assign(set.frame_of.begin() + first, set.frame_of.begin() + end);
    p.coordinates = placement.coordinates.middleRows(first, end - first);
  }
  return out;
}

MapFile placed_map_file(const MapFile& fitted, std::span<const PlacedClip> placed,
                        const std::string& fitted_name) {
  if (placed.empty()) throw ParameterError("placed_map_file: no clip placed");
  if (fitted.model.coordinates.rows() == 0) {
    throw ParameterError("placed_map_file: the map " + fitted_name +
                         " was read without its model (ReadOptions::model)");
  }
  MapFile file = fitted;  // parameters, skeleton, joints and model stay the fitted map's
  file.path.clear();
  file.blend.reset();  // of the fitted map's clips, not of these
  file.clips.clear();
  file.clip_of.clear();
  file.frame_of.clear();
  const int dims = static_cast<int>(fitted.coordinates.cols());
  Eigen::Index rows = 0;
  for (const PlacedClip& p : placed) {
    if (p.frames.empty() || p.coordinates.rows() != Eigen::Index(p.frames.size()) ||
        p.coordinates.cols() != dims) {
      throw ParameterError(
          "placed_map_file: " + p.record.path + " has " + std::to_string(p.frames.size()) +
          " frames and " + std::to_string(p.coordinates.rows()) + " by " +
          std::to_string(p.coordinates.cols()) + " coordinates; expected " +
          "at least one frame and one row of " + std::to_string(dims) + " per frame");
    }
    rows += p.coordinates.rows();
  }
  file.coordinates.resize(rows, dims);
  for (const PlacedClip& p : placed) {
    ClipRecord record = p.record;
    record.first_sample = file.num_samples();
    record.samples = static_cast<int>(p.frames.size());
    file.coordinates.middleRows(record.first_sample, record.samples) = p.coordinates;
    file.clip_of.insert(file.clip_of.end(), p.frames.size(), static_cast<int>(file.clips.size()));
    file.frame_of.insert(file.frame_of.end(), p.frames.begin(), p.frames.end());
    file.clips.push_back(std::move(record));
  }
  const std::size_t fitted_clips = fitted.clips.size();
  file.notes.push_back("every frame placed on the " +
                       std::string(embed::method_name(fitted.model.method)) + " map " +
                       fitted_name + " without refitting it (fitted on " +
                       std::to_string(fitted.model.coordinates.rows()) + " frames of " +
                       (fitted_clips == 1 ? base_name(fitted.clips.front().path)
                                          : std::to_string(fitted_clips) + " clips") +
                       ")");
  return file;
}

embed::Embedding embedding_for_csv(const MapFile& map, const Eigen::MatrixXd& coordinates) {
  embed::Embedding e;
  e.method = map.model.method;
  e.coordinates = coordinates;
  e.k_used = map.k_used;
  e.heat_used = map.heat_used;
  e.from_points = !map.dense;
  if (map.landmarks_used > 0) {
    e.landmarks.emplace();
    e.landmarks->frames.assign(std::size_t(map.landmarks_used), 0);
  }
  e.neighbor_search = map.neighbor_search;
  e.graph_components = map.graph_components;
  e.connecting_edges = map.connecting_edges;
  return e;
}

}  // namespace motionmap::mapfile
