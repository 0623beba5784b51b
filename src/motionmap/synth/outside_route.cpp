#include "motionmap/synth/detail/outside_route.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "motionmap/synth/detail/map_index.h"
#include "motionmap/synth/detail/smoothing.h"
#include "motionmap/synth/route.h"

namespace motionmap::synth::detail {

std::vector<char> stalled_frames(const MapBlender& blender, std::span<const Eigen::Vector2d> points,
                                 double dt, std::span<const MapWeights> located,
                                 std::size_t first) {
  std::vector<char> stalled(located.size(), 0);
  if (blender.options().mode != BlendMode::Local || points.size() < 2) return stalled;
  const double moving = kStallPathSpeed * blender.median_speed();
  const double followed = kFollowNear * blender.median_step();
  for (std::size_t i = 0; i < located.size(); ++i) {
    // (A path along a clip's trajectory plays that clip at its own pace, slow or fast.)
    const bool slow = located[i].pace < kStallPace && located[i].validity.distance > followed;
    if (!slow && !(located[i].lead_pace < kStallPace)) continue;
    const std::size_t k = first + i;
    const std::size_t a = k > 0 ? k - 1 : k, b = std::min(points.size() - 1, k + 1);
    const double speed = (points[b] - points[a]).norm() / (static_cast<double>(b - a) * dt);
    stalled[i] = speed >= moving ? 1 : 0;
  }
  return stalled;
}

int stall_spread(double dt) {
  return static_cast<int>(std::lround(kStallSeconds / dt));
}

std::string stalled_note(std::span<const char> stalled, std::span<const PointValidity> validity) {
  std::size_t count = 0;
  for (std::size_t k = 0; k < stalled.size(); ++k)
    count += stalled[k] && !(k < validity.size() && validity[k].clamped);
  if (count == 0) return {};
  return "gait: at " + std::to_string(count) + (count == 1 ? " frame" : " frames") +
         " the blend held its legs mid-stride while the path moved on; the clips' own "
         "frames play there and within " +
         std::to_string(static_cast<int>(std::lround(kStallSeconds * 1000))) + " ms of them";
}

OutsideRuns outside_runs(const MapBlender& blender, std::span<const Eigen::Vector2d> points,
                         std::span<const char> stalled, int spread, int pad) {
  OutsideRuns runs;
  // (A map whose samples never move has no reach: no routes, every point its edge.)
  if (blender.options().mode != BlendMode::Local || !(blender.reach_distance() > 0.0)) return runs;
  // Frames within `spread` of a stalled one.
  std::vector<char> near_stall(points.size(), 0);
  for (std::size_t k = 0; k < std::min(points.size(), stalled.size()); ++k) {
    if (!stalled[k]) continue;
    const std::size_t a = k > static_cast<std::size_t>(spread) ? k - spread : 0;
    const std::size_t b = std::min(points.size(), k + 1 + static_cast<std::size_t>(spread));
    std::fill(near_stall.begin() + static_cast<std::ptrdiff_t>(a),
              near_stall.begin() + static_cast<std::ptrdiff_t>(b), 1);
  }
  // Frames routed: near a stall, outside, or farther from every sample than half the reach and
  // than a clip is played wholly.
  const double line =
      std::max(kFollowNear * blender.median_step(), kRouteReachFraction * blender.reach_distance());
  std::vector<char> outside(points.size(), 0);
  const auto routed = [&](std::size_t k) {
    const PointValidity v = blender.validity(points[k]);
    outside[k] = v.clamped ? 1 : 0;
    return near_stall[k] || v.clamped || v.distance > line;
  };
  for (std::size_t k = 0; k < points.size();) {
    if (!routed(k)) {
      ++k;
      continue;
    }
    std::size_t e = k + 1;
    while (e < points.size() && routed(e)) ++e;
    runs.emplace_back(k, e);
    k = e;
  }
  std::erase_if(runs, [](const auto& run) { return run.second - run.first < 2; });
  // A run with frames outside the data, widened by `pad` frames each side (runs that then meet
  // joined), so that its route plays it wholly and fades in and out over the frames beside it.
  // (Unwidened, a run shorter than the fade was carried at most 0.28 by its route: a coarse golf
  // sketch cutting from impact to the follow-through past the address pose was routed in two
  // runs, 5 and 22 frames, and blended at its points the stance turned 80° and back in 0.3 s,
  // the feet sweeping round at 2–3 m/s. Runs only far inside the data or stalled keep their
  // frames: widened, the runs sketched between two takes skated more, the angry run 30 % of the
  // way to the old one 0.408 → 0.474 of its transitions cleaned.)
  for (auto& [first, end] : runs) {
    if (std::none_of(outside.begin() + static_cast<std::ptrdiff_t>(first),
                     outside.begin() + static_cast<std::ptrdiff_t>(end),
                     [](char c) { return c != 0; }))
      continue;
    first = first > static_cast<std::size_t>(pad) ? first - static_cast<std::size_t>(pad) : 0;
    end = std::min(points.size(), end + static_cast<std::size_t>(pad));
  }
  std::sort(runs.begin(), runs.end());
  OutsideRuns joined;
  for (const auto& run : runs) {
    if (!joined.empty() && run.first <= joined.back().second) {
      joined.back().second = std::max(joined.back().second, run.second);
    } else {
      joined.push_back(run);
    }
  }
  return joined;
}

int routed_outside(const OutsideRuns& runs, std::span<const PointValidity> validity) {
  int count = 0;
  for (const auto& [first, end] : runs) {
    for (std::size_t k = first; k < end; ++k) count += validity[k].clamped ? 1 : 0;
  }
  return count;
}

OutsideRoutes::OutsideRoutes(const MapBlender& blender, std::span<const Eigen::Vector2d> points,
                             double dt, const OutsideRuns& runs, std::size_t first, std::size_t end,
                             const Control& control, std::span<const MapWeights> located,
                             std::size_t located_first) {
  if (runs.empty()) return;
  const MapField field(blender);
  const std::vector<int> next = next_samples(blender);
  const double sample_step = median_sample_step(blender, next);
  const double r = field.reach_distance();
  const auto fade = static_cast<double>(blender.follow_neighbours(dt));
  // Jumps are priced by their poses as in-betweens price theirs (prices_jumps_by_poses), on a
  // saved map every sample's pose read first: so it routes as the clips mapped directly do.
  // Unpriced on the saved map of the 11 Bandai takes (the proud walk left out), the feminine
  // walk sketched with a point every third of a second (bench/traced_walks.py) took another
  // route into its stalled steps than on the same map given its clips: cleaned, 0.141 of its
  // transitions skated and a foot stayed up 1.00 s, against 0.275 and 0.73 s now.
  const bool price_jumps = prices_jumps_by_poses(blender);
  SamplePoses poses(blender);
  if (price_jumps && blender.reads_on_demand()) {
    std::vector<int> every(static_cast<std::size_t>(blender.num_samples()));
    std::iota(every.begin(), every.end(), 0);
    poses.prepare(std::move(every), control);
  }
  // The sample most of a frame's located weight is on.
  const auto anchor = [&](std::size_t k) {
    const auto mostly = [](const MapWeights& w) {
      return w.samples[static_cast<std::size_t>(
          std::max_element(w.weights.begin(), w.weights.end()) - w.weights.begin())];
    };
    if (k >= located_first && k - located_first < located.size())
      return mostly(located[k - located_first]);
    return mostly(blender.locate_path(points, dt, k, k + 1).front());
  };
  for (const auto& [a, e] : runs) {
    if (e <= first || a >= end) continue;
    Run run;
    run.first = a;
    run.end = e;
    run.weights.resize(e - a);
    // The route runs from the frame before the run to the frame after it where there are such
    // frames, from the sample the blend there is mostly on and towards the one after, so that
    // it fades in and out in step with the blend.
    const std::size_t r0 = a > 0 ? a - 1 : a, r1 = e < points.size() ? e : e - 1;
    const int end_anchor = e < points.size() ? anchor(e) : -1;
    int start = a > 0 ? anchor(a - 1) : -1;  // then the sample the last piece ended on
    for (std::size_t p0 = r0; p0 < r1; p0 += kMaxClipRouteSteps) {
      control.check();
      const std::size_t p1 = std::min(r1, p0 + kMaxClipRouteSteps);
      const bool last = p1 == r1;
      ClipRouteEnds ends;
      ends.start = start;
      // How much farther from the frame's point than the nearest sample, in reaches.
      std::vector<double> nearest(p1 - p0 + 1);
      for (std::size_t k = p0; k <= p1; ++k) nearest[k - p0] = field.distance(points[k]);
      ends.step_cost = [&](int t, int s) {
        const auto k = static_cast<std::size_t>(t);
        const double d = ((field.sample(s) - points[p0 + k]).norm() - nearest[k]) / r;
        return kOutsideTrack * d * d;
      };
      if (price_jumps) {
        ends.jump_cost = [&](int from, int to) { return pose_distance(poses(from), poses(to)); };
        if (last && end_anchor >= 0) {
          ends.end_cost = [&](int s) { return pose_distance(poses(s), poses(end_anchor)); };
        }
      }
      const Eigen::Vector2d to = last && end_anchor >= 0 ? field.sample(end_anchor) : points[p1];
      const ClipRoute route =
          find_clip_route(field, next, start >= 0 ? field.sample(start) : points[p0], to,
                          static_cast<int>(p1 - p0), ends);
      start = route.samples.back();
      const ClipRoutePlay play = play_clip_route(blender, next, route.samples, sample_step);
      // Jumps cut, not crossfaded: this route tracks the path and jumps between nearby samples of
      // one action, out of phase by a little; crossfaded, the angry run sketched halfway to the
      // old one skated 0.539 of its transitions, not 0.500 (docs/synthesis.md, clean feet).
      for (std::size_t k = std::max(p0, a); k <= std::min(p1, e - 1); ++k) {
        run.weights[k - a] =
            clip_route_weights(blender, next, play, static_cast<double>(k - p0), 1.0 / dt, 0.0);
      }
    }
    // The route's share: 1, rising from 0 over `fade` frames where the run meets the data.
    run.share.resize(e - a);
    for (std::size_t k = a; k < e; ++k) {
      const double in = a > 0 ? static_cast<double>(k - a + 1) / (fade + 1.0) : 1.0;
      const double out = e < points.size() ? static_cast<double>(e - k) / (fade + 1.0) : 1.0;
      run.share[k - a] = 1.0 - falloff(std::min(in, out));
    }
    m_runs.push_back(std::move(run));
  }
}

const OutsideRoutes::Run* OutsideRoutes::run_at(std::size_t k) const {
  const auto it = std::upper_bound(m_runs.begin(), m_runs.end(), k,
                                   [](std::size_t f, const Run& run) { return f < run.first; });
  return it != m_runs.begin() && k < (it - 1)->end ? &*(it - 1) : nullptr;
}

void OutsideRoutes::apply(std::size_t k, MapWeights& w) const {
  const Run* found = run_at(k);
  if (found == nullptr) return;
  const Run& run = *found;
  const MapWeights& route = run.weights[k - run.first];
  const double share = run.share[k - run.first];
  if (share >= 1.0) {
    const PointValidity validity = w.validity;
    w = route;
    w.validity = validity;
    return;
  }
  const double pace = share * route.pace + (1.0 - share) * w.pace;
  std::vector<std::pair<int, double>> entries;
  for (std::size_t i = 0; i < route.samples.size(); ++i)
    entries.emplace_back(route.samples[i], share * route.weights[i]);
  for (std::size_t i = 0; i < w.samples.size(); ++i)
    entries.emplace_back(w.samples[i], (1.0 - share) * w.weights[i]);
  w = weights_by_sample(std::move(entries), w.validity);
  w.pace = pace;
}

}  // namespace motionmap::synth::detail
