#include "motionmap/features/features.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/features/detail/point_cloud.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/features/joint_match.h"

namespace motionmap::features {

namespace {
constexpr EnumName<FeatureKind> kFeatureKinds[] = {{FeatureKind::Quaternions, "quat"},
                                                   {FeatureKind::Positions, "positions"}};
constexpr EnumName<DistanceKind> kDistanceKinds[] = {{DistanceKind::PointCloud, "pointcloud"},
                                                     {DistanceKind::Geodesic, "geodesic"},
                                                     {DistanceKind::Features, "features"}};
constexpr EnumName<JointSelection> kJointSelections[] = {{JointSelection::All, "all"},
                                                         {JointSelection::Common, "common"}};
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

std::string_view joint_selection_name(JointSelection s) {
  return enum_name(kJointSelections, s);
}
std::optional<JointSelection> parse_joint_selection(std::string_view name) {
  return parse_enum(kJointSelections, name);
}
const std::vector<JointSelection>& all_joint_selections() {
  static const std::vector<JointSelection> selections = enum_values(kJointSelections);
  return selections;
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

// The exclude pattern, compiled; nullopt when empty.
std::optional<std::regex> exclude_pattern(const std::string& exclude) {
  std::optional<std::regex> pattern;
  if (!exclude.empty()) {
    try {
      pattern.emplace(exclude, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
      throw ParameterError("exclude: '" + exclude + "' is not a valid regular expression (" +
                           e.what() + ")");
    }
  }
  return pattern;
}

// Joints in X: every non-root joint whose name the exclude pattern does not match.
std::vector<int> used_joints(const Skeleton& skeleton, const std::string& exclude) {
  const std::optional<std::regex> pattern = exclude_pattern(exclude);
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

/// Which joints each clip puts in X and which columns of its point cloud it keeps, in one order
/// for every clip. With JointSelection::All one entry serves every clip.
struct JointPlan {
  std::vector<std::vector<int>> x_joints;
  std::vector<std::vector<Eigen::Index>> point_columns;

  const std::vector<int>& x(std::size_t clip) const {
    return x_joints.size() == 1 ? x_joints.front() : x_joints[clip];
  }
  const std::vector<Eigen::Index>& points(std::size_t clip) const {
    return point_columns.size() == 1 ? point_columns.front() : point_columns[clip];
  }
};

// JointSelection::Common: the shared joint names, matched in every clip (see FeatureOptions),
// with the notes that say what was kept and dropped.
JointPlan plan_common_joints(std::span<const Clip> clips, const FeatureOptions& options,
                             std::vector<std::string>& notes) {
  const std::vector<std::string> names = common_joint_names(clips);
  const Clip& first = clips.front();
  if (names.empty()) {
    std::string why;
    for (const Clip& clip : clips) {
      const std::vector<Clip> pair{first, clip};
      if (common_joint_names(pair).empty()) {
        why = base_name(clip.path) + " has none of " + base_name(first.path) + "'s joints, e.g. '" +
              first.skeleton.joints.front().name + "'";
        break;
      }
    }
    if (why.empty()) why = "each of " + base_name(first.path) + "'s joints is missing somewhere";
    throw ParameterError("joints common: the clips share no joint name (" + why + ")");
  }
  const std::size_t n = clips.size(), k_count = names.size();
  // index[c][k]: clip c's joint called names[k].
  std::vector<std::vector<int>> index(n, std::vector<int>(k_count));
  std::vector<bool> root(k_count, false);
  for (std::size_t c = 0; c < n; ++c) {
    for (std::size_t k = 0; k < k_count; ++k) {
      const int j = clips[c].skeleton.find(names[k]);
      index[c][k] = j;
      if (clips[c].skeleton.joints[static_cast<std::size_t>(j)].parent < 0) root[k] = true;
    }
  }
  const std::optional<std::regex> pattern = exclude_pattern(options.exclude);
  std::vector<std::size_t> in_x, in_cloud;
  std::vector<std::string> root_names;
  for (std::size_t k = 0; k < k_count; ++k) {
    const bool excluded = pattern && std::regex_match(names[k], *pattern);
    if (!root[k] && !excluded) in_x.push_back(k);
    if (root[k] || !excluded) in_cloud.push_back(k);
    if (root[k]) root_names.push_back(names[k]);
  }
  if (in_x.empty()) {
    if (root_names.size() == k_count) {
      throw ParameterError(
          "joints common: the clips share only " + name_list(root_names) +
          (k_count == 1 ? ", a root in some clip, which X never uses (it carries the heading)"
                        : ", roots in some clip, which X never uses (they carry the heading)"));
    }
    throw ParameterError("exclude: '" + options.exclude + "' leaves no joint to map (the clips " +
                         "share " + std::to_string(k_count) + " joints, roots are never used)");
  }
  // End Sites of a point-cloud joint that has as many in every clip.
  std::vector<std::size_t> with_sites;
  std::size_t sites = 0;
  for (const std::size_t k : in_cloud) {
    const std::size_t count =
        first.skeleton.joints[static_cast<std::size_t>(index[0][k])].end_sites.size();
    bool same = count > 0;
    for (std::size_t c = 1; c < n && same; ++c) {
      same =
          clips[c].skeleton.joints[static_cast<std::size_t>(index[c][k])].end_sites.size() == count;
    }
    if (same) {
      with_sites.push_back(k);
      sites += count;
    }
  }

  JointPlan plan;
  for (std::size_t c = 0; c < n; ++c) {
    const Skeleton& s = clips[c].skeleton;
    auto& x = plan.x_joints.emplace_back();
    for (const std::size_t k : in_x) x.push_back(index[c][k]);
    auto& cols = plan.point_columns.emplace_back();
    for (const std::size_t k : in_cloud) {
      for (int a = 0; a < 3; ++a) cols.push_back(3 * Eigen::Index{index[c][k]} + a);
    }
    // heading_local_points() lists End Sites after the joints, in joint order.
    std::vector<int> first_site(static_cast<std::size_t>(s.num_joints()), 0);
    for (int j = 1; j < s.num_joints(); ++j) {
      first_site[static_cast<std::size_t>(j)] =
          first_site[static_cast<std::size_t>(j) - 1] +
          static_cast<int>(s.joints[static_cast<std::size_t>(j) - 1].end_sites.size());
    }
    for (const std::size_t k : with_sites) {
      const auto j = static_cast<std::size_t>(index[c][k]);
      for (std::size_t e = 0; e < s.joints[j].end_sites.size(); ++e) {
        const Eigen::Index point = s.num_joints() + first_site[j] + static_cast<Eigen::Index>(e);
        for (int a = 0; a < 3; ++a) cols.push_back(3 * point + a);
      }
    }
  }

  // What was kept and dropped, skeletons with the same dropped joints together.
  const bool all_kept = std::all_of(clips.begin(), clips.end(), [&](const Clip& clip) {
    return clip.skeleton.num_joints() == static_cast<int>(k_count);
  });
  if (all_kept) {
    notes.push_back("joints common: " + (n == 1 ? std::string("a single clip: all ") +
                                                      std::to_string(k_count) + " joints kept"
                                                : "the " + std::to_string(n) + " clips share all " +
                                                      std::to_string(k_count) + " joints"));
  } else {
    std::vector<std::pair<std::vector<std::string>, std::vector<std::size_t>>> dropped;
    for (std::size_t c = 0; c < n; ++c) {
      std::vector<std::string> lost;
      for (const Joint& j : clips[c].skeleton.joints) {
        if (std::find(names.begin(), names.end(), j.name) == names.end()) lost.push_back(j.name);
      }
      if (lost.empty()) continue;
      auto same = std::find_if(dropped.begin(), dropped.end(),
                               [&](const auto& d) { return d.first == lost; });
      if (same == dropped.end()) {
        dropped.push_back({std::move(lost), {c}});
      } else {
        same->second.push_back(c);
      }
    }
    std::string note = "joints common: " + std::to_string(k_count) + " joints shared by the " +
                       std::to_string(n) + " clips are kept (" + std::to_string(in_x.size()) +
                       " in X, ";
    if (!root_names.empty()) {
      note += std::string(root_names.size() == 1 ? "the root " : "the roots ") +
              name_list(root_names) + " only in the point cloud, ";
    }
    note += (sites == 0 ? std::string("no End Site")
                        : std::to_string(sites) + (sites == 1 ? " End Site" : " End Sites")) +
            "): " + name_list(names, names.size()) + "; dropped: ";
    for (std::size_t d = 0; d < dropped.size(); ++d) {
      const auto& [lost, which] = dropped[d];
      note += (d ? ", " : "") + name_list(lost, 40) + " (" + base_name(clips[which[0]].path);
      if (which.size() > 1) {
        note += " and " + std::to_string(which.size() - 1) +
                (which.size() == 2 ? " more clip" : " more clips");
      }
      note += ")";
    }
    notes.push_back(std::move(note));
  }

  // Local rotations are relative to the parent: a parent of another name is another reference.
  if (options.features == FeatureKind::Quaternions || options.distance == DistanceKind::Geodesic) {
    std::vector<std::string> moved;
    auto parent_name = [&](std::size_t c, std::size_t k) {
      const Skeleton& s = clips[c].skeleton;
      const int p = s.joints[static_cast<std::size_t>(index[c][k])].parent;
      return p < 0 ? std::string() : s.joints[static_cast<std::size_t>(p)].name;
    };
    for (const std::size_t k : in_x) {
      const std::string mine = parent_name(0, k);
      for (std::size_t c = 1; c < n; ++c) {
        const std::string theirs = parent_name(c, k);
        if (theirs != mine) {
          moved.push_back(names[k] + " (parent '" + mine + "' in " + base_name(first.path) + ", '" +
                          theirs + "' in " + base_name(clips[c].path) + ")");
          break;
        }
      }
    }
    if (!moved.empty()) {
      const bool one = moved.size() == 1;
      notes.push_back(
          "joints common: " + std::to_string(moved.size()) +
          (one ? " kept joint has another parent in some clip, so its local rotation is measured "
                 "against another bone there"
               : " kept joints have another parent in some clip, so their local rotations are "
                 "measured against other bones there") +
          " (quaternion features, geodesic distance): " + name_list(moved, 8));
    }
  }
  return plan;
}

/// The samples of `clips` (clip_of, frame_of, segment_starts, joints, notes; no X or D) and, per
/// clip, the frames selected and the joints and point-cloud columns it contributes. With
/// `points`, also the selected frames' heading-local point clouds (those columns: what D is
/// computed from), #samples by #columns, written in place as each clip's are computed.
struct Selection {
  FeatureSet set;
  std::vector<std::vector<int>> frames;
  JointPlan plan;
};

Selection select(std::span<const Clip> clips, const FeatureOptions& options,
                 RowMatrix* points = nullptr) {
  options.validate();
  if (clips.empty()) throw ParameterError("no clip given");
  const Skeleton& skeleton = clips.front().skeleton;
  for (const Clip& clip : clips) {
    if (options.joints == JointSelection::All) check_same_hierarchy(clip, clips.front());
    if (clip.motion.num_frames == 0) throw ParameterError(clip.path + ": the clip has no frames");
    check_clip(clip);
  }

  Selection out;
  FeatureSet& set = out.set;
  if (options.joints == JointSelection::Common) {
    out.plan = plan_common_joints(clips, options, set.notes);
    set.joints = out.plan.x_joints.front();
  } else {
    set.joints = used_joints(skeleton, options.exclude);
    out.plan.x_joints.push_back(set.joints);
    out.plan.point_columns.push_back(kept_point_columns(skeleton, set.joints));
  }
  if (points) {
    // Room for every frame; cut to the samples at the end (a row-major matrix keeps its first
    // rows in place when it shrinks).
    Eigen::Index bound = 0;
    for (const Clip& clip : clips) bound += clip.motion.num_frames;
    points->resize(bound, static_cast<Eigen::Index>(out.plan.points(0).size()));
  }
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
    if (points) {
      const std::vector<Eigen::Index>& point_cols = out.plan.points(std::size_t(c));
      const Eigen::Index row = set.segment_starts.back();
      for (std::size_t r = 0; r < frames.size(); ++r) {
        for (std::size_t k = 0; k < point_cols.size(); ++k) {
          (*points)(row + static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) =
              cloud(frames[r], point_cols[k]);
        }
      }
    }
    out.frames.push_back(std::move(frames));
  }
  if (points) points->conservativeResize(set.num_samples(), points->cols());
  return out;
}

}  // namespace

FeatureSet select_samples(std::span<const Clip> clips, const FeatureOptions& options) {
  return select(clips, options).set;
}

void check_same_hierarchy(const Clip& clip, const Clip& first) {
  if (clip.skeleton.same_hierarchy(first.skeleton)) return;
  throw ParameterError(clip.path + ": its joint hierarchy differs from " + first.path + "'s (" +
                       hierarchy_difference(first, clip) +
                       "); clips mapped together must share one (joint names and parents), or be "
                       "mapped by the joints whose names they all have: --joints common");
}

namespace {

// build_features() without D; `whole_set`: the clips are the whole set, so the set's "same pose"
// note is decided here (clip_rows() gives one clip of a larger set).
FeatureSet build_rows(std::span<const Clip> clips, const FeatureOptions& options, bool whole_set) {
  RowMatrix cloud;
  Selection selection = select(clips, options, &cloud);
  FeatureSet set = std::move(selection.set);

  // Each matrix is allocated once and filled clip by clip. (Whole point clouds, blocks of the kept
  // columns, the quaternions stacked and then copied into X held every value two or three times:
  // a peak of 6.3 GB at 10⁶ library frames, against 3.6 GB now, the clips themselves included.)
  const Eigen::Index n = set.num_samples();
  const bool geodesic = options.distance == DistanceKind::Geodesic;
  const bool quaternions = options.features == FeatureKind::Quaternions || geodesic;
  RowMatrix quats;  // the distance input of DistanceKind::Geodesic
  if (quaternions) {
    const Eigen::Index cols = 4 * static_cast<Eigen::Index>(selection.plan.x(0).size());
    if (geodesic) {
      quats.resize(n, cols);
    } else {
      set.X.resize(n, cols);
    }
  }
  Eigen::Index row = 0;
  for (std::size_t c = 0; c < clips.size(); ++c) {
    const std::vector<int>& frames = selection.frames[c];
    const Eigen::Index rows = static_cast<Eigen::Index>(frames.size());
    if (quaternions) {
      const Eigen::MatrixXd block = quaternion_block(clips[c].motion, selection.plan.x(c), frames);
      if (geodesic) {
        quats.middleRows(row, rows) = block;
      } else {
        set.X.middleRows(row, rows) = block;
      }
    }
    row += rows;
  }
  if (options.features == FeatureKind::Positions) {
    set.X = Eigen::MatrixXd(cloud);
  } else if (geodesic) {
    set.X = Eigen::MatrixXd(quats);
  }

  set.distance = options.distance;
  if (!whole_set) {
    set.distance_input = options.distance == DistanceKind::PointCloud ? std::move(cloud)
                         : options.distance == DistanceKind::Geodesic ? std::move(quats)
                                                                      : RowMatrix(set.X);
    return set;
  }
  // Every frame as far from the first as rounding goes (point clouds: relative to their size,
  // since removing a moving root's floor translation is not exact in floating point).
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
  if (n > 1 && farthest <= same) set.notes.push_back(same_pose_note(options.distance));
  return set;
}

}  // namespace

std::string same_pose_note(DistanceKind distance) {
  return "every frame has the same pose (distance " + std::string(distance_kind_name(distance)) +
         " 0 between all of them): a map can only show one point";
}

FeatureSet build_features(std::span<const Clip> clips, const FeatureOptions& options,
                          const Control& control, Distances distances) {
  FeatureSet set = build_rows(clips, options, true);
  if (distances == Distances::Now) add_distances(set, control);
  return set;
}

FeatureSet clip_rows(const Clip& clip, const Clip& first, const FeatureOptions& options) {
  if (options.joints != JointSelection::All) {
    throw ParameterError(
        "joints common: the joints all clips share are known only once every clip is read; a "
        "library read a clip at a time maps by all joints (--joints all)");
  }
  check_same_hierarchy(clip, first);
  return build_rows(std::span<const Clip>(&clip, 1), options, false);
}

void SamePoseCheck::add(const FeatureSet& rows) {
  const RowMatrix& points = rows.distance_input;
  if (points.rows() == 0) return;
  if (m_first.size() == 0) m_first = points.row(0);
  for (Eigen::Index j = 0; j < points.rows(); ++j) {
    const double d = rows.distance == DistanceKind::Geodesic
                         ? quaternion_angle_distance(m_first, points.row(j))
                         : euclidean_distance(m_first, points.row(j));
    m_farthest = std::max(m_farthest, d);
  }
  m_largest = std::max(m_largest, points.cwiseAbs().maxCoeff());
  m_samples += points.rows();
}

std::optional<std::string> SamePoseCheck::note(DistanceKind distance) const {
  const double same = 1e-9 * (distance == DistanceKind::PointCloud ? 1.0 + m_largest : 1.0);
  if (m_samples > 1 && m_farthest <= same) return same_pose_note(distance);
  return std::nullopt;
}

void add_distances(FeatureSet& set, const Control& control) {
  if (set.has_distances() || set.num_samples() == 0) return;
  set.D = set.distance == DistanceKind::Geodesic ? geodesic_distances(set.distance_input, control)
                                                 : pairwise_distances(set.distance_input, control);
}

}  // namespace motionmap::features
