#include "motionmap/features/features.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/features/detail/point_cloud.h"
#include "motionmap/features/diagnostics.h"

namespace motionmap::features {

namespace {
constexpr EnumName<FeatureKind> kFeatureKinds[] = {{FeatureKind::Quaternions, "quat"},
                                                   {FeatureKind::Positions, "positions"}};
constexpr EnumName<DistanceKind> kDistanceKinds[] = {{DistanceKind::PointCloud, "pointcloud"},
                                                     {DistanceKind::Geodesic, "geodesic"},
                                                     {DistanceKind::Features, "features"}};
}  // namespace

std::string_view feature_kind_name(FeatureKind k) {
  return enum_name(kFeatureKinds, k);
}
std::optional<FeatureKind> parse_feature_kind(std::string_view name) {
  return parse_enum(kFeatureKinds, name);
}
const std::vector<FeatureKind>& all_feature_kinds() {
  static const std::vector<FeatureKind> kinds = enum_values(kFeatureKinds);
  return kinds;
}

std::string_view distance_kind_name(DistanceKind k) {
  return enum_name(kDistanceKinds, k);
}
std::optional<DistanceKind> parse_distance_kind(std::string_view name) {
  return parse_enum(kDistanceKinds, name);
}
const std::vector<DistanceKind>& all_distance_kinds() {
  static const std::vector<DistanceKind> kinds = enum_values(kDistanceKinds);
  return kinds;
}

void FeatureOptions::validate() const {
  if (first_frame < 0) {
    throw ParameterError("frames: first frame " + std::to_string(first_frame) + " is negative");
  }
  if (end_frame >= 0 && end_frame <= first_frame) {
    throw ParameterError("frames: range " + std::to_string(first_frame) + ":" +
                         std::to_string(end_frame) + " is empty (need A < B)");
  }
  if (stride < 1) {
    throw ParameterError("stride: " + std::to_string(stride) + " is out of range (must be ≥ 1)");
  }
}

namespace {

// quaternion_features() of a motion, joints and frames already checked.
Eigen::MatrixXd quaternion_block(const Motion& motion, std::span<const int> joints,
                                 std::span<const int> frames) {
  const auto cols = static_cast<Eigen::Index>(4 * joints.size());
  Eigen::MatrixXd X(static_cast<Eigen::Index>(frames.size()), cols);
  for (std::size_t r = 0; r < frames.size(); ++r) {
    for (std::size_t k = 0; k < joints.size(); ++k) {
      const Eigen::Quaterniond& q = motion.rotation(frames[r], joints[k]);
      Eigen::Vector4d v(q.w(), q.x(), q.y(), q.z());
      const auto c = static_cast<Eigen::Index>(4 * k);
      const bool flip =
          r == 0 ? v[0] < 0.0
                 : v.dot(X.row(static_cast<Eigen::Index>(r) - 1).segment<4>(c).transpose()) < 0.0;
      if (flip) v = -v;
      X.row(static_cast<Eigen::Index>(r)).segment<4>(c) = v.transpose();
    }
  }
  return X;
}

}  // namespace

Eigen::MatrixXd quaternion_features(const Motion& motion, std::span<const int> joints,
                                    std::span<const int> frames) {
  check_motion(motion, "quaternion_features");
  for (const int j : joints) {
    if (j < 0 || j >= motion.num_joints) {
      throw ParameterError("quaternion_features: joint index " + std::to_string(j) +
                           " is out of range (the motion has " + std::to_string(motion.num_joints) +
                           " joints)");
    }
  }
  for (const int f : frames) {
    if (f < 0 || f >= motion.num_frames) {
      throw ParameterError("quaternion_features: frame " + std::to_string(f) +
                           " is out of range (the motion has " + std::to_string(motion.num_frames) +
                           " frames)");
    }
  }
  return quaternion_block(motion, joints, frames);
}

namespace {

// The distance between two rows, as every entry of D and every check below computes it (and
// the scalable maps' neighbour searches, through the same core functions).
double point_distance(const Eigen::Ref<const RowMatrix>& points, Eigen::Index i, Eigen::Index j) {
  return euclidean_distance(points.row(i), points.row(j));
}

double geodesic_distance(const Eigen::Ref<const RowMatrix>& quaternions, Eigen::Index i,
                         Eigen::Index j) {
  return quaternion_angle_distance(quaternions.row(i), quaternions.row(j));
}

// D from a per-pair distance: row i fills D(i, i+1…n−1), written as column i (contiguous in the
// column-major D) and mirrored afterwards.
template <class Distance>
Eigen::MatrixXd all_pairs(Eigen::Index n, const Distance& distance, const Control& control) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  parallel_for(
      static_cast<int>(n),
      [&](int i) {
        for (Eigen::Index j = i + 1; j < n; ++j) D(j, i) = distance(i, j);
      },
      control);
  D.triangularView<Eigen::StrictlyUpper>() = D.transpose();
  return D;
}

}  // namespace

Eigen::MatrixXd pairwise_distances(const Eigen::Ref<const RowMatrix>& points,
                                   const Control& control) {
  return all_pairs(
      points.rows(), [&](Eigen::Index i, Eigen::Index j) { return point_distance(points, i, j); },
      control);
}

Eigen::MatrixXd geodesic_distances(const Eigen::Ref<const RowMatrix>& quaternions,
                                   const Control& control) {
  return all_pairs(
      quaternions.rows(),
      [&](Eigen::Index i, Eigen::Index j) { return geodesic_distance(quaternions, i, j); },
      control);
}

namespace {

// Joints in X: every non-root joint whose name the exclude pattern does not match.
std::vector<int> used_joints(const Skeleton& skeleton, const std::string& exclude) {
  std::optional<std::regex> pattern;
  if (!exclude.empty()) {
    try {
      pattern.emplace(exclude, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
      throw ParameterError("exclude: '" + exclude + "' is not a valid regular expression (" +
                           e.what() + ")");
    }
  }
  std::vector<int> joints;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    if (skeleton.joints[j].parent < 0) continue;
    if (pattern && std::regex_match(skeleton.joints[j].name, *pattern)) continue;
    joints.push_back(j);
  }
  if (joints.empty()) {
    throw ParameterError("exclude: '" + exclude + "' leaves no joint to map (the skeleton has " +
                         std::to_string(skeleton.num_joints()) + " joints, roots are never used)");
  }
  return joints;
}

// Columns of heading_local_points() that belong to kept joints (the roots' too: the point cloud
// holds the whole body) and their end sites.
std::vector<Eigen::Index> kept_point_columns(const Skeleton& skeleton,
                                             const std::vector<int>& used) {
  std::vector<bool> keep(static_cast<std::size_t>(skeleton.num_joints()), false);
  for (int j : used) keep[static_cast<std::size_t>(j)] = true;
  for (int r : skeleton.roots()) keep[static_cast<std::size_t>(r)] = true;
  std::vector<Eigen::Index> cols;
  const int joints = skeleton.num_joints();
  for (int j = 0; j < joints; ++j) {
    if (keep[static_cast<std::size_t>(j)]) {
      for (int c = 0; c < 3; ++c) cols.push_back(3 * j + c);
    }
  }
  int site = 0;
  for (int j = 0; j < joints; ++j) {
    for (std::size_t e = 0; e < skeleton.joints[j].end_sites.size(); ++e, ++site) {
      if (keep[static_cast<std::size_t>(j)]) {
        for (int c = 0; c < 3; ++c) cols.push_back(3 * (joints + site) + c);
      }
    }
  }
  return cols;
}

/// The samples of `clips` (clip_of, frame_of, segment_starts, joints, notes; no X or D) and, per
/// clip, its heading-local point cloud (all frames) and the frames selected.
struct Selection {
  FeatureSet set;
  std::vector<RowMatrix> clouds;
  std::vector<std::vector<int>> frames;
};

Selection select(std::span<const Clip> clips, const FeatureOptions& options) {
  options.validate();
  if (clips.empty()) throw ParameterError("no clip given");
  const Skeleton& skeleton = clips.front().skeleton;
  for (const Clip& clip : clips) {
    if (!clip.skeleton.same_hierarchy(skeleton)) {
      throw ParameterError(clip.path + ": its joint hierarchy (names and parents) differs from " +
                           clips.front().path + "'s; clips mapped together must share one");
    }
    if (clip.motion.num_frames == 0) throw ParameterError(clip.path + ": the clip has no frames");
    check_clip(clip);
  }

  Selection out;
  FeatureSet& set = out.set;
  set.joints = used_joints(skeleton, options.exclude);
  for (const Clip& clip : clips) {
    RowMatrix cloud = detail::checked_heading_local_points(clip.skeleton, clip.motion, options.up);
    int first = options.first_frame;
    if (first == 0 && !options.keep_first) {
      const BindPoseCheck bind = check_leading_bind_pose(cloud);
      if (bind.detected) {
        first = 1;
        set.notes.push_back(
            base_name(clip.path) + ": frame 0 looks like a bind pose (" +
            std::to_string(static_cast<long long>(std::min(bind.ratio, 1e9))) +
            "× the median step away from frame 1): left out (--keep-first keeps it)");
      }
    }
    const int end = options.end_frame < 0 ? clip.motion.num_frames
                                          : std::min(options.end_frame, clip.motion.num_frames);
    std::vector<int> frames;
    for (int f = first; f < end; f += options.stride) frames.push_back(f);
    if (frames.empty()) {
      throw ParameterError(
          clip.path + ": the frame selection " + std::to_string(options.first_frame) + ":" +
          (options.end_frame < 0 ? std::string() : std::to_string(options.end_frame)) +
          " with stride " + std::to_string(options.stride) + " holds no frame (the clip has " +
          std::to_string(clip.motion.num_frames) + ")");
    }
    set.segment_starts.push_back(set.num_samples());
    const int c = static_cast<int>(out.frames.size());
    for (int f : frames) {
      set.clip_of.push_back(c);
      set.frame_of.push_back(f);
    }
    out.clouds.push_back(std::move(cloud));
    out.frames.push_back(std::move(frames));
  }
  return out;
}

}  // namespace

FeatureSet select_samples(std::span<const Clip> clips, const FeatureOptions& options) {
  return select(clips, options).set;
}

FeatureSet build_features(std::span<const Clip> clips, const FeatureOptions& options,
                          const Control& control, Distances distances) {
  Selection selection = select(clips, options);
  FeatureSet set = std::move(selection.set);
  const Skeleton& skeleton = clips.front().skeleton;
  const auto point_cols = kept_point_columns(skeleton, set.joints);

  std::vector<RowMatrix> x_blocks;
  std::vector<RowMatrix> cloud_blocks;
  for (std::size_t c = 0; c < clips.size(); ++c) {
    const std::vector<int>& frames = selection.frames[c];
    const RowMatrix& cloud = selection.clouds[c];
    if (options.features == FeatureKind::Quaternions ||
        options.distance == DistanceKind::Geodesic) {
      x_blocks.push_back(quaternion_block(clips[c].motion, set.joints, frames));
    }
    RowMatrix kept(static_cast<Eigen::Index>(frames.size()),
                   static_cast<Eigen::Index>(point_cols.size()));
    for (std::size_t r = 0; r < frames.size(); ++r) {
      for (std::size_t k = 0; k < point_cols.size(); ++k)
        kept(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) =
            cloud(frames[r], point_cols[k]);
    }
    cloud_blocks.push_back(std::move(kept));
  }

  const Eigen::Index n = set.num_samples();
  auto stack = [n](std::vector<RowMatrix>& blocks) {
    Eigen::Index cols = blocks.front().cols(), row = 0;
    RowMatrix out(n, cols);
    for (auto& b : blocks) {
      out.middleRows(row, b.rows()) = b;
      row += b.rows();
      b = RowMatrix();
    }
    return out;
  };
  RowMatrix cloud = stack(cloud_blocks);
  RowMatrix quats;
  if (!x_blocks.empty()) quats = stack(x_blocks);
  set.X = options.features == FeatureKind::Quaternions ? Eigen::MatrixXd(quats)
                                                       : Eigen::MatrixXd(cloud);

  // Every frame as far from the first as rounding goes (point clouds: relative to their size,
  // since removing a moving root's floor translation is not exact in floating point).
  set.distance = options.distance;
  double farthest = 0.0;
  switch (options.distance) {
    case DistanceKind::PointCloud:
      for (Eigen::Index j = 1; j < n; ++j)
        farthest = std::max(farthest, point_distance(cloud, 0, j));
      set.distance_input = std::move(cloud);
      break;
    case DistanceKind::Geodesic:
      for (Eigen::Index j = 1; j < n; ++j)
        farthest = std::max(farthest, geodesic_distance(quats, 0, j));
      set.distance_input = std::move(quats);
      break;
    case DistanceKind::Features:
      set.distance_input = set.X;  // row-major, as the distance loops read it
      for (Eigen::Index j = 1; j < n; ++j)
        farthest = std::max(farthest, point_distance(set.distance_input, 0, j));
      break;
  }
  const double same = 1e-9 * (options.distance == DistanceKind::PointCloud
                                  ? 1.0 + set.distance_input.cwiseAbs().maxCoeff()
                                  : 1.0);
  if (n > 1 && farthest <= same) {
    set.notes.push_back("every frame has the same pose (distance " +
                        std::string(distance_kind_name(options.distance)) +
                        " 0 between all of them): a map can only show one point");
  }
  if (distances == Distances::Now) add_distances(set, control);
  return set;
}

void add_distances(FeatureSet& set, const Control& control) {
  if (set.has_distances() || set.num_samples() == 0) return;
  set.D = set.distance == DistanceKind::Geodesic ? geodesic_distances(set.distance_input, control)
                                                 : pairwise_distances(set.distance_input, control);
}

}  // namespace motionmap::features
