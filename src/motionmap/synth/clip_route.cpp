// Routes through the clips' own frames: a shortest path over (step, sample) by dynamic
// programming, one step at a time (route.h, find_clip_route).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "motionmap/core/error.h"
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

  // Per sample, its best cost at the step being built and where from (−1: not reached).
  std::vector<double> best(static_cast<std::size_t>(n), kInf);
  std::vector<int> best_from(static_cast<std::size_t>(n), -1);
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
      const int from = on >= 0 ? on : s;
      for (const Jump& jump : jumps_from(from)) {
        if (jump.to != on) offer(jump.to, c + jump.cost, i);
      }
    }
    // Keep the cheapest when too many were reached, ranked with how far they are from b.
    if (static_cast<int>(reached.size()) > kClipRouteBeam) {
      const double left = static_cast<double>(steps - t) / steps;
      const auto rank = [&](int s) {
        return best[static_cast<std::size_t>(s)] +
               (1.0 - left) * costs.ends * sq((field.sample(s) - b).norm());
      };
      std::nth_element(reached.begin(), reached.begin() + kClipRouteBeam, reached.end(),
                       [&](int x, int y) { return rank(x) < rank(y); });
      for (std::size_t i = kClipRouteBeam; i < reached.size(); ++i) {
        best[static_cast<std::size_t>(reached[i])] = kInf;
        best_from[static_cast<std::size_t>(reached[i])] = -1;
      }
      reached.resize(kClipRouteBeam);
    }
    std::sort(reached.begin(), reached.end());  // the same order whatever the hash of the jumps
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

  // The cheapest end among the samples it may end on (any sample reached when none of them is),
  // then back to the start.
  const Step& last = path.back();
  std::vector<double> end_cost(static_cast<std::size_t>(n), kInf);
  for (const auto& [s, c] : ends_near(b, ends.end_cost)) end_cost[static_cast<std::size_t>(s)] = c;
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
  return route;
}

}  // namespace motionmap::synth
