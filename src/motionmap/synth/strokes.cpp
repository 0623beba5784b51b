#include "motionmap/synth/detail/strokes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "motionmap/synth/blender.h"
#include "motionmap/synth/detail/smoothing.h"

namespace motionmap::synth::detail {

namespace {

// A clip time near a point of the path: its run (first sample), the seconds into the run and the
// squared distance from the point to the curve there. At most kFollowTimelines of them, the
// nearest, each from a different place in the clips (kFollowSameSeconds apart), as
// locate_path() fits.
struct Near {
  int run = 0;
  double seconds = 0.0, distance2 = 0.0;
};

std::vector<Near> clip_times_near(const MapIndex& index, const Eigen::Vector2d& p, double radius) {
  std::vector<MapIndex::TrajectoryHit> hits;
  index.trajectory_near(p, radius, kTrajectoryMaxSeconds, hits);
  std::vector<Near> out;
  for (const auto& hit : hits) {  // nearest first: keep the nearest of each place in a clip
    if (out.size() >= static_cast<std::size_t>(kFollowTimelines)) break;
    const auto [run, seconds] = index.clip_time(hit);
    const Near n{run, seconds, hit.distance * hit.distance};
    const bool seen = std::any_of(out.begin(), out.end(), [&](const Near& o) {
      return o.run == n.run && std::abs(o.seconds - n.seconds) < kFollowSameSeconds;
    });
    if (!seen) out.push_back(n);
  }
  return out;
}

// 1 within [kFollowMinRate, kFollowMaxRate], falling to 0 over a further kStrokeRateMargin.
double rate_factor(double rate) {
  if (!(rate > 0.0)) return 0.0;
  const double over = std::max(std::log(kFollowMinRate / rate), std::log(rate / kFollowMaxRate));
  return falloff(over / std::log(kStrokeRateMargin));
}

}  // namespace

void follow_strokes(const MapIndex& index, const MapPath& timed, double dt,
                    std::span<Eigen::Vector2d> points) {
  const double step = index.median_step();
  if (!(step > 0.0) || timed.points.size() < 2) return;
  const double near = kFollowNear * step, far = kFollowFar * step;
  const double t0 = timed.times.front();
  Eigen::Vector2d v;
  // The clip times near each point of the path, found when a stroke needs them.
  std::vector<std::vector<Near>> near_point(timed.points.size());
  std::vector<char> known(timed.points.size(), 0);
  const auto clip_times = [&](std::size_t i) -> const std::vector<Near>& {
    if (!known[i]) near_point[i] = clip_times_near(index, timed.points[i], far);
    known[i] = 1;
    return near_point[i];
  };
  for (std::size_t s = 0; s + 1 < timed.points.size(); ++s) {
    const double ta = timed.times[s] - t0, tb = timed.times[s + 1] - t0;
    // The stroke's frames: t = k·dt strictly between its ends.
    const auto k0 = static_cast<std::size_t>(std::floor(ta / dt + 1e-9)) + 1;
    const auto k1 = std::min(points.size(), static_cast<std::size_t>(std::ceil(tb / dt - 1e-9)));
    if (k0 >= k1) continue;
    const Eigen::Vector2d& a = timed.points[s];
    const Eigen::Vector2d& b = timed.points[s + 1];
    const std::vector<Near>& at_a = clip_times(s);
    const std::vector<Near>& at_b = clip_times(s + 1);
    struct Candidate {
      Near a, b;
      double rate = 1.0, cost = 0.0;
    };
    std::vector<Candidate> found;
    double least = std::numeric_limits<double>::infinity();
    for (const Near& na : at_a) {
      for (const Near& nb : at_b) {
        if (nb.run != na.run) continue;
        const double rate = (nb.seconds - na.seconds) / (tb - ta);
        const double fit = rate_factor(rate);
        if (fit == 0.0) continue;
        // Drawn at the clip's own timing, or as far off it as a rate of 2 (½) is off it.
        const double timing = std::log(rate) / std::log(2.0);
        const double cost = 0.5 * (na.distance2 + nb.distance2) + timing * timing * near * near +
                            (1.0 - fit) * far * far;
        found.push_back({na, nb, rate, cost});
        least = std::min(least, cost);
      }
    }
    const double share = found.empty() ? 0.0 : falloff((std::sqrt(least) - near) / (far - near));
    if (share == 0.0) continue;
    const double tie = kFollowTie * least + kFollowTieSteps * kFollowTieSteps * step * step;
    std::vector<double> alpha(found.size());
    double total = 0.0;
    // The ends' offsets from their points on each sharing candidate's curve.
    std::vector<std::array<Eigen::Vector2d, 2>> offsets(found.size());
    for (std::size_t c = 0; c < found.size(); ++c) {
      alpha[c] = falloff((found[c].cost - least) / tie);
      total += alpha[c];
      if (alpha[c] == 0.0) continue;
      offsets[c] = {a - index.trajectory_at(found[c].a.run, found[c].a.seconds, v),
                    b - index.trajectory_at(found[c].b.run, found[c].b.seconds, v)};
    }
    for (std::size_t k = k0; k < k1; ++k) {
      const double t = static_cast<double>(k) * dt;
      const double u = (t - ta) / (tb - ta);
      Eigen::Vector2d curve = Eigen::Vector2d::Zero();
      for (std::size_t c = 0; c < found.size(); ++c) {
        if (alpha[c] == 0.0) continue;
        const Candidate& f = found[c];
        const Eigen::Vector2d on = index.trajectory_at(f.a.run, f.a.seconds + f.rate * (t - ta), v);
        curve += (alpha[c] / total) * (on + (1.0 - u) * offsets[c][0] + u * offsets[c][1]);
      }
      points[k] = (1.0 - share) * points[k] + share * curve;
    }
  }
}

}  // namespace motionmap::synth::detail
