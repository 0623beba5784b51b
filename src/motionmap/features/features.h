#pragma once
// The inputs of the maps, built from one or more clips:
//  - X, the data matrix (#samples by 4·#joints used): every non-root joint's local rotation
//    quaternion (w, x, y, z), sign-consistent over time; or, with FeatureKind::Positions, the
//    heading-local point cloud;
//  - D, the pose distance matrix (#samples by #samples): by default the point-cloud distance
//    (Euclidean distance between heading-local joint and end-site positions).
//
//   motionmap::features::FeatureOptions opt;            // quaternions + point-cloud distance
//   auto set = motionmap::features::build_features(clips, opt);
//   // set.X, set.D, set.frame_of[i] = file frame of sample i, set.notes = what was left out
//
// D costs O(#samples²) time and memory (3.2 GB at 20 000 frames) and PCA and SVD never read it:
// build_features(…, Distances::Later) leaves it out, and add_distances() computes it when a
// method or a metric asks for it.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::features {

enum class FeatureKind { Quaternions, Positions };
enum class DistanceKind { PointCloud, Geodesic, Features };
/// Which joints clips are compared by (FeatureOptions::joints).
enum class JointSelection {
  /// Every joint of the one hierarchy all clips must share (names and parents).
  All,
  /// The joints whose names every clip has (common_joint_names()): clips of different skeletons
  /// in one map.
  Common,
};

/// "quat" / "positions".
std::string_view feature_kind_name(FeatureKind k);
/// The kind named `name` (as feature_kind_name writes it), or nullopt.
std::optional<FeatureKind> parse_feature_kind(std::string_view name);
/// Every feature kind, in the enum's order.
const std::vector<FeatureKind>& all_feature_kinds();

/// "pointcloud" / "geodesic" / "features".
std::string_view distance_kind_name(DistanceKind k);
/// The kind named `name` (as distance_kind_name writes it), or nullopt.
std::optional<DistanceKind> parse_distance_kind(std::string_view name);
/// Every distance kind, in the enum's order.
const std::vector<DistanceKind>& all_distance_kinds();

/// "all" / "common".
std::string_view joint_selection_name(JointSelection s);
/// The selection named `name` (as joint_selection_name writes it), or nullopt.
std::optional<JointSelection> parse_joint_selection(std::string_view name);
/// Every joint selection, in the enum's order.
const std::vector<JointSelection>& all_joint_selections();

struct FeatureOptions {
  FeatureKind features = FeatureKind::Quaternions;
  DistanceKind distance = DistanceKind::PointCloud;
  Axis up = Axis::Y;
  /// ECMAScript regular expression; joints whose whole name matches are left out of X and D
  /// (with their end sites), e.g. ".*(Thumb|Finger).*". Empty: keep every joint.
  std::string exclude;
  int first_frame = 0;  ///< first file frame used (per clip)
  int end_frame = -1;   ///< one past the last file frame used; −1 = the clip's end
  int stride = 1;       ///< use every stride-th frame from first_frame
  /// Keep a leading bind pose (frame 0 farther from frame 1 than 10× the median step and 20× the
  /// next steps: check_leading_bind_pose); by default it is left out and a note says so.
  bool keep_first = false;
  /// All: the clips must share one joint hierarchy, and every joint is used. Common: the clips
  /// may come from different skeletons; they are compared by the joints whose names all of them
  /// have, each clip computing its point cloud by its own forward kinematics and its own motion
  /// root (so heading and floor position are each clip's), and its quaternions from its own
  /// joints of those names:
  ///  - X: the shared joints that are a root in no clip (and not excluded), in the first clip's
  ///    joint order;
  ///  - point cloud: those joints and the shared joints that are a root in some clip, plus the
  ///    End Sites of such a joint when every clip gives it the same number of End Sites (a joint
  ///    that is a leaf in one skeleton and has children in another loses its End Site);
  ///  - notes: how many joints were kept, which each skeleton lost, and the kept joints whose
  ///    parent has another name in some clip (their local rotations are measured against
  ///    different bones, which matters to the quaternion features and the geodesic distance).
  /// With clips of one hierarchy, Common gives the same X and D as All.
  JointSelection joints = JointSelection::All;

  /// @throws ParameterError naming the option, its value and the valid range.
  void validate() const;
};

/// The feature set of a map: matrices plus where every sample came from.
struct FeatureSet {
  Eigen::MatrixXd X;  ///< #samples by #features (no rows after pipeline::map_features() of a map
                      ///< that does not read X)
  Eigen::MatrixXd D;  ///< #samples by #samples, symmetric, zero diagonal
  std::vector<int> clip_of;         ///< per sample: index of its clip
  std::vector<int> frame_of;        ///< per sample: its frame index in the clip's file
  std::vector<int> segment_starts;  ///< first sample of each clip
  /// Skeleton joints used in X (non-root, not excluded), as indices of the first clip's skeleton
  /// (with JointSelection::Common the other clips' joints of the same names may have others).
  std::vector<int> joints;
  std::vector<std::string> notes;  ///< e.g. "64_08.bvh: frame 0 looks like a bind pose: left out"
  /// What D is computed from (and what the maps that never form D read): the kept point clouds
  /// (PointCloud), the quaternions (Geodesic), or X in row-major order (Features).
  DistanceKind distance = DistanceKind::PointCloud;
  RowMatrix distance_input;

  int num_samples() const { return static_cast<int>(frame_of.size()); }
  /// Whether D has been computed.
  bool has_distances() const { return D.rows() == num_samples() && num_samples() > 0; }
};

/// Whether build_features() computes D now or leaves it to add_distances().
enum class Distances { Now, Later };

/// Builds X and D for `clips`, which must share one joint hierarchy (names and parents; offsets
/// may differ: each clip uses its own for forward kinematics) unless options.joints is
/// JointSelection::Common. Every clip goes through check_clip() (MotionCheck::Values) first.
/// @throws ParameterError for bad options; clips of different hierarchies (naming the first
///         clip that differs and how, see hierarchy_difference(), and suggesting --joints
///         common); clips that share no joint name or no non-root joint (Common); a selection
///         with no frames; an exclude pattern that is invalid or leaves no joint; or a clip whose
///         motion does not fit its skeleton (sizes, parents, frame time);
///         NumericalError if a clip holds NaN, infinite or zero values (messages name the clip's
///         path, frame and joint); Cancelled if `control` says so.
FeatureSet build_features(std::span<const Clip> clips, const FeatureOptions& options,
                          const Control& control = {}, Distances distances = Distances::Now);

/// JointSelection::All's test of a clip against the set's first clip. @throws ParameterError
///   naming `clip` and how its joint hierarchy differs from `first`'s, and suggesting --joints
///   common.
void check_same_hierarchy(const Clip& clip, const Clip& first);

/// One clip of a larger set, for a library read a clip at a time (pipeline/stream_map.h): its
/// rows of X and of distance_input, frame_of, segment_starts {0}, joints and its own notes (its
/// bind pose) exactly as build_features() of the whole set gives them for that clip (a clip's
/// rows depend on that clip only). `first` is the set's first clip, whose joint hierarchy every
/// clip must share; the set's "every frame has the same pose" note needs every clip:
/// SamePoseCheck. @throws as build_features(); ParameterError for JointSelection::Common (the
///   joints shared are known only once every clip is read) or a clip of another hierarchy
///   (naming it and how it differs from `first`).
FeatureSet clip_rows(const Clip& clip, const Clip& first, const FeatureOptions& options);

/// The note build_features() adds when every frame of a set has the same pose.
std::string same_pose_note(DistanceKind distance);

/// build_features()'s "every frame has the same pose" test over a set given a clip at a time
/// (clip_rows() of each clip, in order): every frame's distance from the set's first frame, to
/// rounding.
class SamePoseCheck {
 public:
  void add(const FeatureSet& rows);
  /// same_pose_note() when every frame added has the first one's pose.
  std::optional<std::string> note(DistanceKind distance) const;

 private:
  Eigen::RowVectorXd m_first;
  double m_farthest = 0.0, m_largest = 0.0;
  Eigen::Index m_samples = 0;
};

/// Computes D of a set built with Distances::Later (nothing when D is there already). What it is
/// computed from stays (it is #samples by a few hundred at most; the maps that never form D read
/// it). @throws Cancelled if `control` says so.
void add_distances(FeatureSet& set, const Control& control = {});

/// The samples build_features() would use — clip_of, frame_of, segment_starts, joints and notes,
/// with X and D left empty — at the cost of forward kinematics only. For checking that a map
/// computed earlier (a CSV) belongs to the clips. @throws as build_features().
FeatureSet select_samples(std::span<const Clip> clips, const FeatureOptions& options);

/// Sign-consistent local rotation quaternions: #frames by 4·#joints (w, x, y, z per joint) of
/// the given frames; row 0 has w ≥ 0 per joint, every later row flips a joint's quaternion whose
/// dot product with the previous row's is negative.
/// @throws ParameterError if `motion` fails check_motion(motion, …) (sizes, frame time) or a
///         joint or frame index is out of range; NumericalError for NaN, infinite or zero
///         rotations or non-finite translations.
Eigen::MatrixXd quaternion_features(const Motion& motion, std::span<const int> joints,
                                    std::span<const int> frames);

/// Euclidean distances between the rows of `points` (#rows by #rows), computed directly (no
/// Gram-matrix shortcut, which loses accuracy for nearby poses) on all cores.
Eigen::MatrixXd pairwise_distances(const Eigen::Ref<const RowMatrix>& points,
                                   const Control& control = {});

/// Geodesic pose distance between rows of quaternion features (4 values per joint):
/// sqrt(Σ_j θ_j²) with θ_j = 2·acos|q_a,j · q_b,j|.
Eigen::MatrixXd geodesic_distances(const Eigen::Ref<const RowMatrix>& quaternions,
                                   const Control& control = {});

}  // namespace motionmap::features
