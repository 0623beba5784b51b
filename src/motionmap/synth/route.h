#pragma once
// Routes on a motion map: the cheapest way from one map point to another through the part of
// the map where poses can be trusted, as in-betweening (inbetween.h) follows it between keys.
// Below the grid route (find_route), the route through the clips' own frames (find_clip_route)
// and how it is played (play_clip_route, clip_route_weights): in-betweens follow it between
// keys, and a path outside the data along its frames there (detail/outside_route.h).
//
//   motionmap::synth::MapField field(blender);               // distances to the samples
//   motionmap::synth::RouteGrid grid = make_grid(field, {});  // cells and their costs
//   auto route = find_route(field, grid, a, b);                // a polyline from a to b
//
// Validity (the one rule for shading, clamping and routes): a map point is valid when a sample
// lies within MapBlender::reach_distance() of it — exactly where MapBlender::locate() does not
// clamp. With d(p) the distance from p to the nearest sample and r the reach distance, the cost
// of passing through p is
//     c(p) = 1 + kRoutePenalty·(d(p)/r)²  where d(p) ≤ r, impassable elsewhere,
// so a route prefers to stay near the data (on a sample the cost is 1, at the edge of the valid
// region 1 + kRoutePenalty).
//
// The grid: square cells over the samples' bounding box, grown by r on every side. By default
// the cell side is r/2, the number of cells along the longer side clamped to [kMinGridCells,
// kMaxGridCells]; RouteOptions::grid = N sets N cells along the longer side (Shin & Lee use 20
// and 40). A cell is passable when its centre is valid, or when it holds a sample (a cell larger
// than 2r may have an invalid centre and yet a trajectory through it); its node is its centre,
// or, when the centre is invalid, the point at 0.9·r from the centre's nearest sample towards the
// centre. Cell cost c(node). The route is Dijkstra's (A* with the straight-line distance, which
// never overestimates since every cost is ≥ 1) over the 8-connected cells, an edge costing its
// length × the mean of its two cells' costs; keys join the grid at the passable cell whose node
// is nearest (when the key's own cell is not passable, e.g. a placed frame outside the data, that
// straight stretch is outside and reported so by the blender's validity).
//
// Smoothing: string pulling (a vertex is dropped when the straight line that replaces it is valid
// and costs no more, integrated over c, than the stretch it replaces), then two rounds of
// Chaikin corner cutting whose new segments are each checked valid — a corner whose cut would
// leave the valid region is kept. Every segment of a route between two valid points is checked
// valid (everywhere: the distance to the samples is 1-Lipschitz) and, where it is not, split at
// its midpoint pulled to 0.9·r of its nearest sample (depth-limited).
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/synth/blender.h"

namespace motionmap::synth {

/// How much more a route pays per unit length at the edge of the valid region than on a sample
/// (c = 1 + kRoutePenalty·(d/r)²).
inline constexpr double kRoutePenalty = 4.0;
/// How much more a route pays per unit length across a gap in the data (outside the valid
/// region), times 1 + kRoutePenalty·(d/r)², than on a sample: only where the valid region does
/// not join two keys (RouteOptions::cross_gaps).
inline constexpr double kGapPenalty = 1000.0;
/// Default grid: cells along the longer side, at most and at least.
inline constexpr int kMinGridCells = 20;
inline constexpr int kMaxGridCells = 200;
/// Most cells along the longer side that RouteOptions::grid may ask for.
inline constexpr int kMaxGridOption = 2000;

/// How a route between two keys is found.
enum class RouteMode {
  /// Through the clips' own frames (find_clip_route): the motion between the keys is the
  /// samples' own, played on, held, sped up or jumping to a nearby sample of another clip.
  Clips,
  /// Shin & Lee's: the cheapest path over the grid through the valid region, smoothed
  /// (find_route), walked at the samples' own speed.
  Grid,
};

/// "clips" or "grid".
const char* route_mode_name(RouteMode mode);
/// @throws ParameterError naming `route` and the accepted names.
RouteMode parse_route_mode(const std::string& name);

struct RouteOptions {
  /// How the route is found (see RouteMode).
  RouteMode mode = RouteMode::Clips;
  /// Cells along the longer side of the grid; 0 = from the map's density (see the top).
  int grid = 0;
  /// String pulling and Chaikin smoothing of the grid route.
  bool smooth = true;
  /// Where the valid region does not join the two ends (a clip whose consecutive frames lie
  /// farther apart on the map than the reach: a golf swing's downswing), cross the gap where it
  /// costs least (cells outside at kGapPenalty × their cost) instead of failing; the frames
  /// there are outside the data (the blender clamps them, and says so).
  bool cross_gaps = true;

  /// @throws ParameterError naming `grid`, its value and the valid range ({0} ∪ [2, 2000]).
  void validate() const;
};

/// Distances from map points to the samples of a map, and the validity and cost they give.
/// Immutable; its const member functions are thread-safe.
class MapField {
 public:
  /// The samples of `blender`'s map (sample_point()) and its reach_distance(); on a GP-LVM map
  /// (BlendOptions::gplvm) the GP's rule of where the map is valid instead of the reach, as
  /// MapBlender::locate() has it: valid() is MapGp::inside() and the cost grows with the GP's
  /// variance, c(p) = 1 + kRoutePenalty·(v/τ)² (v = the variance, τ its threshold).
  explicit MapField(const MapBlender& blender);
  /// `points`: the samples' map points (≥ 1, finite); `reach_distance` > 0.
  /// @throws ParameterError otherwise.
  MapField(std::vector<Eigen::Vector2d> points, double reach_distance);
  ~MapField();
  MapField(MapField&&) noexcept;
  MapField& operator=(MapField&&) noexcept;

  double reach_distance() const { return m_reach; }
  /// The samples' bounding box.
  const Eigen::Vector2d& min() const { return m_min; }
  const Eigen::Vector2d& max() const { return m_max; }
  int num_samples() const;
  const Eigen::Vector2d& sample(int i) const;

  /// Distance from p to the nearest sample, and which it is.
  double distance(const Eigen::Vector2d& p, int* nearest = nullptr) const;
  /// The k nearest samples (nearest first; fewer when the map has fewer): indices out.
  int nearest(const Eigen::Vector2d& p, int k, std::vector<int>& indices) const;
  /// distance(p) ≤ reach_distance() (a GP-LVM map: the GP's rule): where MapBlender::locate()
  /// does not clamp.
  bool valid(const Eigen::Vector2d& p) const;
  /// c(p) = 1 + kRoutePenalty·(d/r)² (a GP-LVM map: 1 + kRoutePenalty·(v/τ)²), +∞ outside the
  /// valid region.
  double cost(const Eigen::Vector2d& p) const;
  /// Whether every point of the straight segment a–b is valid (shown with the distance's
  /// Lipschitz bound, halving the segment where needed; a segment that touches the edge of the
  /// valid region may be called invalid). On a GP-LVM map: checked at steps of ℓ/8.
  bool segment_valid(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;
  /// p when valid, else moved towards its nearest sample into the valid region: to
  /// kPullFraction of the reach from it, or on a GP-LVM map to kPullFraction of the way from it
  /// to the region's edge on that segment (the sample itself when that is outside too).
  Eigen::Vector2d pulled_in(const Eigen::Vector2d& p) const;
  /// ∫ c ds along the segment a–b (midpoint rule, steps of at most r/8); +∞ if it leaves the
  /// valid region.
  double segment_cost(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;

 private:
  bool interval_valid(const Eigen::Vector2d& p, double dp, const Eigen::Vector2d& q, double dq,
                      int depth) const;

  struct Tree;
  std::unique_ptr<Tree> m_tree;
  double m_reach = 0.0;
  std::shared_ptr<const MapGp> m_gp;  ///< a GP-LVM map's rule (MapField(const MapBlender&))
  Eigen::Vector2d m_min = Eigen::Vector2d::Zero(), m_max = Eigen::Vector2d::Zero();
};

/// The grid a route is found on (see the top of the file).
struct RouteGrid {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< corner of cell (0, 0)
  double cell = 0.0;                                 ///< side of a cell, map units
  int nx = 0, ny = 0;                                ///< cells along x and y
  /// Per cell (index y·nx + x): the cost c of its node, +∞ when impassable.
  std::vector<double> cost;
  /// Per cell: its cost, or for an impassable cell kGapPenalty·(1 + kRoutePenalty·(d/r)²) at its
  /// centre (RouteOptions::cross_gaps).
  std::vector<double> gap_cost;
  /// Per cell: the point a route passes through in it (its centre, or pulled into the data).
  std::vector<Eigen::Vector2d> node;

  int index(int x, int y) const { return y * nx + x; }
  /// The cell holding p (clamped to the grid).
  int cell_of(const Eigen::Vector2d& p) const;
  bool passable(int c) const;
};

/// The grid over `field`'s samples with `options.grid` cells along its longer side (0: from the
/// density). @throws ParameterError for bad options.
RouteGrid make_grid(const MapField& field, const RouteOptions& options = {});

/// The cheapest route from a to b (first point exactly a, last exactly b; smoothed when
/// options.smooth), through the valid region except for the straight stretches joining a key
/// outside it to the nearest passable cell.
/// Where the valid region does not join a and b, the route crosses the cheapest gap
/// (options.cross_gaps) or the call fails.
/// @throws ParameterError if a or b is not finite, or no route joins them (the valid region is
///         cut between them and cross_gaps is false: the message says so and suggests a larger
///         reach).
std::vector<Eigen::Vector2d> find_route(const MapField& field, const RouteGrid& grid,
                                        const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                        const RouteOptions& options = {});

/// Costs of a clip route's steps, in units of (map distance / reach)² (see find_clip_route).
struct ClipRouteCosts {
  double hold = 0.2;  ///< a sample repeated (time slowed)
  double skip = 0.2;  ///< a sample skipped (time sped up)
  double jump = 1.0;  ///< to another sample than the next, plus (its distance from the next / r)²
  double ends = 1.0;  ///< times (distance / r)² of the first sample from a and the last from b
};

/// Nearest samples a clip route may start or end on (ClipRouteEnds::candidates), and jump to
/// from a sample's successor.
inline constexpr int kClipRouteEnds = 16;
inline constexpr int kClipRouteJumps = 8;
/// Most samples a clip route keeps per step (the cheapest; the search is exact below it).
inline constexpr int kClipRouteBeam = 4096;
/// Most steps a clip route may take (inbetween() takes the grid route for longer segments).
inline constexpr int kMaxClipRouteSteps = 2000;

/// The samples a route through the clips' own frames visits from a to b in exactly `steps`
/// steps (steps + 1 samples): the path minimising
///     (|s₀ − a|/r)² + Σ step costs + (|s_T − b|/r)²,
/// a step from sample s going to next[s] (its clip's next sample) at no cost, or staying on s
/// (costs.hold), or to next[next[s]] (costs.skip), or to one of the kClipRouteJumps samples
/// nearest next[s]'s point (nearest s's at a clip's end) within r, at costs.jump + (d/r)². The
/// ends are among the kClipRouteEnds samples nearest a and b, and the further ones up to the
/// ends.candidates nearest that cost less than every one of those. Exact while no step has more
/// than kClipRouteBeam samples reached; beyond, the cheapest are kept, ranked with their distance
/// to b. `next[s]` = −1 at a clip's last sample.
/// @throws ParameterError if next's size is not the field's number of samples, an entry is out
///         of range, steps is outside [1, kMaxClipRouteSteps], ends.candidates is not positive,
///         or a or b is not finite.
/// `ends`: where the route may start (a sample, e.g. a previous route's last) and what starting
/// or ending on a sample costs beyond its distance (e.g. how far its pose is from a key's).
/// What a bridge whose jump is forbidden costs for its jump (ClipRouteEnds::bridge_jump_cost):
/// more than any route a search finds.
inline constexpr double kForbiddenBridge = 1e12;
struct ClipRouteEnds {
  int start = -1;  ///< ≥ 0: the route starts on this sample, not near a
  /// How many samples nearest a and b the route may start and end on; those beyond the
  /// kClipRouteEnds nearest only where cheaper than all of them. More let start_cost and
  /// end_cost find a pose that the points alone miss (a 2-D map lays a walk's phases close).
  int candidates = kClipRouteEnds;
  std::function<double(int)> start_cost;  ///< extra cost of starting on a sample; null: none
  std::function<double(int)> end_cost;    ///< extra cost of ending on a sample; null: none
  /// Extra cost of being on a sample at a step (0 … steps), e.g. how far it is from a path's
  /// point then; null: none.
  std::function<double(int, int)> step_cost;
  /// Extra cost of a jump from one sample (the next one's place) to another, e.g. how far apart
  /// their poses are; null: none.
  std::function<double(int, int)> jump_cost;
  /// Non-null: the route may bridge — the cheapest start's clip played on for half the steps
  /// (held at its last sample), then the cheapest end's clip played up to it (held at its
  /// first), one jump between (crossfaded when played, clip_route_weights) — at the start's and
  /// end's costs, the step costs, one jump's (costs.jump + bridge_jump_cost from the next
  /// sample's place, not its map distance; a hold, step or skip where the halves meet in one
  /// clip) and costs.hold per held step. The route is the bridge where that is cheaper than the
  /// search's best (whose jumps are priced by bridge_jump_cost for that comparison), and where
  /// no sample b's end may be is reached (clips the map's jumps do not join: a run's key and a
  /// walk's) rather than ending wherever lies nearest b — where bridge_jump_cost forbids its
  /// jump (infinite) too, at kForbiddenBridge instead. Ended nearest b, a run's key held its pose
  /// while the root glided on to a walk's key 1.5 m away; a dash's key to a bow's, the cheapest
  /// chain of jumps played a walk backwards.
  std::function<double(int, int)> bridge_jump_cost;
};
struct ClipRoute {
  std::vector<int> samples;  ///< steps + 1 samples
  double cost = 0.0;         ///< the path's cost (see above)
};
ClipRoute find_clip_route(const MapField& field, std::span<const int> next,
                          const Eigen::Vector2d& a, const Eigen::Vector2d& b, int steps,
                          const ClipRouteEnds& ends = {}, const ClipRouteCosts& costs = {});

/// Per sample: the next sample of its clip on the map (MapBlender::next_sample), −1 at a
/// clip's last: find_clip_route's `next`.
std::vector<int> next_samples(const MapBlender& blender);
/// The median frames between a sample and the next of its clip (1 when no clip has two).
double median_sample_step(const MapBlender& blender, std::span<const int> next);

/// A clip route's samples as played, one step a unit of time. The search holds a sample or skips
/// one wherever it costs least: played step by step, a stretch would stop and rush (a skip plays
/// a step at twice the clip's pace). So each run of steps between two jumps plays its clip at
/// one even pace, from the run's first sample to its last, which it still reaches at its step.
struct ClipRoutePlay {
  std::vector<int> samples;     ///< the route's samples (steps + 1)
  std::vector<double> advance;  ///< per step: the clips' frames it advances (even over its run)
  std::vector<char> jumps;      ///< per step: whether it jumps to another clip's sample
  std::vector<int> run_start;   ///< per step: the first step of its run
};
/// `visited`: find_clip_route's samples; `next` as there; a jump advances `sample_step` frames.
ClipRoutePlay play_clip_route(const MapBlender& blender, std::span<const int> next,
                              std::vector<int> visited, double sample_step);
/// How long a clip route takes to cross from one clip to another at a jump: the clip jumped
/// from played on and the clip jumped to played up to it, mixed over this time about the jump.
/// Cut at the jump, an in-between from a bow's key to a walk's popped a joint 32 cm in a frame;
/// over 0.2 s, a walk's to a punch's stance moved one 21 cm (the clips' fastest: 12).
inline constexpr double kJumpFadeSeconds = 0.6;
/// The weights of the frame at time t ∈ [0, steps] (in steps) of a played route: in a run, the
/// two samples of the run around its clip frame at the run's pace (weights 1 − f and f: the
/// clip's own frames in between); within fade_seconds about a jump (less where another jump or
/// an end is nearer) the clip jumped from played on and the clip jumped to played up to it, mixed
/// by a smoothstep (a blend at a map point between them would mix nearby samples of other clips);
/// fade_seconds 0: the nearer of the jump's two samples. Validity: their point, weighted alike, and
/// the most weighted sample. Pace (MapWeights::pace), the route played at `steps_per_second`: the
/// clips' frames its step advances (0 where it holds a frame, 2 where it skips every other) times
/// their frame time, per second played — a held pose stands still, a skipping one strides on; 1 for
/// a route of one sample.
MapWeights clip_route_weights(const MapBlender& blender, std::span<const int> next,
                              const ClipRoutePlay& play, double t, double steps_per_second,
                              double fade_seconds = kJumpFadeSeconds);

/// Poses as clip routes compare them: one frame's joint rotations, normalised, the motion
/// root's heading removed; two poses are (mean over the joints of the squared angle between
/// their rotations) / kRoutePoseAngle² apart.
inline constexpr double kRoutePoseAngle = 0.1;
using PoseRotations = std::vector<Eigen::Quaterniond>;
PoseRotations pose_rotations(const MapBlender& blender, const Motion& pose);
double pose_distance(const PoseRotations& a, const PoseRotations& b);

/// Most samples of a map read on demand (a saved map's) whose clip routes' jumps are priced by
/// their poses (prices_jumps_by_poses): in-betweens' routes (InbetweenOptions::priced_jump_samples)
/// and a path's routes outside the data (detail/outside_route.h).
inline constexpr int kPricedJumpSamples = 20000;

/// Whether clip routes on `blender` price their jumps by the two samples' poses: always where it
/// holds its clips; on one reading them on demand (a saved map's) where it has at most
/// `priced_samples` samples, whose every pose the caller reads first (SamplePoses::prepare), each
/// clip once, so that it routes as its clips mapped directly do. Beyond, pricing them would read a
/// clip for nearly every sample the search reaches: they are priced by their map distance alone
/// (docs/synthesis.md, "The clip route").
bool prices_jumps_by_poses(const MapBlender& blender, int priced_samples = kPricedJumpSamples);

/// Samples' own poses (their clips' frames) as routes compare them, each read once when first
/// asked for: only its own clip, where the blend at its point, equal to it on maps whose blend
/// is exact at samples, reads its neighbours' too (an in-between on a saved map of 100 000
/// frames, whose 8 clips kept could not hold them, read 545 clips for a few jumps' poses, 5.9 s).
/// Not thread-safe.
class SamplePoses {
 public:
  explicit SamplePoses(const MapBlender& blender) : m_blender(blender) {}
  const PoseRotations& operator()(int sample);
  /// Reads these samples' poses together (a blender reading its clips on demand reads each clip
  /// they need once). Polls `control`.
  void prepare(std::vector<int> samples, const Control& control = {});

 private:
  const MapBlender& m_blender;
  std::unordered_map<int, PoseRotations> m_poses;
};

/// Length of a polyline.
double polyline_length(std::span<const Eigen::Vector2d> points);

}  // namespace motionmap::synth
