#include "motionmap/synth/inbetween.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/rotation.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/synth/clean_feet.h"
#include "motionmap/synth/detail/root_motion.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::synth {

namespace {

// Samples whose map speeds are averaged for the speed at a point of a route.
constexpr int kSpeedNeighbors = 8;
// The slowest speed a route is walked at, as a fraction of the median map speed (a route over
// samples of a standing pose would otherwise take forever).
constexpr double kMinSpeedFraction = 0.1;
// A route is walked in pieces of at most reach / kWalkSteps for its time.
constexpr double kWalkSteps = 4.0;
// The samples nearest a key with a pose that a clip route may start or end on (ClipRouteEnds::
// candidates): enough to reach past the map's overlaps, where a 2-D map lays a walk's phases and
// styles close and places a key among them by its features.
constexpr int kKeyCandidates = 256;
// The rates a clip route is tried at (its steps = the segment's samples × rate), on segments of at
// least kMinRatedSteps samples.
constexpr double kClipRouteRates[] = {0.7, 0.8, 0.9, 1.0, 1.1, 1.25, 1.4};
constexpr double kMinRatedSteps = 12.0;
// Untimed, a segment between two keys with poses lasts at least the keys' floor distance over the
// mean root speed over ±kPaceSeconds of the clip of each key's nearest sample — unless that is
// slower than kStandingSpeed body sizes (detect_length_units' size) per second: the clips stand
// there, and the route's map time alone sets it.
constexpr double kStandingSpeed = 0.05;
constexpr double kPaceSeconds = 0.5;
// See jump_cost in inbetween().
constexpr double kLoopSeconds = 1.0;
// A segment whose root must cover its keys' distance faster than this many times the clips' own
// speed about its keys (at least kStandingSpeed) gets a note (see inbetween(), after the routes).
constexpr double kGlideNoteFactor = 1.5;
// A timed segment between keys of gaits whose legs must step more than this many times as fast
// as the clips' cadence (or less than its inverse) to meet the later key's phase in its time gets
// a note (see inbetween(), after the routes).
constexpr double kStepNoteFactor = 1.5;
// Between two keys with poses, a root gliding (the keys' placement less where the clips played
// carry it, over the time) faster than this share of the clips' own speed there, and than
// kGlideNoteFactor × kStandingSpeed, gets a note (see inbetween(), after the root's placement).
constexpr double kGlideNoteShare = 0.5;
// A segment's root path is turned and scaled onto the later key when it travels between this
// fraction and its inverse of the keys' distance, turned by at most kMaxTravelTurn radians.
constexpr double kMinTravelRatio = 0.5;
constexpr double kMaxTravelTurn = 1.0;

// A length of the clips' units for a note: in metres where the units are known ("1.52 m").
std::string length_text(const LengthUnits& units, double v) {
  return units.plausible ? format_number(v * units.metres_per_unit, 3) + " m"
                         : format_number(v, 3) + " units";
}

// Whether sample i + 1 is the next frame sampled of sample i's clip.
bool consecutive(const features::FeatureSet& samples, int i) {
  const auto n = static_cast<int>(samples.clip_of.size());
  return i >= 0 && i + 1 < n && samples.clip_of[i] == samples.clip_of[i + 1] &&
         samples.frame_of[i + 1] > samples.frame_of[i];
}

// Per sample: its map speed towards the next sample of its clip (the previous one's for the last
// frame of a clip; 0 for a clip of one sample), map units per second.
std::vector<double> sample_speeds(const MapBlender& blender, const features::FeatureSet& samples) {
  const int n = blender.num_samples();
  const double dt = blender.frame_time();
  std::vector<double> speed(static_cast<std::size_t>(n), -1.0);
  for (int i = 0; i < n; ++i) {
    if (consecutive(samples, i)) {
      speed[i] = (blender.sample_point(i + 1) - blender.sample_point(i)).norm() /
                 ((samples.frame_of[i + 1] - samples.frame_of[i]) * dt);
    } else if (consecutive(samples, i - 1)) {
      speed[i] = speed[i - 1];
    } else {
      speed[i] = 0.0;
    }
  }
  return speed;
}

// A route walked at the samples' own speed: points at most reach / kWalkSteps apart and the
// time at each (seconds from the route's start).
struct WalkedRoute {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> times;
  /// A clip route's samples as played (one per point); empty for a grid route, whose blended
  /// root velocities are the samples' own speed already.
  ClipRoutePlay play;
};

WalkedRoute walk(const MapField& field, const std::vector<double>& speeds, double floor_speed,
                 const std::vector<Eigen::Vector2d>& route) {
  WalkedRoute w;
  w.points.push_back(route.front());
  w.times.push_back(0.0);
  std::vector<int> near;
  const double piece = field.reach_distance() / kWalkSteps;
  for (std::size_t i = 1; i < route.size(); ++i) {
    const Eigen::Vector2d a = route[i - 1], b = route[i];
    const double length = (b - a).norm();
    if (length == 0.0) continue;
    const int steps = static_cast<int>(std::clamp(std::ceil(length / piece), 1.0, 1e5));
    for (int s = 1; s <= steps; ++s) {
      const double t0 = static_cast<double>(s - 1) / steps, t1 = static_cast<double>(s) / steps;
      const Eigen::Vector2d mid = (1.0 - 0.5 * (t0 + t1)) * a + 0.5 * (t0 + t1) * b;
      const int found = field.nearest(mid, kSpeedNeighbors, near);
      double v = 0.0;
      for (int k = 0; k < found; ++k) v += speeds[static_cast<std::size_t>(near[k])];
      v = std::max(found > 0 ? v / found : 0.0, floor_speed);
      w.points.push_back(s == steps ? b : (1.0 - t1) * a + t1 * b);
      w.times.push_back(w.times.back() + length / steps / v);
    }
  }
  return w;
}

// The point of a walked route at time t (clamped to its ends; exact at its points).
Eigen::Vector2d at_time(const WalkedRoute& w, double t) {
  if (w.points.size() == 1 || t <= 0.0) return w.points.front();
  if (t >= w.times.back()) return w.points.back();
  const auto it = std::upper_bound(w.times.begin(), w.times.end(), t);
  const auto i = static_cast<std::size_t>(it - w.times.begin());  // times[i - 1] ≤ t < times[i]
  const double a = (t - w.times[i - 1]) / (w.times[i] - w.times[i - 1]);
  return (1.0 - a) * w.points[i - 1] + a * w.points[i];
}

Eigen::Quaterniond slerp_or_end(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b,
                                double s) {
  if (s <= 0.0) return a;
  if (s >= 1.0) return b;
  return a.slerp(s, b).normalized();
}

}  // namespace

void InbetweenOptions::validate() const {
  if (frames_between < -1 || frames_between > kMaxFramesBetween) {
    throw ParameterError("frames_between: " + std::to_string(frames_between) +
                         " is out of range (must be in [0, " + std::to_string(kMaxFramesBetween) +
                         "], or −1 = not given)");
  }
  if (priced_jump_samples < 0) {
    throw ParameterError("priced_jump_samples: " + std::to_string(priced_jump_samples) +
                         " is negative (must be ≥ 0: 0 prices every jump by its map distance)");
  }
  route.validate();
}

int find_sample(const features::FeatureSet& samples, int clip, int frame) {
  const int n = samples.num_samples();
  for (int i = 0; i < n; ++i) {
    if (samples.clip_of[i] == clip && samples.frame_of[i] == frame) return i;
  }
  return -1;
}

Key sample_key(const MapBlender& blender, int sample, const Motion& motion, int frame) {
  if (sample < 0 || sample >= blender.num_samples()) {
    throw ParameterError("key: sample " + std::to_string(sample) +
                         " is out of range (the map has " + std::to_string(blender.num_samples()) +
                         ")");
  }
  if (frame < 0 || frame >= motion.num_frames) {
    throw ParameterError("key: frame " + std::to_string(frame) +
                         " is out of range (the motion has " + std::to_string(motion.num_frames) +
                         " frames)");
  }
  const int J = blender.skeleton().num_joints();
  if (motion.num_joints != J) {
    throw ParameterError("key: the motion has " + std::to_string(motion.num_joints) +
                         " joints, the map's skeleton " + std::to_string(J));
  }
  Key key;
  key.point = blender.sample_point(sample);
  key.pose.frame_time = motion.frame_time;
  key.pose.resize(1, J);
  for (int j = 0; j < J; ++j) {
    key.pose.rotation(0, j) = motion.rotation(frame, j);
    key.pose.translation(0, j) = motion.translation(frame, j);
  }
  return key;
}

InbetweenResult inbetween(const MapBlender& blender, const features::FeatureSet& samples,
                          std::span<const Key> keys, const InbetweenOptions& options,
                          const Control& control) {
  options.validate();
  const int K = static_cast<int>(keys.size());
  if (K < 2) {
    throw ParameterError("keys: " + std::to_string(K) + " given; in-betweening needs at least 2");
  }
  if (static_cast<int>(samples.clip_of.size()) != blender.num_samples() ||
      samples.frame_of.size() != samples.clip_of.size()) {
    throw ParameterError("inbetween: the samples are not the blender's (" +
                         std::to_string(samples.clip_of.size()) + " rows, the map has " +
                         std::to_string(blender.num_samples()) + ")");
  }
  const int J = blender.skeleton().num_joints();
  const auto name = [&](int i) {
    return "key " + std::to_string(i + 1) +
           (keys[i].label.empty() ? "" : " (" + keys[i].label + ")");
  };
  int timed = 0;
  for (int i = 0; i < K; ++i) {
    const Key& key = keys[i];
    if (!key.point.allFinite()) throw ParameterError(name(i) + ": its map point is not finite");
    if (key.has_pose() && (key.pose.num_frames != 1 || key.pose.num_joints != J)) {
      throw ParameterError(name(i) + ": its pose has " + std::to_string(key.pose.num_frames) +
                           " frames of " + std::to_string(key.pose.num_joints) +
                           " joints; a key pose is one frame of the map's " + std::to_string(J) +
                           " joints");
    }
    if (key.time) {
      ++timed;
      if (!std::isfinite(*key.time))
        throw ParameterError(name(i) + ": its time is not a finite number");
    }
  }
  if (timed != 0 && timed != K) {
    throw ParameterError("keys: " + std::to_string(timed) + " of " + std::to_string(K) +
                         " keys have a time; give a time to every key or to none");
  }
  if (timed != 0 && options.frames_between >= 0) {
    throw ParameterError(
        "frames_between: the keys have times; give either times or frames between keys");
  }
  const double dt = blender.frame_time();
  // The key poses as the blend makes poses: the motion root's ancestors folded into it.
  std::vector<Motion> key_poses(static_cast<std::size_t>(K));
  for (int i = 0; i < K; ++i) {
    if (!keys[i].has_pose()) continue;
    key_poses[i] = keys[i].pose;
    fold_root(key_poses[i], 0, blender.motion_root(), blender.root_ancestors());
  }

  // Frames of the keys.
  std::vector<long long> key_frames(static_cast<std::size_t>(K), 0);
  if (timed) {
    for (int i = 1; i < K; ++i) {
      key_frames[i] = std::llround((*keys[i].time - *keys[0].time) / dt);
      if (!(*keys[i].time > *keys[i - 1].time) || key_frames[i] <= key_frames[i - 1]) {
        throw ParameterError(name(i) + ": its time " + format_number(*keys[i].time) +
                             " s is not at least a frame (" + format_number(dt, 6) +
                             " s) after the previous key's " + format_number(*keys[i - 1].time) +
                             " s");
      }
    }
  } else if (options.frames_between >= 0) {
    for (int i = 1; i < K; ++i) key_frames[i] = key_frames[i - 1] + options.frames_between + 1;
  }
  if (key_frames.back() + 1 > kMaxSynthFrames) {
    throw ParameterError("keys: " + std::to_string(key_frames.back() + 1) +
                         " frames, more than the limit of " + std::to_string(kMaxSynthFrames));
  }

  // Routes, and each walked at the samples' own speed.
  const Control routing = control.stage("routes", 0.0, 0.2);
  InbetweenResult result;
  const MapField field(blender);
  result.grid = make_grid(field, options.route);
  const std::vector<double> speeds = sample_speeds(blender, samples);
  const double floor_speed = kMinSpeedFraction * blender.median_speed();
  const bool clip_routes = options.route.mode == RouteMode::Clips;
  const std::vector<int> next = clip_routes ? next_samples(blender) : std::vector<int>{};
  const double sample_step = clip_routes ? median_sample_step(blender, next) : 1.0;
  // How far apart two poses are (pose_distance): a sample's own pose, read once.
  SamplePoses sample_pose(blender);
  std::vector<PoseRotations> key_rotations(static_cast<std::size_t>(K));
  for (int i = 0; i < K; ++i) {
    if (keys[i].has_pose()) key_rotations[i] = pose_rotations(blender, key_poses[i]);
  }
  // A route's jumps are priced by their poses; on a blender reading its clips on demand (a saved
  // map's) only where it has at most options.priced_jump_samples, every one of whose poses is read
  // first, each clip once. Beyond, pricing them would read a clip for almost every sample the
  // search reaches (an in-between on a saved map of 100 000 frames did not end in 5 minutes): its
  // jumps are priced by the map distance alone there; a bridge's one jump by its poses everywhere.
  // Unpriced on the saved map of the 12 Bandai takes, the route from the tired walk's frame 178 to
  // the feminine walk's 223 jumped between their steps at two phases, and the swinging foot
  // dragged forward 0–6 cm above the floor.
  const bool price_jumps = prices_jumps_by_poses(blender, options.priced_jump_samples);
  if (clip_routes) {
    // The poses of the samples a route may start or end on, read together; on a blender reading
    // its clips on demand whose jumps are priced, every sample's (those among them).
    std::vector<int> read;
    if (price_jumps && blender.reads_on_demand()) {
      read.resize(samples.clip_of.size());
      std::iota(read.begin(), read.end(), 0);
    } else {
      std::vector<int> near;
      for (int i = 0; i < K; ++i) {
        if (!keys[i].has_pose()) continue;
        const int k = field.nearest(keys[i].point, kKeyCandidates, near);
        read.insert(read.end(), near.begin(), near.begin() + k);
      }
    }
    sample_pose.prepare(std::move(read), routing);
  }
  const auto pose_cost = [&](int key) {
    return [&, key](int s) { return pose_distance(key_rotations[key], sample_pose(s)); };
  };
  // A jump back into its own clip by less than kLoopSeconds plays the clip backwards: a chain of
  // them moonwalked a walk towards a bow's key. Not a jump a route may take (a jump back a whole
  // gait cycle or more loops the clip).
  const auto backwards = [&](int from, int to) {
    const int back = samples.frame_of[from] - samples.frame_of[to];
    return samples.clip_of[from] == samples.clip_of[to] && back >= 0 &&
           back * blender.frame_time() < kLoopSeconds;
  };
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const auto jump_cost = [&](int from, int to) {
    if (backwards(from, to)) return kNever;
    return price_jumps ? pose_distance(sample_pose(from), sample_pose(to)) : 0.0;
  };
  const auto bridge_jump_cost = [&](int from, int to) {
    return backwards(from, to) ? kNever : pose_distance(sample_pose(from), sample_pose(to));
  };
  // Per segment between two keys with poses, what its root must walk: the floor distance
  // between the keys' roots; the clips' pace about them, the mean root speed over ±kPaceSeconds
  // of the clip of each key's nearest sample (one gait cycle of a walk; the speeds of the samples
  // nearest a point mix clips — a walk's key lies beside runs on a map), 0 where neither has a
  // sample. Read by the untimed segments' time and by the glide notes, as are each key's units
  // (detect_length_units of its pose) and a standing body's drift in them (kStandingSpeed body
  // sizes per second).
  struct Walk {
    bool known = false;  // both keys have poses
    double apart = 0.0, pace = 0.0;
  };
  std::vector<Walk> walks(static_cast<std::size_t>(K - 1));
  std::vector<LengthUnits> key_units(static_cast<std::size_t>(K));
  for (int i = 0; i < K; ++i)
    if (keys[i].has_pose()) key_units[i] = detect_length_units(blender.skeleton(), key_poses[i]);
  const auto standing = [&](int i) { return kStandingSpeed * key_units[i].size; };
  // Each key's nearest sample (−1: none).
  std::vector<int> nearest(static_cast<std::size_t>(K), -1);
  {
    std::vector<int> near;
    for (int k = 0; k < K; ++k)
      if (field.nearest(keys[k].point, 1, near) >= 1) nearest[k] = near.front();
  }
  const auto clip_near = [&](int k) { return nearest[k] < 0 ? -1 : samples.clip_of[nearest[k]]; };
  {
    const int root = blender.motion_root();
    const Axis up = blender.options().up;
    const Eigen::Vector3d up_unit = Eigen::Vector3d::Unit(static_cast<int>(up));
    const int span = static_cast<int>(std::ceil(kPaceSeconds / dt));
    for (int i = 0; i + 1 < K; ++i) {
      if (!keys[i].has_pose() || !keys[i + 1].has_pose()) continue;
      // With free roots, keys of two takes (of their nearest samples' clips) are not placed
      // apart: their distance, of two capture places, asks for no time.
      if (options.free_roots && clip_near(i) != clip_near(i + 1)) continue;
      Walk& w = walks[static_cast<std::size_t>(i)];
      w.known = true;
      const Eigen::Vector3d apart = root_placement(key_poses[i + 1], 0, root, up).floor -
                                    root_placement(key_poses[i], 0, root, up).floor;
      w.apart = (apart - apart.dot(up_unit) * up_unit).norm();
      double speed = 0.0;
      int count = 0;
      for (const int k : {i, i + 1}) {
        if (nearest[k] < 0) continue;
        const int s = nearest[k], frame = samples.frame_of[s];
        int from = s, to = s;
        while (consecutive(samples, from - 1) && frame - samples.frame_of[from - 1] <= span) --from;
        while (consecutive(samples, to) && samples.frame_of[to + 1] - frame <= span) ++to;
        for (int j = from; j <= to; ++j) {
          speed += blender.blend(MapWeights::of_sample(j)).velocity.norm();
          ++count;
        }
      }
      w.pace = count == 0 ? 0.0 : speed / count;
    }
  }
  // Untimed, how long segment i takes at least for its root to cover the floor distance between
  // its keys at the clips' pace there; 0: no floor (the clips stand). A route between two keys
  // of a walk at one phase, steps apart, is short on the map.
  const auto walking_time = [&](int i) {
    const Walk& w = walks[static_cast<std::size_t>(i)];
    return w.known && w.pace > standing(i) ? w.apart / w.pace : 0.0;
  };
  // Untimed keys of two gaits (their nearest samples' clips' phases, detail/gait_phase.h): of
  // the times at which the later key's phase comes round, (Δφ + k) / cadence for whole k ≥ 0
  // (Δφ the phases' difference in [0, 1), the cadence the two samples' mean), the one nearest
  // `duration` not under `least`; `duration` where either has no phase. Two walks' keys at one
  // phase, 0.7 s apart by their route and the jump's crossfade, were joined by half a step and
  // the standing foot slid (the tired walk's frame 178 to the feminine walk's 223, free roots,
  // 20 frames between: 0.62 of the transitions and 74 cm/s in contact, against the walks' 0.41
  // and 58; untimed now 1.3 s, 0.40 and 66).
  // Where the later key's phase comes round after the earlier key's: `ahead` seconds, then every
  // `cycle` (Δφ / cadence and 1 / cadence).
  struct GaitGap {
    double ahead = 0.0, cycle = 0.0;
    // The last time it comes round by `duration` not under `least` (the first such, if later).
    double last_by(double duration, double least) const {
      const double first = ahead + std::max(0.0, std::ceil((least - ahead) / cycle)) * cycle;
      return first + std::floor(std::max(0.0, duration - first) / cycle) * cycle;
    }
    // The time it comes round not under `least` nearest `duration`.
    double nearest(double duration, double least) const {
      const double later = last_by(duration, least);
      return duration - later <= later + cycle - duration ? later : later + cycle;
    }
  };
  const auto gait_gap = [&](int i) -> std::optional<GaitGap> {
    if (nearest[i] < 0 || nearest[i + 1] < 0) return std::nullopt;
    double ca = 0.0, cb = 0.0;
    const double pa = blender.gait_phase(nearest[i], &ca);
    const double pb = blender.gait_phase(nearest[i + 1], &cb);
    if (!std::isfinite(pa) || !std::isfinite(pb) || !(ca > 0.0) || !(cb > 0.0)) return std::nullopt;
    const double cycle = 2.0 / (ca + cb);
    return GaitGap{(pb - pa - std::floor(pb - pa)) * cycle, cycle};
  };
  const auto in_step = [&](int i, double duration, double least) {
    const std::optional<GaitGap> gap = gait_gap(i);
    return gap ? gap->nearest(duration, least) : duration;
  };
  // A segment's frames (from key to key) for a time, as untimed keys take it, and that as a note
  // offers it: "1.33 s (39 frames between the keys)".
  const auto segment_frames = [&](double seconds) {
    return std::max(1.0, std::round(seconds / dt));
  };
  const auto segment_text = [&](double seconds) {
    const double frames = segment_frames(seconds);
    return format_number(frames * dt, 3) + " s (" + format_number(frames - 1.0) +
           " frames between the keys)";
  };
  std::vector<WalkedRoute> walked;
  int last_visited = -1;  // the sample the previous clip route ended on
  for (int i = 0; i + 1 < K; ++i) {
    routing.check();
    const bool untimed = !timed && options.frames_between < 0;
    // Steps of a clip route: one sample each, over the segment's frames (known now when timed).
    const auto clip_steps = [&](long long span) {
      return std::max(1.0, std::round(static_cast<double>(span) / sample_step));
    };
    const bool clip_route =
        clip_routes && (untimed || clip_steps(key_frames[i + 1] - key_frames[i]) <=
                                       static_cast<double>(kMaxClipRouteSteps));
    if (!clip_route || untimed) {
      result.routes.push_back(
          find_route(field, result.grid, keys[i].point, keys[i + 1].point, options.route));
      walked.push_back(walk(field, speeds, floor_speed, result.routes.back()));
    }
    if (untimed) {
      double duration = std::max(walked.back().times.back(), walking_time(i));
      // Keys of one clip, the later one later in it: the clip's own time between them, where the
      // map's route walks it in a time the clip route's rates reach (the clip then plays between
      // them as captured: the omimo walk's frames 100 and 600, walked on the map in 3.9 s of the
      // clip's 4.2, were played 7 % fast, skating 0.31 of the transitions against its 0.25).
      if (clip_route && keys[i].has_pose() && keys[i + 1].has_pose() && clip_near(i) >= 0 &&
          clip_near(i) == clip_near(i + 1)) {
        const double own = (samples.frame_of[nearest[i + 1]] - samples.frame_of[nearest[i]]) * dt;
        if (own >= std::ranges::min(kClipRouteRates) * duration &&
            own <= std::ranges::max(kClipRouteRates) * duration)
          duration = std::max(own, walking_time(i));
      }
      // Keys whose nearest samples are of two clips: a clip route between them jumps, and its
      // crossfade takes kJumpFadeSeconds (with free roots the keys' distance asks for no time,
      // and the map may lay the two poses close: a tired walk's key beside a run's was walked in
      // 0.17 s, its feet sliding 2.9 m/s).
      if (clip_route && clip_near(i) >= 0 && clip_near(i + 1) >= 0 &&
          clip_near(i) != clip_near(i + 1)) {
        duration = std::max(duration, kJumpFadeSeconds);
        duration = in_step(i, duration, std::max(kJumpFadeSeconds, walking_time(i)));
      }
      if (!std::isfinite(duration)) {
        throw ParameterError(
            "keys: the map has no motion to take the samples' speed from; give "
            "frames_between or times");
      }
      const double frames = segment_frames(duration);
      if (!(key_frames[i] + frames + 1 <= static_cast<double>(kMaxSynthFrames))) {
        throw ParameterError("keys: the routes take more than the limit of " +
                             std::to_string(kMaxSynthFrames) +
                             " frames at the samples' own speed; give frames_between or times");
      }
      key_frames[i + 1] = key_frames[i] + static_cast<long long>(frames);
    }
    const double want = clip_steps(key_frames[i + 1] - key_frames[i]);
    if (!clip_route || want > static_cast<double>(kMaxClipRouteSteps)) {
      last_visited = -1;
    } else {
      // The clips' own frames, one sample per step, the steps spread evenly over the segment.
      ClipRouteEnds ends;
      ends.start = last_visited;
      ends.candidates = kKeyCandidates;
      ends.jump_cost = jump_cost;
      ends.bridge_jump_cost = bridge_jump_cost;
      if (keys[i].has_pose()) ends.start_cost = pose_cost(i);
      if (keys[i + 1].has_pose()) ends.end_cost = pose_cost(i + 1);
      // The cheapest of the route played at a few uniform rates (a walk of another cadence
      // lands in step), when the segment is long enough for a rate to change its length. A rate
      // adds (drops) samples to the segment's steps, as skips (holds) spread evenly would, and
      // pays for them as the search does for those: unpriced, rate 1.4 was the cheapest for the
      // proud walk's key to the angry walk's, 18 frames, whose route then skipped on too, the
      // walk played 3 times as fast, a joint stepping 35 cm between frames.
      const ClipRouteCosts costs;
      ClipRoute best;
      best.cost = std::numeric_limits<double>::infinity();
      for (const double rate : kClipRouteRates) {
        if (want < kMinRatedSteps && rate != 1.0) continue;
        const int rated = static_cast<int>(
            std::clamp(std::round(want * rate), 1.0, static_cast<double>(kMaxClipRouteSteps)));
        ClipRoute route =
            find_clip_route(field, next, keys[i].point, keys[i + 1].point, rated, ends, costs);
        route.cost += (rated > want ? costs.skip : costs.hold) * std::abs(rated - want);
        if (route.cost < best.cost) best = std::move(route);
      }
      const std::vector<int>& visited = best.samples;
      const int steps_taken = static_cast<int>(visited.size()) - 1;
      last_visited = visited.back();
      // The route's points are its samples' (a map-point key's end, its point), a step a unit of
      // time.
      WalkedRoute w;
      for (int t = 0; t <= steps_taken; ++t) {
        w.points.push_back(field.sample(visited[static_cast<std::size_t>(t)]));
        w.times.push_back(static_cast<double>(t));
      }
      w.play = play_clip_route(blender, next, visited, sample_step);
      if (!keys[i].has_pose()) w.points.front() = keys[i].point;
      if (!keys[i + 1].has_pose()) w.points.back() = keys[i + 1].point;
      // The route drawn: from key i's point through the samples to key i + 1's.
      std::vector<Eigen::Vector2d> drawn{keys[i].point};
      for (const Eigen::Vector2d& p : w.points) {
        if (p != drawn.back()) drawn.push_back(p);
      }
      if (keys[i + 1].point != drawn.back()) drawn.push_back(keys[i + 1].point);
      if (untimed) {
        walked.back() = std::move(w);
        result.routes.back() = std::move(drawn);
      } else {
        walked.push_back(std::move(w));
        result.routes.push_back(std::move(drawn));
      }
    }
    routing.update(static_cast<double>(i + 1) / (K - 1));
  }
  // A segment whose keys stand further apart than the clips about them walk in its time (keys of
  // clips captured in different places, or timed too short): its root, which must meet each key
  // where it stood, glides and the feet slide. Said, with the time the clips would take.
  std::vector<char> glide_noted(static_cast<std::size_t>(K - 1), 0);
  for (int i = 0; i + 1 < K; ++i) {
    const auto& [known, apart, pace] = walks[static_cast<std::size_t>(i)];
    if (!known || options.free_roots) continue;
    const double seconds = static_cast<double>(key_frames[i + 1] - key_frames[i]) * dt;
    const double needed = apart / seconds;
    if (needed <= kGlideNoteFactor * std::max(pace, standing(i))) continue;
    glide_noted[static_cast<std::size_t>(i)] = 1;
    const auto length = [&](double v) { return length_text(key_units[i], v); };
    std::string note = name(i) + " to " + name(i + 1) + ": their roots stand " + length(apart) +
                       " apart (each where it stood in its clip), covered in " +
                       format_number(seconds, 3) + " s at " + length(needed) + "/s";
    if (pace > standing(i)) {
      note += ", " + format_number(needed / pace, 2) + " times as fast as the clips there move (" +
              length(pace) + "/s): the feet slide; at the clips' pace it takes " +
              segment_text(walking_time(i));
    } else {
      note += " where the clips there stand: the body glides, its feet sliding";
    }
    result.notes.push_back(std::move(note));
  }
  // A timed segment between keys of gaits (both phases known) whose time is out of step with
  // them: the legs must step much faster or slower than the clips to meet the later key's phase
  // in it, and the feet slide. Said, with the nearest time in step (as untimed keys take it).
  if (timed || options.frames_between >= 0) {
    for (int i = 0; i + 1 < K; ++i) {
      if (!keys[i].has_pose() || !keys[i + 1].has_pose()) continue;
      const std::optional<GaitGap> gap = gait_gap(i);
      if (!gap) continue;
      const double seconds = static_cast<double>(key_frames[i + 1] - key_frames[i]) * dt;
      // The times about `seconds` at which the later key's phase comes round (at least a frame
      // on): the legs step `slower` or `faster` times as fast as the clips to meet it (slower 0:
      // none by then).
      const double last = gap->last_by(seconds, dt);
      const bool none_by = last > seconds;
      const double slower = none_by ? 0.0 : last / seconds;
      const double faster = (none_by ? last : last + gap->cycle) / seconds;
      if (faster <= kStepNoteFactor || slower >= 1.0 / kStepNoteFactor) continue;
      // The time in step offered: as untimed keys take it (after a jump's crossfade, when the
      // keys are of two clips, and the time to walk their distance).
      const double least = clip_near(i) != clip_near(i + 1) ? kJumpFadeSeconds : dt;
      result.notes.push_back(name(i) + " to " + name(i + 1) +
                             ": out of step, the later key's gait phase comes round " +
                             format_number(gap->last_by(0.0, dt), 3) +
                             " s after the first's and every " + format_number(gap->cycle, 3) +
                             " s more; in " + format_number(seconds, 3) + " s the legs step " +
                             (slower > 0.0 ? format_number(slower, 2) + " or " : "") +
                             format_number(faster, 2) +
                             " times as fast as the clips, and the feet slide; in step it takes " +
                             segment_text(gap->nearest(seconds, std::max(least, walking_time(i)))));
    }
  }

  // The map point of every frame: equal steps of the samples' time along each route. On a clip
  // route a frame blends the two samples of its run around its clip frame (the clip's frames in
  // between), at its place between their points; about a jump the two clips crossfade
  // (clip_route_weights); a map-point key's frame is the blend at its point.
  const long long frames = key_frames.back() + 1;
  result.points.resize(static_cast<std::size_t>(frames));
  std::vector<MapWeights> frame_weights;
  if (clip_routes) frame_weights.resize(static_cast<std::size_t>(frames));
  for (int i = 0; i + 1 < K; ++i) {
    const WalkedRoute& w = walked[static_cast<std::size_t>(i)];
    const long long a = key_frames[i], b = key_frames[i + 1];
    const bool last = i + 2 == K;
    for (long long k = a; k < b || (last && k == b); ++k) {
      const double t = w.times.back() * static_cast<double>(k - a) / static_cast<double>(b - a);
      const auto ks = static_cast<std::size_t>(k);
      result.points[ks] = k == b ? w.points.back() : at_time(w, t);
      if (!clip_routes) continue;
      const bool key_point = (k == a && !keys[i].has_pose()) || (k == b && !keys[i + 1].has_pose());
      if (w.play.samples.empty() || key_point) {
        frame_weights[ks] = blender.locate(result.points[ks]);
      } else {
        // The route's steps over the segment's frames.
        frame_weights[ks] = clip_route_weights(blender, next, w.play, t,
                                               w.times.back() / (static_cast<double>(b - a) * dt));
        result.points[ks] = frame_weights[ks].validity.point;
      }
    }
  }

  // Blended poses and root motion along them: a path timed at the frames (or the clip routes'
  // weights), the weights smoothed over time as a sketch's are (kDefaultSmoothSeconds): the
  // grid route's kriging, whose neighbours change between actions from one point to the next,
  // moved a joint 61 cm in a frame from a walk's key towards a dash's, where the clips' fastest
  // moves 32 (AnInbetweenBetweenActionsMovesNoFasterThanItsClips; now 18).
  // Every key, a map-point key's too, is then reached through the displacement map below.
  // The feet are cleaned last, once the keys' poses and roots are in place.
  SynthOptions blend_only;
  blend_only.clean_feet = false;
  const Control blending = control.stage("blending frames", 0.2, 0.9);
  SynthResult synth;
  if (clip_routes) {
    synth = synthesize(blender, frame_weights, blend_only, blending);
  } else {
    MapPath path;
    path.points = result.points;
    path.times.resize(static_cast<std::size_t>(frames));
    for (long long k = 0; k < frames; ++k)
      path.times[static_cast<std::size_t>(k)] = static_cast<double>(k) * dt;
    synth = synthesize(blender, path, blend_only, blending);
  }
  if (synth.motion.num_frames != frames) {
    throw NumericalError("inbetween: " + std::to_string(synth.motion.num_frames) +
                         " frames synthesized where " + std::to_string(frames) + " were asked");
  }
  Motion& m = synth.motion;
  // The feet's contacts are found in the blend as it is now, before the keys' displacement map:
  // spread over a segment, it lifts a planted foot slowly towards a key's, which no longer looks
  // planted in the result (a left foot rose 7 cm through a stance of a held-out walk's in-between
  // and slid at 0.3 m/s).
  const Motion blended = options.clean_feet ? m : Motion{};
  const int root = blender.motion_root();
  const Axis up = blender.options().up;
  const Eigen::Vector3d up_unit = Eigen::Vector3d::Unit(static_cast<int>(up));

  // The blend split as synthesize() built it: free root placement, tilt and height.
  std::vector<double> heading(static_cast<std::size_t>(frames));
  std::vector<Eigen::Vector3d> floor(static_cast<std::size_t>(frames));
  std::vector<Eigen::Quaterniond> tilt(static_cast<std::size_t>(frames));
  std::vector<double> height(static_cast<std::size_t>(frames));
  for (long long k = 0; k < frames; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    const Eigen::Quaterniond q = m.rotation(static_cast<int>(k), root).normalized();
    heading[ks] = features::heading_angle(q, up);
    tilt[ks] = detail::remove_heading(q, up);
    const Eigen::Vector3d t = m.translation(static_cast<int>(k), root);
    height[ks] = t.dot(up_unit);
    floor[ks] = t - height[ks] * up_unit;
  }
  // The displacement map at each key: rotations (the root's of the tilts) and translations.
  std::vector<std::vector<Eigen::Quaterniond>> dq(
      static_cast<std::size_t>(K),
      std::vector<Eigen::Quaterniond>(static_cast<std::size_t>(J), Eigen::Quaterniond::Identity()));
  std::vector<std::vector<Eigen::Vector3d>> dx(
      static_cast<std::size_t>(K),
      std::vector<Eigen::Vector3d>(static_cast<std::size_t>(J), Eigen::Vector3d::Zero()));
  for (int i = 0; i < K; ++i) {
    // A map-point key's pose: the blend at its point (its root free, below).
    const Motion& p = keys[i].has_pose() ? key_poses[i] : blender.pose_at(keys[i].point);
    const int f = static_cast<int>(key_frames[i]);
    for (int j = 0; j < J; ++j) {
      if (j == root) {
        dq[i][j] = (detail::remove_heading(p.rotation(0, j), up) *
                    tilt[static_cast<std::size_t>(f)].conjugate())
                       .normalized();
        dx[i][j] =
            (p.translation(0, j).dot(up_unit) - height[static_cast<std::size_t>(f)]) * up_unit;
      } else {
        dq[i][j] = (p.rotation(0, j).normalized() * m.rotation(f, j).normalized().conjugate())
                       .normalized();
        dx[i][j] = p.translation(0, j) - m.translation(f, j);
      }
    }
  }

  // Root placements of the keys with poses, and the free placement aligned to each.
  std::vector<int> placed;
  std::vector<RootPlacement> placement(static_cast<std::size_t>(K));
  for (int i = 0; i < K; ++i) {
    if (!keys[i].has_pose() || (options.free_roots && !placed.empty())) continue;
    placed.push_back(i);
    placement[i] = root_placement(key_poses[i], 0, root, up);
    placement[i].floor -= placement[i].floor.dot(up_unit) * up_unit;
  }
  // The free placement of frame k moved rigidly so that frame `at` stands at `p`.
  auto aligned = [&](long long k, long long at, const RootPlacement& p) {
    const auto ks = static_cast<std::size_t>(k), as = static_cast<std::size_t>(at);
    RootPlacement out;
    const double turn = p.heading - heading[as];
    out.floor = p.floor + axis_rotation(up, turn) * (floor[ks] - floor[as]);
    out.heading = heading[ks] + turn;
    return out;
  };

  std::size_t next_placed = 0;  // the first key with a pose at or after the current frame
  for (int i = 0; i + 1 < K; ++i) {
    const long long a = key_frames[i], b = key_frames[i + 1];
    const bool last = i + 2 == K;
    for (long long k = a; k < b || (last && k == b); ++k) {
      const auto ks = static_cast<std::size_t>(k);
      const int f = static_cast<int>(k);
      const double s = static_cast<double>(k - a) / static_cast<double>(b - a);
      // Pose: the displacement faded between the keys.
      for (int j = 0; j < J; ++j) {
        const Eigen::Quaterniond d = slerp_or_end(dq[i][j], dq[i + 1][j], s);
        const Eigen::Vector3d t = s <= 0.0   ? dx[i][j]
                                  : s >= 1.0 ? dx[i + 1][j]
                                             : (1.0 - s) * dx[i][j] + s * dx[i + 1][j];
        if (j == root) {
          tilt[ks] = (d * tilt[ks]).normalized();
          height[ks] += t.dot(up_unit);
        } else {
          m.rotation(f, j) = (d * m.rotation(f, j)).normalized();
          m.translation(f, j) += t;
        }
      }
      // Root: between the keys with poses around k, integrated from the earlier one and its
      // error at the later one spread linearly; before the first and after the last, rigid.
      while (next_placed < placed.size() && key_frames[placed[next_placed]] < k) ++next_placed;
      RootPlacement r{heading[ks], floor[ks]};
      if (!placed.empty()) {
        const bool after_all = next_placed == placed.size();
        const int later = after_all ? placed.back() : placed[next_placed];
        if (after_all || key_frames[later] == k || next_placed == 0) {
          r = aligned(k, key_frames[later], placement[later]);
        } else {
          const int earlier = placed[next_placed - 1];
          const long long fa = key_frames[earlier], fb = key_frames[later];
          r = aligned(k, fa, placement[earlier]);
          const RootPlacement end = aligned(fb, fa, placement[earlier]);
          const double u = static_cast<double>(k - fa) / static_cast<double>(fb - fa);
          // Where the blend travels about as far as the keys are apart and in about their
          // direction, its path is turned and scaled about the earlier key onto the later one,
          // so the error spreads with the distance walked (a slower or faster walk's steps keep
          // their length ratio); elsewhere (in place, or far off) it spreads with time.
          const Eigen::Vector3d& start = placement[earlier].floor;
          const Eigen::Vector3d went = end.floor - start, want = placement[later].floor - start;
          const double ratio = want.norm() / went.norm();
          const double turn = wrap_angle(std::atan2(went.cross(want).dot(up_unit), went.dot(want)));
          if (ratio >= kMinTravelRatio && ratio <= 1.0 / kMinTravelRatio &&
              std::abs(turn) <= kMaxTravelTurn) {
            r.floor = start + ratio * (axis_rotation(up, turn) * (r.floor - start));
          } else {
            r.floor += u * (placement[later].floor - end.floor);
          }
          // The heading's error spreads with time either way: turning the body by `turn` at
          // once would swing it round on the frame after the earlier key.
          r.heading += u * wrap_angle(placement[later].heading - end.heading);
        }
      }
      m.rotation(f, root) = (axis_rotation(up, r.heading) * tilt[ks]).normalized();
      m.translation(f, root) = r.floor + height[ks] * up_unit;
    }
  }

  // Keys in time for their distance can still ask what the clips played do not do: a key behind
  // the other (clips captured in different places), or a route that stands (a bow) or walks
  // another way. Where the root then glides, the rest of the way from where the clips carry it
  // to the later key, faster than kGlideNoteShare of the clips' own speed, the feet slide: said,
  // unless the note above said so already. So do they where the clips walk and leave the body
  // facing away from the later key's heading: turned over the segment while it walks the clips'
  // path, the body walks askew, its feet sliding sideways at about 2·sin(turn/4) of the clips'
  // speed halfway (`motionmap inbetween` of the omimo walk's frame 600 to its frame 100, untimed:
  // the clips leave it facing 126° away, and its feet slide 138 cm/s in contact, 72 with free
  // roots).
  for (std::size_t q = 0; q + 1 < placed.size(); ++q) {
    const int e = placed[q], l = placed[q + 1];
    if (l == e + 1 && glide_noted[static_cast<std::size_t>(e)]) continue;
    const long long fa = key_frames[e], fb = key_frames[l];
    const double seconds = static_cast<double>(fb - fa) * dt;
    const RootPlacement carried = aligned(fb, fa, placement[e]);
    const double glide = (placement[l].floor - carried.floor).norm();
    const double turn = std::abs(wrap_angle(placement[l].heading - carried.heading));
    double walked = 0.0;  // the clips' own root path on the floor
    for (long long k = fa; k < fb; ++k) {
      walked +=
          (floor[static_cast<std::size_t>(k) + 1] - floor[static_cast<std::size_t>(k)]).norm();
    }
    const double drift = kGlideNoteFactor * standing(e) * seconds;
    const bool glides = glide > std::max(kGlideNoteShare * walked, drift);
    const bool turns = walked > drift && 2.0 * std::sin(turn / 4.0) > kGlideNoteShare;
    if (!glides && !turns) continue;
    const auto length = [&](double v) { return length_text(key_units[e], v); };
    const std::string degrees = format_number(rad_to_deg(turn), 3) + "°";
    std::string note = name(e) + " to " + name(l) + ": the clips played ";
    if (glides) {
      note += "carry the root " + length((carried.floor - placement[e].floor).norm()) +
              " and leave it " + length(glide) + " from where key " + std::to_string(l + 1) +
              "'s root stood in its clip" +
              (turns ? ", facing " + degrees + " away from its heading" : std::string()) +
              ": the root glides that in " + format_number(seconds, 3) + " s (" +
              length(glide / seconds) + "/s)" + (turns ? " and turns," : "") +
              " and the feet slide (with free roots it stands" + (turns ? " and faces" : "") +
              " where the clips carry it)";
    } else {
      note += "leave the body facing " + degrees + " away from key " + std::to_string(l + 1) +
              "'s heading in its clip: it turns that in " + format_number(seconds, 3) +
              " s as it walks, and the feet slide (with free roots it faces where the clips "
              "carry it)";
    }
    result.notes.push_back(std::move(note));
  }
  result.key_frames.assign(key_frames.begin(), key_frames.end());
  if (options.clean_feet) {
    std::string why;
    if (const std::optional<Feet> feet = try_find_feet(blender.skeleton(), up, &why)) {
      CleanFeetOptions clean;
      clean.contacts.up = up;
      clean.fixed_frames = result.key_frames;
      // The keys set the root's height between them: where a leg cannot reach its held spot it
      // reaches as far as it can (the foot creeps a few cm/s), the hips are not lowered. The
      // root's path, turned and scaled to meet the keys, outpaces the blend's strides a little:
      // lowered, the hips of the held-out proud walk's in-betweens dipped up to 5.6 cm (LAFAN1
      // protocol, docs/synthesis.md).
      clean.max_root_drop = 0.0;
      clean.keep_above_floor = true;
      const Control cleaning = control.stage("cleaning feet", 0.9, 1.0);
      std::array<FootContacts, 2> contacts =
          synth.contact_shares.empty()
              ? detect_contacts(blender.skeleton(), blended, *feet, clean.contacts)
              : contacts_from_shares(blender.skeleton(), blended, *feet, synth.contact_shares,
                                     clean.contacts);
      // ... held at the blend's heights (the keys' displacement map, spread over a segment,
      // tilts a stance: a held-out walk's planted feet stood 2-4 cm up and, rising with it, rose
      // out of the skating measure's contact line up to 0.17 s early) and cut where a key leaves
      // the foot in the air: the frames about that key where its ankle stays above the contact
      // height must lift to the key, not stand held at the key's height.
      const AnklePaths ankles = ankle_paths(blender.skeleton(), synth.motion, *feet);
      const AnklePaths blend_ankles = ankle_paths(blender.skeleton(), blended, *feet);
      std::vector<char> is_key(static_cast<std::size_t>(frames), 0);
      for (const long long k : key_frames) is_key[static_cast<std::size_t>(k)] = 1;
      for (int side = 0; side < 2; ++side) {
        FootContacts& c = contacts[side];
        for (const Eigen::Vector3d& a : blend_ankles[side])
          clean.ankle_heights[side].push_back(a.dot(up_unit));
        const double top = c.floor + clean.contacts.height * c.leg_length;
        const auto low = [&](int f) { return ankles[side][f].dot(up_unit) <= top; };
        const int shortest = frames_at_least(clean.contacts.min_seconds, 1.0 / dt);
        std::vector<ContactInterval> kept;
        const auto keep = [&](const ContactInterval& piece) {
          if (piece.frames() >= std::max(1, shortest)) kept.push_back(piece);
        };
        for (const ContactInterval& in : c.intervals) {
          // The contact's runs of frames in the air (the ankle above `top`) with a key in them
          // are cut out.
          int from = in.first;
          for (int f = in.first; f <= in.last;) {
            int g = f;
            bool key = is_key[static_cast<std::size_t>(f)] != 0;
            while (g < in.last && low(g + 1) == low(f)) {
              ++g;
              if (is_key[static_cast<std::size_t>(g)]) key = true;
            }
            if (!low(f) && key) {
              keep({from, f - 1});
              from = g + 1;
            }
            f = g + 1;
          }
          keep({from, in.last});
        }
        c.intervals = std::move(kept);
        // ... and a contact over which the ankle, the keys' root spread over the segment, glides
        // on the floor more than twice kMaxHoldDrift is cut as a gliding blend's is: standing in
        // a bow while the root crossed to a walk's key, a held foot was left 72 cm behind, lifted
        // 45 cm by its stretched leg, and snapped back 62 cm in a frame. (Every contact cut at
        // kMaxHoldDrift, the held-out proud walk's stretched stances skated 0.45, not 0.38.)
        cut_drifting_contacts(c, ankles[side], up, 1.0 / dt, clean.contacts.min_seconds,
                              kMaxHoldDrift, 2.0 * kMaxHoldDrift);
      }
      CleanFeetResult cleaned =
          clean_feet(blender.skeleton(), synth.motion, *feet, contacts, clean, cleaning);
      synth.motion = std::move(cleaned.motion);
      result.feet_cleaned = true;
    } else {
      result.notes.push_back("feet not cleaned: " + why);
    }
  }
  result.motion = std::move(synth.motion);
  result.validity = std::move(synth.validity);
  result.outside_frames = synth.clamped_frames;
  return result;
}

}  // namespace motionmap::synth
