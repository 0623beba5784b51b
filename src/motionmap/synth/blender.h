#pragma once
// Map point → pose: the weights a point of a 2-D motion map gives every sample (frame) of the
// clips the map was built from, and the pose blended from the samples with those weights.
//
//   motionmap::synth::BlendOptions opt;                    // local kriging, K = 12, reach 3
//   motionmap::synth::MapBlender blender(clips, set, coords, opt);
//   motionmap::Motion pose = blender.pose_at({0.3, -1.2});  // one frame, at the origin, facing +Z
//   auto w = blender.locate({0.3, -1.2});                   // weights and validity of that point
//   if (w.validity.clamped) { /* the point was outside the data and moved to its edge */ }
//
// Weights (see docs/synthesis.md for the maths):
//  - Kriging: ordinary kriging with a linear variogram over all samples. With A_ij = ‖c_i − c_j‖
//    and a_i = ‖c_i − p‖ it solves [A 1; 1ᵀ 0]·[w; μ] = [a; 1]; the (N+1)² matrix is LU-factored
//    once, in the constructor (in chunks that can be cancelled), so a query is O(N²).
//  - Local (default): kriging on small neighbourhoods, made continuous. Every sample i has its
//    own system on K mutually separated map neighbours (itself included), factored once; a
//    query blends the predictions of the 4 map-nearest samples' systems with partition-of-unity
//    weights (Franke–Little: ((R − d)/(R·d))², R = distance of the 5th nearest) that are 1 at a
//    sample and fall to 0 before a sample leaves the 4 nearest. Along a path (locate_path) it
//    also plays the clips themselves where the path follows one: each segment between consecutive
//    samples of a clip (≤ kTrajectoryMaxSeconds apart) within kFollowSearch median steps of
//    frame k's point starts a fit of a clip time τ and a rate r ∈ [kFollowMinRate,
//    kFollowMaxRate] that lay the clip's trajectory T(τ + r·j·Δt) on the path's points p_{k+j},
//    |j·Δt| ≤ kFollowSeconds (Gauss–Newton on the weighted mean squared distance D, weights
//    1 − |j|/(h + 1)). The least D, as an RMS in median steps, gives the clips' share: 1 up to
//    kFollowNear, 0 from kFollowFar, smoothstep between; the fits within a tie of it (D ≤
//    (1 + kFollowTie)·D_min + (kFollowTieSteps steps)²) share that part, each on its two samples
//    around τ, (1 − t, t); the local kriging takes the rest. A fit's D rises towards kFollowFar's
//    as its point at frame k nears the search radius, so every share is continuous along the
//    path. So a path along a clip's curve at its pace replays the clip, between samples too (D =
//    0, one fit); one drawn near the curve by hand plays a gait cycle through rather than sliding
//    between cycles; one that crosses it, runs against it, or at over twice or under half its
//    pace keeps the kriging blend. Then, on a map of walks or runs, every clip time the frame
//    blends (each sample the kriging weighs, each fitted time) is moved in its clip to one gait
//    phase, read off the frames ±kPhaseWindowSeconds around it at the clips' cadence, so that a
//    left stance is never blended with a right one, and the frame's pace (MapWeights::pace) is
//    how fast that phase advances, so that the root moves on as far as the legs step
//    (detail/gait_phase.h).
//  - Idw: Franke–Little inverse-distance weights on the K nearest samples (R = distance of the
//    (K+1)-th): non-negative, continuous, the robust fallback.
//  - Gp (a GP-LVM map's default; needs BlendOptions::gplvm): the GP's predictive mean as
//    weights over every sample (embed::GplvmMap::frame_weights: w' = W k(p) + (1 − Σw)/N, summing
//    to 1); the smallest, together at most kGpWeightTolerance of Σ|w'|, dropped and the rest
//    rescaled to sum to 1. For the quaternion features the blend is the GP's predictive mean,
//    normalised per joint; the root and every other value follow the same weights. A smoother, not
//    an interpolator: at a sample's own point it gives a pose near, not equal to, the sample's.
// The first three are exact at samples (the weights at a sample's own map point are 1 on it) and
// continuous in p. Samples closer to each other than 1e-9 × the map's extent share a map point
// and are merged: such a point gives each of them an equal share of the weight.
//
// Outside the data, on a GP-LVM map (BlendOptions::gplvm, in every mode): a point whose GP
// variance without the noise exceeds kGplvmValidFraction of its prior (embed::GplvmMap::inside)
// is moved, and reported, to the edge of that region on the segment towards its nearest sample
// (bisection to 1e-9 of the segment), or to the sample itself when that is outside too; this is
// continuous in p except where two samples are equally near. PointValidity::variance is then the
// GP's variance at the point evaluated.
//
// Outside the data, on other maps: a point farther from every sample than r = reach_radius() (reach
// × the median step between consecutive samples, at least 5 % of the map's size) is moved, and
// reported: to the nearest point q of the trajectory (the polyline through consecutive samples of
// each clip), then back towards the point by √(r² − e²), e = the distance from q to the nearer end
// of its segment, so it lands within r of that sample. This is continuous in p except where two
// stretches of trajectory are equally near (the nearest point of the union of reach disks would
// jump at every boundary between two samples' cells), and costs O(#samples), for outside points
// only.
//
// Blending: joint rotations per joint, every sample's quaternion aligned to the hemisphere of the
// largest-weight sample, weighted sum, normalised (negative weights allowed; weighted_average in
// core/rotation.h). The root (the "motion root", see motion_root()) is split into heading (yaw
// about the up axis, from features::heading_angle), floor position, height and tilt (rotation
// with the heading removed); a blended pose keeps height and tilt and stands at the origin
// facing the heading-0 direction (+Z for the usual Y-up BVH). Its heading-local velocity and yaw
// rate are blended too, for synthesize() to integrate (synth/detail/root_motion.h). The arithmetic
// is blend_state.h's (sample_state, blend_states), which a saved map's pose uses too.
//
// A MapBlender copies what it needs from the clips; its const member functions are thread-safe.
// One made from a ClipSource instead (a saved map of 10⁶ frames: mapfile::make_blender) copies
// nothing up front: it reads the frames a blend uses from the source when it blends them and
// builds a local kriging system the first time a query needs it, and blends exactly (bit for
// bit) as one given every clip.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motionmap/core/control.h"
#include "motionmap/core/map_gp.h"
#include "motionmap/core/rotation.h"
#include "motionmap/features/features.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blend_state.h"
#include "motionmap/synth/path.h"

namespace motionmap::synth {

enum class BlendMode { Kriging, Local, Idw, Gp };

/// "kriging" / "local" / "idw" / "gp".
std::string_view blend_mode_name(BlendMode mode);
/// The mode called `name` (exact, lower case as blend_mode_name writes it), or nothing.
std::optional<BlendMode> parse_blend_mode(std::string_view name);
/// Every blend mode, the default (local) first.
const std::vector<BlendMode>& all_blend_modes();

/// Most merged map points the kriging mode factors: a (N+1)² dense matrix, 800 MB at 10 000.
inline constexpr int kMaxKrigingSamples = 10000;
/// Number of nearest samples whose local systems the local mode blends per query.
inline constexpr int kLocalPartitionSize = 4;

/// A path that follows a clip's trajectory plays that clip (locate_path, local mode; see the top of
/// the file). The window of path frames a frame's clip times are fitted to: ±this many seconds.
inline constexpr double kFollowSeconds = 0.25;
/// The window is compared every max(1, ⌊h / this⌋)-th frame (h: its half-width in frames).
inline constexpr int kFollowWindowPoints = 8;
/// Segments of the trajectory within this many median steps of a path point start a fit.
inline constexpr double kFollowSearch = 3.5;
/// A fitted clip time whose window stays within this many median steps of the path (RMS) plays
/// wholly; beyond kFollowFar it plays no part; between, it shares with the kriging. (A walk drawn
/// 1–2 steps beside a walk's curve is that walk: blended by the kriging there, its gait phases
/// mixed and its feet slid 106 cm/s in contact, against 68 as captured.)
inline constexpr double kFollowNear = 1.5;
inline constexpr double kFollowFar = 3.0;
/// Clip times whose fits' mean squared distances exceed the least, D, by less than
/// kFollowTie·D + (kFollowTieSteps median steps)² share the clips' part (1 − smoothstep of the
/// excess over that): several where the path is as near several, one where it runs on one.
inline constexpr double kFollowTie = 1.0;
inline constexpr double kFollowTieSteps = 0.02;
/// The rates a followed clip may play at (1: its own pace).
inline constexpr double kFollowMinRate = 0.5;
inline constexpr double kFollowMaxRate = 2.0;
/// At most this many clip times are fitted per frame (the nearest segments' first), each from a
/// different place in the clips (kFollowSameSeconds apart), by this many Gauss–Newton steps.
inline constexpr int kFollowTimelines = 16;
inline constexpr double kFollowSameSeconds = 0.1;
inline constexpr int kFollowIterations = 4;
/// The longest time between two consecutive samples whose segment locate_path starts a fit on.
inline constexpr double kTrajectoryMaxSeconds = 0.25;

/// The least reach radius, as a fraction of the map's size (the larger side of its samples'
/// bounding box): see reach_radius().
inline constexpr double kMinReachFraction = 0.05;

/// The gp mode drops its smallest weights while their magnitudes sum to at most this fraction of
/// Σ|w'|, and rescales the rest to sum to 1. The weights are dense and spread (Σ|w'| ≫ 1, the
/// normalised quaternion sum is sensitive to them): measured on CMU 64_08 (364 frames, full), a
/// 987-frame full and a 10 778-frame sparse map (docs/methods/gplvm.md), 10⁻⁵ moves a joint by at
/// most 3.5·10⁻⁴ rad and keeps 87–93 % of the frames; 10⁻⁴ already moves one by 4·10⁻³ rad.
inline constexpr double kGpWeightTolerance = 1e-5;

/// The one rule of where a map is valid, on maps other than GP-LVM maps (those use the GP's
/// variance: embed::GplvmMap::inside): a map point is inside the data when a sample lies within
/// max(reach × median_step, kMinReachFraction × map_size) of it. Blending clamps to it, Studio
/// shades it, routes keep to it. The multiple of the step keeps a coarse map's reach above its
/// gaps; the share of the map's size keeps a finely sampled one (120 fps, 4× shorter steps than
/// 30 fps) from shrinking to a thread around its trajectory. 0 for a map of one point.
double reach_radius(double reach, double median_step, double map_size);

/// Franke–Little partition-of-unity weights of `count` samples at ascending distances `d` (not
/// squared) from a map point, falling to 0 at radius R: ((R − d)/(R·d))², normalised. All the
/// weight goes to the nearest when it is within 1e-12·R (a hit) or alone; samples all at R share
/// it equally among the nearest. `phi`: `count` weights out. The idw and local blends use them,
/// with R the next sample's distance.
void franke_little_weights(const double* d, int count, double R, double* phi);

struct BlendOptions {
  BlendMode mode = BlendMode::Local;
  /// K: samples per local system (local) or samples blended (idw), in [1, #samples]; unused by
  /// kriging.
  int neighbors = 12;
  /// A point is inside the data when a sample lies within reach × median step (or the least
  /// radius, see reach_radius()); > 0.
  double reach = 3.0;
  /// The up axis, as for the features (heading and height are about / along it).
  Axis up = Axis::Y;
  /// A GP-LVM map's GP over the map's coordinates (embed::GplvmMap; sample i's latent point =
  /// row i): with it the map's validity is the GP's (MapGp::inside) in every mode, and the gp mode
  /// blends with its predictive mean. Null for other maps (the gp mode then is an error).
  std::shared_ptr<const MapGp> gplvm;
  /// Made from a ClipSource: the sample states read from the clips that the blender keeps (about
  /// 1 KB each for 30 joints), ≥ 1; beyond it, it keeps only those of the samples being read.
  int kept_states = 200000;

  /// @throws ParameterError naming `neighbors`, `reach` or `kept_states`, its value and the valid
  ///         range (neighbors is only checked in the local and idw modes), for the gp mode without
  ///         `gplvm`, or for a `gplvm` of another number of frames than `num_samples`.
  void validate(int num_samples) const;
};

/// How far a map point is from the data, and where it was actually evaluated.
struct PointValidity {
  Eigen::Vector2d query = Eigen::Vector2d::Zero();  ///< the point asked for
  Eigen::Vector2d point =
      Eigen::Vector2d::Zero();  ///< the point evaluated (== query unless clamped)
  bool clamped = false;         ///< query was outside the data and moved (see the top of the file)
  double distance = 0.0;        ///< from query to the nearest sample (map units)
  int nearest_sample = 0;       ///< the sample at that distance (the first of merged ones)
  /// Kriging variance at `point` (map units: the linear variogram's), 0 at samples, growing away
  /// from them: w·a + μ (kriging), the partition-weighted local variances (local); NaN (idw). On
  /// a GP-LVM map (BlendOptions::gplvm), in every mode: the GP's variance without the noise at
  /// `point` (embed::GplvmMap::variance, in the features' units squared).
  double variance = 0.0;
};

/// Weights of a map point over the samples: sparse, sample indices increasing, summing to 1.
/// Local and idw weights touch a few dozen samples, kriging weights every sample.
struct MapWeights {
  std::vector<int> samples;     ///< sample indices (rows of the map), strictly increasing
  std::vector<double> weights;  ///< one per entry of samples; may be negative (kriging, local)
  PointValidity validity;
  /// How fast the blend at these weights moves on against its samples' own pace: blend() scales
  /// the root's velocity and yaw rate by it. 1 but where locate_path() registers a gait's phase
  /// and the path leads it faster or slower than the clips' cadence (detail/gait_phase.h).
  double pace = 1.0;
  /// How fast the blend's legs move on through the gait where locate_path() could not register
  /// its phase: its sources' own lead phase, against their cadence; 1 elsewhere
  /// (detail::lead_pace). A low one, while the path moves on, is a stall (detail/outside_route.h).
  double lead_pace = 1.0;

  /// Sample `s` alone, weight 1: its own captured frame.
  static MapWeights of_sample(int s) {
    MapWeights w;
    w.samples = {s};
    w.weights = {1.0};
    return w;
  }
};

/// Where a one-frame pose's motion root stands on the floor: its heading (yaw about the up axis,
/// radians, as features::heading_angle of the root's local rotation) and its floor position (the
/// root's local translation; the component along the up axis is not used).
struct RootPlacement {
  double heading = 0.0;
  Eigen::Vector3d floor = Eigen::Vector3d::Zero();
};

/// The placement of the motion root `root` in frame `frame` of `motion` (a viewer keeps it while
/// the user drags over a map, so the body does not turn to heading 0 or jump to the origin), its
/// `ancestors` folded in (MapBlender::root_ancestors(); blend_state.h's root_transform).
/// @throws ParameterError if `frame`, `root` or an ancestor is out of range.
RootPlacement root_placement(const Motion& motion, int frame, int root, Axis up = Axis::Y,
                             std::span<const int> ancestors = {});

/// Turns the one-frame `pose`, whose joint `root` faces heading 0 at the floor origin (as
/// MapBlender::pose and mapfile::SavedMap::pose_at make it), to `placement.heading` about `up` and
/// moves it to `placement.floor`; its height and tilt stay.
/// @throws ParameterError if `root` is out of range, pose has no frame, or placement is not finite.
void place_root(Motion& pose, int root, const RootPlacement& placement, Axis up = Axis::Y);

/// The clips of a map read on demand (a saved map's, loaded from files): what a MapBlender made
/// without the clips asks for the frames it blends.
class ClipSource {
 public:
  virtual ~ClipSource() = default;
  /// Clip `c` of the map, the same data every time. Thread-safe. @throws what loading throws.
  virtual std::shared_ptr<const Clip> clip(int c) const = 0;
};

/// What a MapBlender needs to know of all its clips together: with it, one that reads frames on
/// demand blends as one given every clip. summarize_clips() computes it; a saved map records it.
struct ClipsSummary {
  std::vector<int> frames;          ///< per clip: its frame count
  std::vector<double> frame_times;  ///< per clip: seconds per frame
  /// The joint carrying the root motion (MapBlender::motion_root()): the deepest of the clips'
  /// motion_root()s, its ancestors folded into it (blend_state.h).
  int motion_root = 0;
  /// The joints other than motion_root and its ancestors whose translation differs between the
  /// map's samples (beyond 1e-12 relative to the first sample's), increasing: the ones a blend
  /// averages.
  std::vector<int> moving;
};

/// The summary of `clips` (sharing one hierarchy) for the map rows `samples` (clip_of, frame_of
/// checked by the caller). @throws ParameterError for no clips or clips of different hierarchies.
ClipsSummary summarize_clips(std::span<const Clip> clips, const features::FeatureSet& samples);
/// The same, reading clip c as `clip_at(c)` (c = 0 … num_clips − 1, once each, plus the first
/// sample's clip once more; on the pool's threads, thread-safe), so that only a clip per thread
/// need be in memory at a time. Reports through `control`. @throws as summarize_clips() and
/// clip_at (the first clip's error); Cancelled.
ClipsSummary summarize_clips(int num_clips,
                             const std::function<std::shared_ptr<const Clip>(int)>& clip_at,
                             const features::FeatureSet& samples, const Control& control = {});

namespace detail {
struct PathFitsData;
}

/// What MapBlender::locate_path() fitted at the frames of one path in the local mode, before it
/// registered their gait phases: each frame's validity and blend (the clip times it follows and
/// the kriging's samples), with the path's points, frame time and blender. Given to a later
/// locate_path() on the same blender and frame time, a frame whose points around it (the
/// follow_neighbours() that its fit reads) are the same takes its fit from it rather than fitting
/// again, bit for bit, and the frames fitted then are added. synthesize() keeps its path's in
/// SynthResult, so that edit_path() fits again only the frames around a moved point. Copies share
/// what they hold; a change makes its own copy.
class PathFits {
 public:
  /// The frames it holds a fit for.
  std::size_t size() const;

 private:
  friend class MapBlender;
  std::shared_ptr<const detail::PathFitsData> m;
};

class MapBlender {
 public:
  /// Prepares blending for a map of `samples` (the features the map was built from: their
  /// clip_of and frame_of say which clip and frame each map row is; X and D are not used).
  /// `coords` is #samples by ≥ 2 map coordinates; only the first two columns are used. `clips`
  /// are the clips of build_features, in the same order, sharing one joint hierarchy; the first
  /// one's skeleton and frame time are the blender's. Kriging factors its system here: about
  /// (2/3)·N³ flops and 8·N² bytes (docs/performance.md); the local mode's set-up is
  /// O(N·K·log N). Both report the stage "kriging set-up" through `control` and poll it for
  /// cancellation (kriging: between chunks of the factorisation; local: every few dozen systems).
  /// @throws ParameterError for bad options, a map that does not belong to the clips (row count
  ///         ≠ #samples, a clip or frame index out of range, clips of different hierarchies),
  ///         fewer than 2 columns, or kriging with more than kMaxKrigingSamples merged points;
  ///         NumericalError for non-finite coordinates or motion values or a singular system;
  ///         Cancelled if `control` says so.
  MapBlender(std::span<const Clip> clips, const features::FeatureSet& samples,
             const Eigen::MatrixXd& coords, const BlendOptions& options = {},
             const Control& control = {});
  /// A blender over the clips of `source`, read on demand: here only its first clip (for the
  /// skeleton and frame time) and the first sample's; a blend reads the clips of the samples it
  /// blends; the local mode builds each sample's kriging system the first time a query needs it
  /// (kept, and the same as the constructor above builds). `summary` is the clips' (as
  /// summarize_clips() gives it). Set-up is O(N log N) in the samples and holds no per-sample
  /// pose. Blends equal those of the constructor above for the same clips, bit for bit; a clip
  /// of another hierarchy, a non-finite value or a singular local system is then an error of the
  /// query that reads it rather than of construction.
  /// @throws ParameterError as above, for a summary that does not fit the samples or the first
  ///         clip, or for the kriging mode (it blends every sample: give the clips); as `source`.
  MapBlender(std::shared_ptr<const ClipSource> source, const ClipsSummary& summary,
             const features::FeatureSet& samples, const Eigen::MatrixXd& coords,
             const BlendOptions& options = {}, const Control& control = {});
  ~MapBlender();
  MapBlender(MapBlender&&) noexcept;
  MapBlender& operator=(MapBlender&&) noexcept;

  /// Weights and validity of map point p (clamped into the data's reach first when outside).
  /// @throws ParameterError if p is not finite.
  MapWeights locate(const Eigen::Vector2d& p) const;
  /// locate() for many points at once (kriging solves them together, much faster than one by
  /// one). @throws ParameterError naming the first non-finite point.
  std::vector<MapWeights> locate(std::span<const Eigen::Vector2d> points) const;
  /// The weights of frames [first, end) of a path sampled every `frame_time` seconds (`points`:
  /// every frame's map point): locate()'s, and in the local mode where the path around a frame
  /// follows a clip's trajectory, that clip's samples at the fitted time (top of the file); in the
  /// local mode, the times blended registered to one gait phase (detail/gait_phase.h).
  /// synthesize() and edit_path() locate their paths with it. The frames are located in
  /// parallel. With `fits` (local mode): the frames it holds for these points are not fitted
  /// again, and it is made to hold this path's fits of every frame located (see PathFits).
  /// @throws ParameterError if [first, end) is not within points, frame_time is not positive and
  ///         finite, or as locate().
  std::vector<MapWeights> locate_path(std::span<const Eigen::Vector2d> points, double frame_time,
                                      std::size_t first, std::size_t end,
                                      PathFits* fits = nullptr) const;
  /// The map point of every frame of `path` sampled every `frame_time` seconds, as synthesize()
  /// and edit_path() follow it: resample_path()'s, an untimed path drawn at `speed`; in the local
  /// mode, a stroke between two of its points on a clip's curve at about that clip's timing
  /// follows the curve (detail/strokes.h).
  /// @throws ParameterError as resample_path().
  std::vector<Eigen::Vector2d> path_points(const MapPath& path, double frame_time, double speed,
                                           long long max_frames) const;
  /// How many frames either side of a frame locate_path() reads the points of, for a path sampled
  /// every `frame_time` seconds (0 but in the local mode): a point moved changes the weights of
  /// that many frames around it. The clip times a frame follows read follow_neighbours() of them,
  /// the registration of its gait phase those frames' around it (detail/gait_phase.h).
  /// @throws ParameterError if frame_time is not positive and finite.
  int path_neighbours(double frame_time) const;
  /// How many frames either side of a frame the fit of the clip times it follows reads (0 but in
  /// the local mode; see the top of the file). @throws as path_neighbours().
  int follow_neighbours(double frame_time) const;
  /// Weights moved `seconds` later (earlier when negative) in their clips: each sample's weight
  /// goes to the sample of its clip that much later, or is shared linearly between the two
  /// samples around that time (the first or last sample of its run of consecutive samples beyond
  /// the run's ends). The sum is kept. What synthesize()'s smoothing does to a neighbouring
  /// frame's weights before averaging them, so that a path playing a clip stays on it.
  /// @throws ParameterError if a sample is out of range or seconds is not finite.
  MapWeights later_in_clip(const MapWeights& weights, double seconds) const;

  /// The blend of the samples with `weights` (as from locate(), or smoothed: any sparse weights
  /// over valid sample indices, summing to about 1), its root velocity and yaw rate times
  /// weights.pace.
  /// @throws ParameterError if sizes differ, a sample index is out of range, a weight is not
  ///         finite, the weights sum to about 0, or the pace is negative or not finite.
  BlendedFrame blend(const MapWeights& weights) const;

  /// Per foot (left, right): the share of `weights` on samples whose foot is on the floor in
  /// their own clip (detect_contacts, skeleton/contacts.h), in [0, 1] — how much the blend at
  /// these weights is a standing foot. Nothing for a skeleton without feet (find_feet); a
  /// blender reading its clips on demand knows the contacts of the samples it has blended (blend
  /// these weights first), and says nothing for others.
  std::optional<std::array<double, 2>> contact_share(const MapWeights& weights) const;

  /// The pose at map point p as a one-frame Motion of skeleton(): blended joint rotations and
  /// translations, the motion root at floor position 0 (blended height) with heading 0.
  /// Equals pose(locate(p)). @throws ParameterError if p is not finite.
  Motion pose_at(const Eigen::Vector2d& p) const;
  /// The one-frame pose blended with `weights` (from locate(), whose validity a caller may want
  /// too: then locate once and call this). @throws as blend().
  Motion pose(const MapWeights& weights) const;
  /// pose(weights) turned to `placement.heading` about the up axis and moved to its floor
  /// position; the blended height and tilt stay. pose(weights) is this with a zero placement.
  Motion pose(const MapWeights& weights, const RootPlacement& placement) const;

  const Skeleton& skeleton() const;
  const BlendOptions& options() const;
  int num_samples() const;
  /// Distinct map points (samples after merging those that share a point).
  int num_points() const;
  /// Frame time of the first clip (seconds).
  double frame_time() const;
  /// The joint whose translation and heading carry the root motion (ClipsSummary::motion_root):
  /// the first root, or below it while a joint has exactly one child and is constant over a clip
  /// (a static "joint_Root" above the hips), the deepest over the clips.
  int motion_root() const;
  /// The motion root's ancestors, from the top: folded into it by the blend, left at rest in
  /// its poses (blend_state.h).
  std::span<const int> root_ancestors() const;
  /// Median of the non-zero map distances between consecutive samples of a clip (0 if none).
  double median_step() const;
  /// reach_radius(reach, median_step(), the map's size): how far from every sample a point may be
  /// before it is clamped (on a GP-LVM map the GP's rule decides instead: inside()).
  double reach_distance() const;
  /// Whether map point p is inside the data, by the map's one rule: the GP's variance on a GP-LVM
  /// map (BlendOptions::gplvm), else a sample within reach_distance(). locate() clamps exactly
  /// the points where this is false. @throws ParameterError if p is not finite.
  bool inside(const Eigen::Vector2d& p) const;
  /// Where p is, as locate(p) finds it before it weighs the samples: the nearest sample and its
  /// distance, whether p is clamped and the point evaluated (variance: the GP's on a GP-LVM map,
  /// else 0; locate() computes the blend's with the weights). @throws ParameterError if p is
  /// not finite.
  PointValidity validity(const Eigen::Vector2d& p) const;
  /// Median of the non-zero map speeds between consecutive samples of a clip (map units per
  /// second: step / time between the two frames); 0 if none.
  double median_speed() const;
  /// Map point of sample i (first two columns of its coords row).
  Eigen::Vector2d sample_point(int i) const;
  /// The frame of its clip that sample i is, and the sample of the same clip's next frame on
  /// the map (the next row when it is the same clip's next frame), −1 where there is none.
  /// @throws ParameterError if i is not a sample.
  int sample_frame(int i) const;
  int next_sample(int i) const;
  /// Sample i's gait phase in its clip (cycles, not wrapped: whole at its left foot's strikes,
  /// ½ past them at its right foot's; detail/gait_phase.h) and, into *cadence if given, the
  /// cycles per second of the cycle it is in; NaN where the clip has no gait phase (a bow, a
  /// swing).
  /// @throws ParameterError if i is not a sample.
  double gait_phase(int i, double* cadence = nullptr) const;
  /// Made from a ClipSource: reads the states of every sample these weights blend, each clip
  /// once (the clips on the pool's threads), so that blending them reads no clip; a synthesis
  /// calls it for the weights of up to 2048 frames at a time, as blended (smoothed). Does nothing
  /// for a blender given the clips. @throws as blend().
  void prefetch(std::span<const MapWeights> weights) const;
  /// Whether this blender was made from a ClipSource (reads clips on demand).
  bool reads_on_demand() const;
  /// Local kriging systems built so far: all of them (eager), or those queries touched (made
  /// from a ClipSource); 0 in the other modes.
  int num_local_systems() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

}  // namespace motionmap::synth
