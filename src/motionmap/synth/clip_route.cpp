// Routes through the clips' own frames: a shortest path over (step, sample) by dynamic
// programming, one step at a time (route.h, find_clip_route).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/synth/detail/map_index.h"
#include "motionmap/synth/detail/root_motion.h"
#include "motionmap/synth/detail/smoothing.h"
#include "motionmap/synth/route.h"

namespace motionmap::synth {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The samples reached at one step: their costs and, per sample, which of the previous step's it
// came from (an index into that step's list).
struct Step {
  std::vector<int> samples;
  std::vector<double> costs;
  std::vector<int> from;
};

// What a route's step from sample `from` to `to` is (find_clip_route): the sample held, its
// clip's next, the one after that (a skip), or a jump.
enum class StepKind { Hold, Next, Skip, Jump };
StepKind step_kind(std::span<const int> next, int from, int to) {
  if (to == from) return StepKind::Hold;
  const int on = next[from];
  if (to == on) return StepKind::Next;
  if (on >= 0 && to == next[on]) return StepKind::Skip;
  return StepKind::Jump;
}

// Where a jump from sample s is found and priced from: its clip's next sample, s itself at the
// clip's last.
int jump_place(std::span<const int> next, int s) {
  return next[s] >= 0 ? next[s] : s;
}

// The previous sample of s's clip, −1 at its first (a clip's samples are consecutive).
int previous_sample(std::span<const int> next, int s) {
  return s > 0 && next[s - 1] == s ? s - 1 : -1;
}

}  // namespace

const char* route_mode_name(RouteMode mode) {
  return mode == RouteMode::Clips ? "clips" : "grid";
}

RouteMode parse_route_mode(const std::string& name) {
  if (name == "clips") return RouteMode::Clips;
  if (name == "grid") return RouteMode::Grid;
  throw ParameterError("route: '" + name + "' is not a route (clips or grid)");
}

ClipRoute find_clip_route(const MapField& field, std::span<const int> next,
                          const Eigen::Vector2d& a, const Eigen::Vector2d& b, int steps,
                          const ClipRouteEnds& ends, const ClipRouteCosts& costs) {
  const int start = ends.start;
  const int n = field.num_samples();
  if (static_cast<int>(next.size()) != n) {
    throw ParameterError("route: " + std::to_string(next.size()) + " successors for " +
                         std::to_string(n) + " samples");
  }
  for (int s = 0; s < n; ++s) {
    if (next[s] < -1 || next[s] >= n) {
      throw ParameterError("route: sample " + std::to_string(s) + "'s successor " +
                           std::to_string(next[s]) + " is out of range");
    }
  }
  if (steps < 1 || steps > kMaxClipRouteSteps) {
    throw ParameterError("route: " + std::to_string(steps) +
                         " steps is out of range (must be in [1, " +
                         std::to_string(kMaxClipRouteSteps) + "])");
  }
  if (start < -1 || start >= n) {
    throw ParameterError("route: the start sample " + std::to_string(start) + " is out of range");
  }
  if (ends.candidates < 1) {
    throw ParameterError("route: " + std::to_string(ends.candidates) +
                         " candidate ends (must be at least 1)");
  }
  if (!a.allFinite() || !b.allFinite())
    throw ParameterError("route: a key's map point is not finite");
  const double r = field.reach_distance();
  const auto sq = [r](double d) { return (d / r) * (d / r); };

  // The jumps from each sample's point and their costs, found once when first needed.
  struct Jump {
    int to;
    double cost;
  };
  std::vector<std::vector<Jump>> jumps(static_cast<std::size_t>(n));
  std::vector<char> found(static_cast<std::size_t>(n), 0);
  std::vector<int> near;
  const auto jumps_from = [&](int s) -> const std::vector<Jump>& {
    auto& out = jumps[static_cast<std::size_t>(s)];
    if (!found[static_cast<std::size_t>(s)]) {
      found[static_cast<std::size_t>(s)] = 1;
      const int k = field.nearest(field.sample(s), kClipRouteJumps + 1, near);
      for (int i = 0; i < k; ++i) {
        const double d = (field.sample(near[i]) - field.sample(s)).norm();
        if (near[i] == s || d > r) continue;
        out.push_back(
            {near[i], costs.jump + sq(d) + (ends.jump_cost ? ends.jump_cost(s, near[i]) : 0.0)});
      }
    }
    return out;
  };

  // The samples a route may start (end) on near p, and what starting (ending) on each costs: the
  // kClipRouteEnds nearest, and of the further ones up to ends.candidates those cheaper than
  // every one of those.
  const auto ends_near = [&](const Eigen::Vector2d& p, const std::function<double(int)>& extra) {
    std::vector<int> found_near;
    const int k = field.nearest(p, ends.candidates, found_near);
    std::vector<std::pair<int, double>> out;
    double cheapest_near = kInf;
    for (int i = 0; i < k; ++i) {
      const int s = found_near[i];
      const double c = costs.ends * sq((field.sample(s) - p).norm()) + (extra ? extra(s) : 0.0);
      if (i < kClipRouteEnds) {
        cheapest_near = std::min(cheapest_near, c);
      } else if (c >= cheapest_near) {
        continue;
      }
      out.emplace_back(s, c);
    }
    return out;
  };

  std::vector<Step> path(static_cast<std::size_t>(steps) + 1);
  if (start >= 0) {
    path[0] = Step{{start}, {0.0}, {-1}};
  } else {
    for (const auto& [s, c] : ends_near(a, ends.start_cost)) {
      path[0].samples.push_back(s);
      path[0].costs.push_back(c);
      path[0].from.push_back(-1);
    }
  }
  if (ends.step_cost) {
    for (std::size_t i = 0; i < path[0].samples.size(); ++i)
      path[0].costs[i] += ends.step_cost(0, path[0].samples[i]);
  }

  // Per sample, its best cost at the step being built and where from (−1: not reached).
  std::vector<double> best(static_cast<std::size_t>(n), kInf);
  std::vector<int> best_from(static_cast<std::size_t>(n), -1);
  std::vector<double> rank;  // of the samples reached, when too many are (made then)
  // The samples reached in increasing order, the same whatever the hash of the jumps: read off
  // a bitmap of them where they are many for the map's size, else sorted.
  std::vector<std::uint64_t> marks((static_cast<std::size_t>(n) + 63) / 64, 0);
  const auto in_order = [&](std::vector<int>& samples) {
    if (4 * samples.size() < marks.size()) {
      std::sort(samples.begin(), samples.end());
      return;
    }
    for (const int s : samples) marks[static_cast<std::size_t>(s) / 64] |= 1ULL << (s % 64);
    samples.clear();
    for (std::size_t w = 0; w < marks.size(); ++w) {
      for (std::uint64_t bits = marks[w]; bits != 0; bits &= bits - 1)
        samples.push_back(static_cast<int>(64 * w) + std::countr_zero(bits));
      marks[w] = 0;
    }
  };
  std::vector<int> reached;
  for (int t = 1; t <= steps; ++t) {
    const Step& prev = path[static_cast<std::size_t>(t) - 1];
    const auto offer = [&](int s, double cost, int from) {
      if (cost < best[static_cast<std::size_t>(s)]) {
        if (best_from[static_cast<std::size_t>(s)] < 0) reached.push_back(s);
        best[static_cast<std::size_t>(s)] = cost;
        best_from[static_cast<std::size_t>(s)] = from;
      }
    };
    for (int i = 0; i < static_cast<int>(prev.samples.size()); ++i) {
      const int s = prev.samples[i];
      const double c = prev.costs[i];
      offer(s, c + costs.hold, i);
      const int on = next[s];
      if (on >= 0) {
        offer(on, c, i);
        if (next[on] >= 0) offer(next[on], c + costs.skip, i);
      }
      const int from = jump_place(next, s);
      for (const Jump& jump : jumps_from(from)) {
        if (jump.to != on) offer(jump.to, c + jump.cost, i);
      }
    }
    if (ends.step_cost) {
      for (const int s : reached) best[static_cast<std::size_t>(s)] += ends.step_cost(t, s);
    }
    // Keep the cheapest when too many were reached, ranked with how far they are from b.
    if (static_cast<int>(reached.size()) > kClipRouteBeam) {
      const double left = static_cast<double>(steps - t) / steps;
      // Each one's rank computed once: the selection compares each sample a few times.
      rank.resize(static_cast<std::size_t>(n));
      for (const int s : reached) {
        rank[static_cast<std::size_t>(s)] =
            best[static_cast<std::size_t>(s)] +
            (1.0 - left) * costs.ends * sq((field.sample(s) - b).norm());
      }
      std::nth_element(
          reached.begin(), reached.begin() + kClipRouteBeam, reached.end(), [&](int x, int y) {
            return rank[static_cast<std::size_t>(x)] < rank[static_cast<std::size_t>(y)];
          });
      for (std::size_t i = kClipRouteBeam; i < reached.size(); ++i) {
        best[static_cast<std::size_t>(reached[i])] = kInf;
        best_from[static_cast<std::size_t>(reached[i])] = -1;
      }
      reached.resize(kClipRouteBeam);
    }
    in_order(reached);
    Step& step = path[static_cast<std::size_t>(t)];
    for (int s : reached) {
      step.samples.push_back(s);
      step.costs.push_back(best[static_cast<std::size_t>(s)]);
      step.from.push_back(best_from[static_cast<std::size_t>(s)]);
      best[static_cast<std::size_t>(s)] = kInf;
      best_from[static_cast<std::size_t>(s)] = -1;
    }
    reached.clear();
  }

  // The cheapest end among the samples it may end on (any sample reached when none of them is,
  // or the bridge), then back to the start.
  const Step& last = path.back();
  std::vector<double> end_cost(static_cast<std::size_t>(n), kInf);
  const std::vector<std::pair<int, double>> b_ends = ends_near(b, ends.end_cost);
  for (const auto& [s, c] : b_ends) end_cost[static_cast<std::size_t>(s)] = c;
  // The bridge: the cheapest start and end, each clip played towards the middle, one jump there.
  ClipRoute bridge;
  bridge.cost = kInf;
  if (ends.bridge_jump_cost && !b_ends.empty()) {
    const auto first = std::min_element(path[0].costs.begin(), path[0].costs.end());
    const auto end =
        std::min_element(b_ends.begin(), b_ends.end(),
                         [](const auto& x, const auto& y) { return x.second < y.second; });
    bridge.samples.resize(static_cast<std::size_t>(steps) + 1);
    const int middle = steps / 2;
    int held = 0;
    int s = path[0].samples[static_cast<std::size_t>(first - path[0].costs.begin())];
    for (int t = 0; t <= middle; ++t) {
      bridge.samples[static_cast<std::size_t>(t)] = s;
      if (next[s] >= 0)
        s = next[s];
      else if (t < middle)
        ++held;
    }
    s = end->first;
    for (int t = steps; t > middle; --t) {
      bridge.samples[static_cast<std::size_t>(t)] = s;
      if (const int before = previous_sample(next, s); before >= 0)
        s = before;
      else if (t > middle + 1)
        ++held;
    }
    // The middle: a jump, priced as the search's are from the next sample's place, unless the
    // two halves meet in one clip (a hold, a step or a skip there).
    const int from = bridge.samples[static_cast<std::size_t>(middle)];
    const int to = bridge.samples[static_cast<std::size_t>(middle) + 1];
    double jump = 0.0;  // a step to the next sample
    switch (step_kind(next, from, to)) {
      case StepKind::Hold:
        jump = costs.hold;
        break;
      case StepKind::Skip:
        jump = costs.skip;
        break;
      case StepKind::Jump:
        jump = costs.jump + ends.bridge_jump_cost(jump_place(next, from), to);
        break;
      case StepKind::Next:
        break;
    }
    bridge.cost = *first + held * costs.hold + end->second;
    for (int t = 1; ends.step_cost && t <= steps; ++t)
      bridge.cost += ends.step_cost(t, bridge.samples[static_cast<std::size_t>(t)]);
    // Where nothing else reaches b's ends, the bridge even where its jump is forbidden, then at
    // kForbiddenBridge so that any other route (at another rate) costs less.
    if (std::none_of(last.samples.begin(), last.samples.end(),
                     [&](int x) { return std::isfinite(end_cost[static_cast<std::size_t>(x)]); })) {
      bridge.cost += std::isfinite(jump) ? jump : kForbiddenBridge;
      return bridge;
    }
    bridge.cost += jump;
  }
  int at = -1;
  double cheapest = kInf;
  for (const bool near_b : {true, false}) {
    for (int i = 0; i < static_cast<int>(last.samples.size()); ++i) {
      const int s = last.samples[i];
      if (near_b && !std::isfinite(end_cost[static_cast<std::size_t>(s)])) continue;
      const double c = last.costs[i] + (near_b ? end_cost[static_cast<std::size_t>(s)]
                                               : costs.ends * sq((field.sample(s) - b).norm()));
      if (c < cheapest) {
        cheapest = c;
        at = i;
      }
    }
    if (at >= 0) break;
  }
  ClipRoute route;
  route.cost = cheapest;
  route.samples.resize(static_cast<std::size_t>(steps) + 1);
  for (int t = steps; t >= 0; --t) {
    const Step& step = path[static_cast<std::size_t>(t)];
    route.samples[static_cast<std::size_t>(t)] = step.samples[static_cast<std::size_t>(at)];
    at = step.from[static_cast<std::size_t>(at)];
  }
  if (!std::isfinite(bridge.cost)) return route;
  // Against the bridge, the route's jumps are priced as the bridge's is (where jump_cost prices
  // them otherwise: a saved map's, by their map distance alone, chained a walk into a dash
  // through poses 70 cm apart).
  double priced = route.cost;
  for (int t = 1; t <= steps; ++t) {
    const int from = route.samples[static_cast<std::size_t>(t) - 1];
    const int to = route.samples[static_cast<std::size_t>(t)];
    if (step_kind(next, from, to) != StepKind::Jump) continue;
    const int place = jump_place(next, from);
    priced += ends.bridge_jump_cost(place, to) - (ends.jump_cost ? ends.jump_cost(place, to) : 0.0);
  }
  return bridge.cost < priced ? bridge : route;
}

std::vector<int> next_samples(const MapBlender& blender) {
  std::vector<int> next(static_cast<std::size_t>(blender.num_samples()));
  for (int s = 0; s < blender.num_samples(); ++s) next[s] = blender.next_sample(s);
  return next;
}

double median_sample_step(const MapBlender& blender, std::span<const int> next) {
  std::vector<int> steps;
  for (int s = 0; s < static_cast<int>(next.size()); ++s) {
    if (next[s] >= 0) steps.push_back(blender.sample_frame(next[s]) - blender.sample_frame(s));
  }
  if (steps.empty()) return 1.0;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

ClipRoutePlay play_clip_route(const MapBlender& blender, std::span<const int> next,
                              std::vector<int> visited, double sample_step) {
  ClipRoutePlay play;
  play.samples = std::move(visited);
  const int steps = static_cast<int>(play.samples.size()) - 1;
  for (int t = 1; t <= steps; ++t) {
    const int at = play.samples[static_cast<std::size_t>(t)];
    const int from = play.samples[static_cast<std::size_t>(t) - 1];
    const StepKind kind = step_kind(next, from, at);
    const bool jump = kind == StepKind::Jump;
    play.advance.push_back(kind == StepKind::Hold ? 0.0
                           : jump                 ? sample_step
                                  : blender.sample_frame(at) - blender.sample_frame(from));
    play.jumps.push_back(jump ? 1 : 0);
  }
  play.run_start.assign(static_cast<std::size_t>(std::max(steps, 0)), 0);
  for (int t0 = 0; t0 < steps;) {
    int t1 = t0 + 1;
    if (!play.jumps[t0]) {
      while (t1 < steps && !play.jumps[t1]) ++t1;
      double total = 0.0;
      for (int t = t0; t < t1; ++t) total += play.advance[t];
      for (int t = t0; t < t1; ++t) play.advance[t] = total / (t1 - t0);
    }
    for (int t = t0; t < t1; ++t) play.run_start[t] = t0;
    t0 = t1;
  }
  return play;
}

namespace {

// The two samples of s's clip around its frame `frame` and the later one's weight: found from s
// along the clip (a clip's samples are consecutive), its first or last sample beyond its ends.
struct ClipFrame {
  int a = 0, b = 0;
  double f = 0.0;
};
ClipFrame clip_frame(const MapBlender& blender, std::span<const int> next, int s, double frame) {
  ClipFrame out;
  out.a = s;
  while (blender.sample_frame(out.a) > frame && previous_sample(next, out.a) >= 0) --out.a;
  while (next[out.a] >= 0 && blender.sample_frame(next[out.a]) <= frame) out.a = next[out.a];
  out.b = next[out.a] >= 0 ? next[out.a] : out.a;
  const double span = blender.sample_frame(out.b) - blender.sample_frame(out.a);
  out.f = span > 0.0 ? std::clamp((frame - blender.sample_frame(out.a)) / span, 0.0, 1.0) : 0.0;
  return out;
}

// A route frame's validity: at its map point, the sample most of its weight is on its nearest.
PointValidity route_validity(const MapBlender& blender, const Eigen::Vector2d& point, int nearest) {
  PointValidity v;
  v.query = v.point = point;
  v.nearest_sample = nearest;
  v.distance = (point - blender.sample_point(nearest)).norm();
  return v;
}

// Within a jump's crossfade (fade_seconds about its middle, less where another jump or an end
// of the route is nearer), the weights of the clip jumped from played on and the clip jumped to
// played up to it, mixed by a smoothstep; nullopt elsewhere.
std::optional<MapWeights> crossfade(const MapBlender& blender, std::span<const int> next,
                                    const ClipRoutePlay& play, double t, double steps_per_second,
                                    double fade_seconds) {
  const int steps = static_cast<int>(play.samples.size()) - 1;
  if (!(fade_seconds > 0.0)) return std::nullopt;
  // In steps; at least the jump's own step, so that no frame of it is cut.
  const double h = std::max(0.5, 0.5 * fade_seconds * steps_per_second);
  const int lo = std::max(0, static_cast<int>(std::floor(t - h - 0.5)));
  const int hi = std::min(steps - 1, static_cast<int>(std::ceil(t + h)));
  for (int J = lo; J <= hi; ++J) {
    if (!play.jumps[static_cast<std::size_t>(J)]) continue;
    double half = std::min({h, J + 0.5, steps - J - 0.5});
    for (int o = J - 1; o >= 0 && J - o < 2.0 * half; --o) {
      if (play.jumps[static_cast<std::size_t>(o)]) half = std::min(half, 0.5 * (J - o));
    }
    for (int o = J + 1; o < steps && o - J < 2.0 * half; ++o) {
      if (play.jumps[static_cast<std::size_t>(o)]) half = std::min(half, 0.5 * (o - J));
    }
    const double u = half > 0.0 ? (t - (J + 0.5 - half)) / (2.0 * half) : -1.0;
    if (u <= 0.0 || u >= 1.0) continue;
    const double to_share = 1.0 - detail::falloff(u);
    const auto j = static_cast<std::size_t>(J);
    const double from_pace = J > 0 && !play.jumps[j - 1] ? play.advance[j - 1] : play.advance[j];
    const double to_pace =
        J + 1 < steps && !play.jumps[j + 1] ? play.advance[j + 1] : play.advance[j];
    const int from = play.samples[j], to = play.samples[j + 1];
    const ClipFrame x =
        clip_frame(blender, next, from, blender.sample_frame(from) + (t - J) * from_pace);
    const ClipFrame y =
        clip_frame(blender, next, to, blender.sample_frame(to) - (J + 1 - t) * to_pace);
    std::vector<std::pair<int, double>> parts{{x.a, (1.0 - to_share) * (1.0 - x.f)},
                                              {x.b, (1.0 - to_share) * x.f},
                                              {y.a, to_share * (1.0 - y.f)},
                                              {y.b, to_share * y.f}};
    std::erase_if(parts, [](const auto& part) { return part.second <= 0.0; });
    MapWeights out = detail::weights_by_sample(std::move(parts), {});
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
    for (std::size_t k = 0; k < out.samples.size(); ++k)
      point += out.weights[k] * blender.sample_point(out.samples[k]);
    const int nearest = out.samples[static_cast<std::size_t>(
        std::max_element(out.weights.begin(), out.weights.end()) - out.weights.begin())];
    const double i = std::clamp(std::floor(t), 0.0, steps - 1.0);
    out.pace = play.advance[static_cast<std::size_t>(i)] * blender.frame_time() * steps_per_second;
    out.validity = route_validity(blender, point, nearest);
    return out;
  }
  return std::nullopt;
}

}  // namespace

MapWeights clip_route_weights(const MapBlender& blender, std::span<const int> next,
                              const ClipRoutePlay& play, double t, double steps_per_second,
                              double fade_seconds) {
  int a = play.samples.front(), b = a;
  double f = 0.0, pace = 1.0;
  if (play.samples.size() > 1) {
    if (std::optional<MapWeights> mixed =
            crossfade(blender, next, play, t, steps_per_second, fade_seconds))
      return *std::move(mixed);
    const double steps = static_cast<double>(play.samples.size()) - 1.0;
    const double i = std::clamp(std::floor(t), 0.0, steps - 1.0);
    const auto step = static_cast<std::size_t>(i);
    f = std::clamp(t - i, 0.0, 1.0);
    a = play.samples[step];
    b = play.samples[step + 1];
    pace = play.advance[step] * blender.frame_time() * steps_per_second;
    if (play.jumps[step]) {
      f = f < 0.5 ? 0.0 : 1.0;
    } else {
      // In a run, the clip's frame at the run's even pace, between the two samples around it.
      const int t0 = play.run_start[step];
      const int first = play.samples[static_cast<std::size_t>(t0)];
      const ClipFrame at = clip_frame(blender, next, first,
                                      blender.sample_frame(first) + (t - t0) * play.advance[step]);
      a = at.a;
      b = at.b;
      f = at.f;
    }
  }
  // The frame's map point: where its samples' are, weighted alike.
  const Eigen::Vector2d point = (1.0 - f) * blender.sample_point(a) + f * blender.sample_point(b);
  const int nearest = f < 0.5 ? a : b;
  MapWeights out = MapWeights::of_sample(nearest);
  out.pace = pace;
  if (a != b && f > 0.0 && f < 1.0) {
    double wa = 1.0 - f, wb = f;
    if (b < a) {
      std::swap(a, b);
      std::swap(wa, wb);
    }
    out.samples = {a, b};
    out.weights = {wa, wb};
  }
  out.validity = route_validity(blender, point, nearest);
  return out;
}

PoseRotations pose_rotations(const MapBlender& blender, const Motion& pose) {
  const int J = pose.num_joints, root = blender.motion_root();
  PoseRotations q(static_cast<std::size_t>(J));
  for (int j = 0; j < J; ++j) {
    q[j] = pose.rotation(0, j).normalized();
    if (j == root) q[j] = detail::remove_heading(q[j], blender.options().up);
  }
  return q;
}

double pose_distance(const PoseRotations& a, const PoseRotations& b) {
  double sum = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j)
    sum += std::pow(a[j].angularDistance(b[j]) / kRoutePoseAngle, 2);
  return sum / static_cast<double>(a.size());
}

bool prices_jumps_by_poses(const MapBlender& blender, int priced_samples) {
  return !blender.reads_on_demand() || blender.num_samples() <= priced_samples;
}

const PoseRotations& SamplePoses::operator()(int sample) {
  auto it = m_poses.find(sample);
  if (it == m_poses.end()) {
    it = m_poses
             .emplace(sample,
                      pose_rotations(m_blender, m_blender.pose(MapWeights::of_sample(sample))))
             .first;
  }
  return it->second;
}

void SamplePoses::prepare(std::vector<int> samples, const Control& control) {
  std::sort(samples.begin(), samples.end());
  samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
  std::erase_if(samples, [&](int s) { return m_poses.count(s) > 0; });
  std::vector<MapWeights> weights;
  for (const int s : samples) weights.push_back(MapWeights::of_sample(s));
  m_blender.prefetch(weights);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    control.check();
    m_poses.emplace(samples[i], pose_rotations(m_blender, m_blender.pose(weights[i])));
  }
}

}  // namespace motionmap::synth
