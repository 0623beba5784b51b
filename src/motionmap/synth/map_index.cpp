#include "motionmap/synth/detail/map_index.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/stats.h"
#include "motionmap/synth/detail/point_tree.h"

namespace motionmap::synth::detail {

namespace {

// Samples closer than this fraction of the map's extent share one map point.
constexpr double kMergeFraction = 1e-9;

// The 0-based median map step/speed: the upper median (as the blender always had; numpy's mean of
// the two middle values would move the reach, the local systems' separation and the default
// synthesis speed), 0 when there is none.
double median_or_zero(std::vector<double> values) {
  return values.empty() ? 0.0 : upper_median(std::move(values));
}

}  // namespace

struct MapIndex::Tree : detail::PointTree {
  using PointTree::PointTree;
};

MapIndex::MapIndex(std::span<const double> frame_times, const features::FeatureSet& samples,
                   std::vector<Eigen::Vector2d> sample_points, double reach)
    : m_sample_points(std::move(sample_points)) {
  const int n = num_samples();
  Eigen::Vector2d lo = m_sample_points.front(), hi = lo;
  for (const auto& c : m_sample_points) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  const double extent = (hi - lo).norm();
  const double tol = kMergeFraction * extent;

  // Merge samples within tol of an earlier representative (a radius search per representative).
  std::vector<int> point_of(static_cast<std::size_t>(n), -1);
  std::vector<std::vector<int>> groups;
  if (extent == 0.0) {
    groups.emplace_back();
    for (int i = 0; i < n; ++i) groups.back().push_back(i);
  } else {
    const Tree sample_tree(m_sample_points);
    std::vector<std::pair<std::uint32_t, double>> found;
    for (int i = 0; i < n; ++i) {
      if (point_of[i] >= 0) continue;
      const int id = static_cast<int>(groups.size());
      groups.emplace_back();
      sample_tree.index.radiusSearch(m_sample_points[i].data(), tol * tol, found,
                                     nanoflann::SearchParams(32, 0.0f, false));
      point_of[i] = id;
      groups.back().push_back(i);
      for (const auto& [s, d2] : found) {
        if (point_of[s] < 0) {
          point_of[s] = id;
          groups.back().push_back(static_cast<int>(s));
        }
      }
      std::sort(groups.back().begin(), groups.back().end());
    }
  }
  m_member_start.push_back(0);
  for (const auto& g : groups) {
    m_points.push_back(m_sample_points[g.front()]);
    m_members.insert(m_members.end(), g.begin(), g.end());
    m_member_start.push_back(static_cast<int>(m_members.size()));
  }
  m_tree = std::make_unique<Tree>(m_points);
  m_point_of = std::move(point_of);

  // Median step and speed over consecutive samples of a clip that do not share a map point.
  auto consecutive = [&](int i) {
    return samples.clip_of[i] == samples.clip_of[i + 1] &&
           samples.frame_of[i + 1] > samples.frame_of[i];
  };
  auto seconds = [&](int i) {
    return (samples.frame_of[i + 1] - samples.frame_of[i]) *
           frame_times[static_cast<std::size_t>(samples.clip_of[i])];
  };
  std::vector<double> steps, speeds;
  for (int i = 0; i + 1 < n; ++i) {
    if (!consecutive(i)) continue;
    const double step = (m_sample_points[i + 1] - m_sample_points[i]).norm();
    if (step <= tol || step == 0.0) continue;
    const double dt = seconds(i);
    steps.push_back(step);
    speeds.push_back(step / dt);
  }
  m_frame_of = samples.frame_of;
  m_frame_time.resize(static_cast<std::size_t>(n));
  m_run_first.resize(static_cast<std::size_t>(n));
  m_run_last.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    m_frame_time[i] = frame_times[static_cast<std::size_t>(samples.clip_of[i])];
    m_run_first[i] = i > 0 && consecutive(i - 1) ? m_run_first[i - 1] : i;
  }
  for (int i = n - 1; i >= 0; --i)
    m_run_last[i] = i + 1 < n && consecutive(i) ? m_run_last[i + 1] : i;
  m_run_stride.assign(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; i = m_run_last[i] + 1) {
    const int first = i, last = m_run_last[i];
    int stride = last > first ? m_frame_of[first + 1] - m_frame_of[first] : 0;
    for (int j = first + 1; j <= last && stride > 0; ++j)
      if (m_frame_of[j] - m_frame_of[j - 1] != stride) stride = 0;
    std::fill(m_run_stride.begin() + first, m_run_stride.begin() + last + 1, stride);
  }
  std::vector<char> on_segment(static_cast<std::size_t>(n), 0);
  for (int i = 0; i + 1 < n; ++i) {
    if (!consecutive(i)) continue;
    m_segments.emplace_back(i, i + 1);
    m_segment_seconds.push_back(seconds(i));
    on_segment[i] = on_segment[i + 1] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (on_segment[i]) continue;
    m_segments.emplace_back(i, i);
    m_segment_seconds.push_back(0.0);
  }
  // clamp()'s search: the segments in tiers of length (each up to twice the last), a k-d tree
  // over each tier's midpoints.
  const double base = extent > 0.0 ? extent * 1e-6 : 1.0;
  double magnitude = 0.0;
  for (const auto& c : m_sample_points) magnitude = std::max(magnitude, c.cwiseAbs().maxCoeff());
  // Well above the rounding of a midpoint or of a distance between map points.
  m_search_slack = 1e-12 * (magnitude + extent) + std::numeric_limits<double>::min();
  std::vector<std::vector<int>> tier_segments;
  std::vector<std::vector<Eigen::Vector2d>> tier_midpoints;
  std::vector<double> tier_half;
  for (std::size_t s = 0; s < m_segments.size(); ++s) {
    const Eigen::Vector2d& a = m_sample_points[m_segments[s].first];
    const Eigen::Vector2d& b = m_sample_points[m_segments[s].second];
    const double length = (b - a).norm();
    const std::size_t t =
        length > base ? static_cast<std::size_t>(std::ceil(std::log2(length / base))) : 0;
    if (t >= tier_segments.size()) {
      tier_segments.resize(t + 1);
      tier_midpoints.resize(t + 1);
      tier_half.resize(t + 1, 0.0);
    }
    tier_segments[t].push_back(static_cast<int>(s));
    tier_midpoints[t].push_back(0.5 * (a + b));
    tier_half[t] = std::max(tier_half[t], 0.5 * length);
  }
  for (std::size_t t = 0; t < tier_segments.size(); ++t) {
    if (tier_segments[t].empty()) continue;
    m_tiers.push_back(SegmentTier{std::move(tier_segments[t]), tier_half[t],
                                  std::make_unique<Tree>(std::move(tier_midpoints[t]))});
  }
  m_median_step = median_or_zero(std::move(steps));
  m_median_speed = median_or_zero(std::move(speeds));
  m_reach_distance = reach_radius(reach, m_median_step, (hi - lo).maxCoeff());
}

MapIndex::~MapIndex() = default;
MapIndex::MapIndex(MapIndex&&) noexcept = default;
MapIndex& MapIndex::operator=(MapIndex&&) noexcept = default;

int MapIndex::nearest(const Eigen::Vector2d& p, int k, std::uint32_t* idx, double* dist) const {
  const auto found =
      static_cast<int>(m_tree->index.knnSearch(p.data(), static_cast<std::size_t>(k), idx, dist));
  for (int i = 0; i < found; ++i) dist[i] = std::sqrt(dist[i]);
  return found;
}

Eigen::Vector2d MapIndex::clamp(const Eigen::Vector2d& p, double nearest_distance) const {
  // The nearest point q of the trajectory, then back towards p by s(q) = √(r² − e²), e = the
  // distance from q to the nearer end of its segment: at most r from that sample, and
  // continuous in p (unlike the nearest point of the union of reach disks, which jumps at every
  // boundary between two samples' Voronoi cells); it jumps only where two stretches of
  // trajectory are equally near.
  //
  // Only segments that can be nearest are looked at, in the order of m_segments, so the first of
  // equally near ones wins as in a scan of all of them: the nearest sample's own segment is at
  // most `nearest_distance` away, and a segment that near has its midpoint within that plus half
  // its length of p.
  std::vector<int> candidates;
  std::vector<std::pair<std::uint32_t, double>> found;
  for (const SegmentTier& tier : m_tiers) {
    const double radius = (nearest_distance + tier.half_length) * (1.0 + 1e-9) + m_search_slack;
    tier.midpoints->index.radiusSearch(p.data(), radius * radius, found,
                                       nanoflann::SearchParams(32, 0.0f, false));
    for (const auto& [i, d2] : found) candidates.push_back(tier.segments[i]);
  }
  std::sort(candidates.begin(), candidates.end());

  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d q = p;
  double e = 0.0;
  for (const int segment : candidates) {
    const auto [a, b] = m_segments[static_cast<std::size_t>(segment)];
    const Eigen::Vector2d& ca = m_sample_points[a];
    const Eigen::Vector2d d = m_sample_points[b] - ca;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - ca).dot(d) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d foot = ca + t * d;
    const double dist2 = (p - foot).squaredNorm();
    if (dist2 < best) {
      best = dist2;
      q = foot;
      e = std::min(t, 1.0 - t) * std::sqrt(len2);
    }
  }
  const double s = std::sqrt(std::max(0.0, m_reach_distance * m_reach_distance - e * e));
  const double dist = std::sqrt(best);
  return dist > s ? Eigen::Vector2d(q + (p - q) * (s / dist)) : p;
}

void MapIndex::trajectory_near(const Eigen::Vector2d& p, double radius, double max_seconds,
                               std::vector<TrajectoryHit>& out) const {
  out.clear();
  std::vector<std::pair<std::uint32_t, double>> found;
  for (const SegmentTier& tier : m_tiers) {
    const double r = (radius + tier.half_length) * (1.0 + 1e-9) + m_search_slack;
    tier.midpoints->index.radiusSearch(p.data(), r * r, found,
                                       nanoflann::SearchParams(32, 0.0f, false));
    for (const auto& [i, d2] : found) {
      const auto segment = static_cast<std::size_t>(tier.segments[i]);
      const auto [a, b] = m_segments[segment];
      if (a == b || m_segment_seconds[segment] > max_seconds) continue;
      const Eigen::Vector2d& ca = m_sample_points[a];
      const Eigen::Vector2d d = m_sample_points[b] - ca;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - ca).dot(d) / len2, 0.0, 1.0) : 0.0;
      const double dist = (p - (ca + t * d)).norm();
      if (dist < radius) out.push_back({a, b, t, dist, m_segment_seconds[segment]});
    }
  }
  std::sort(out.begin(), out.end(), [](const TrajectoryHit& x, const TrajectoryHit& y) {
    return x.distance != y.distance ? x.distance < y.distance : x.first < y.first;
  });
}

namespace {

// A whole number; the nearest one to x where x is within half of one (only the snap to a whole
// frame below reads it). Inline, unlike std::round's library call: the fits of locate_path
// evaluate clip times millions of times.
double near_whole(double x) {
  if (!(std::abs(x) < 0x1p51)) return x;  // whole already (or not finite)
  return static_cast<double>(static_cast<long long>(x < 0.0 ? x - 0.5 : x + 0.5));
}

}  // namespace

int MapIndex::time_in_run(std::size_t s, double seconds, double& frame, int* samples,
                          double* weights) const {
  const double raw = m_frame_of[s] + seconds / m_frame_time[s];
  frame = raw;
  const double whole = near_whole(raw);
  const double snapped = std::abs(raw - whole) < 1e-9 ? whole : raw;  // a whole frame
  const int first = m_run_first[s], last = m_run_last[s];
  const auto frame_at = [&](int i) {
    return static_cast<double>(m_frame_of[static_cast<std::size_t>(i)]);
  };
  samples[0] = snapped <= frame_at(first) ? first : last;
  weights[0] = 1.0;
  if (snapped <= frame_at(first) || snapped >= frame_at(last)) return 1;
  // The last sample of the run at or before `snapped` (frames increase along the run): found
  // directly in a run of evenly spaced frames (the quotient is positive: truncation floors it).
  int a = 0;
  if (const int stride = m_run_stride[s]; stride == 1) {
    a = first + static_cast<int>(snapped - frame_at(first));
  } else if (stride > 0) {
    a = first + static_cast<int>((snapped - frame_at(first)) / stride);
  } else {
    const auto begin = m_frame_of.begin() + first, end = m_frame_of.begin() + last + 1;
    a = static_cast<int>(
        std::upper_bound(begin, end, snapped, [](double f, int g) { return f < g; }) - 1 -
        m_frame_of.begin());
  }
  const double fa = frame_at(a), gap = frame_at(a + 1) - fa;
  const double u = gap == 1.0 ? snapped - fa : (snapped - fa) / gap;
  samples[0] = a;
  if (u <= 0.0) return 1;
  samples[1] = a + 1;
  weights[0] = 1.0 - u;
  weights[1] = u;
  return 2;
}

int MapIndex::later_in_clip(int sample, double seconds, int* samples, double* weights) const {
  double frame = 0.0;
  return time_in_run(static_cast<std::size_t>(sample), seconds, frame, samples, weights);
}

Eigen::Vector2d MapIndex::trajectory_at(int sample, double seconds,
                                        Eigen::Vector2d& velocity) const {
  int at[2] = {0, 0};
  double w[2] = {1.0, 0.0};
  const auto s = static_cast<std::size_t>(sample);
  double frame = 0.0;  // not snapped to a whole frame
  const int count = time_in_run(s, seconds, frame, at, w);
  // The segment [a, a + 1] of the run whose velocity is taken (none beyond the run's ends).
  int a = at[0];
  if (count == 1 && a == m_run_last[s]) --a;
  if (a < m_run_first[s] || frame < m_frame_of[static_cast<std::size_t>(m_run_first[s])] ||
      frame > m_frame_of[static_cast<std::size_t>(m_run_last[s])]) {
    velocity.setZero();
    return m_sample_points[static_cast<std::size_t>(at[0])];
  }
  const auto ua = static_cast<std::size_t>(a);
  const double step_seconds = (m_frame_of[ua + 1] - m_frame_of[ua]) * m_frame_time[ua];
  velocity = (m_sample_points[ua + 1] - m_sample_points[ua]) / step_seconds;
  if (count == 1) return m_sample_points[static_cast<std::size_t>(at[0])];
  return w[0] * m_sample_points[static_cast<std::size_t>(at[0])] +
         w[1] * m_sample_points[static_cast<std::size_t>(at[1])];
}

double MapIndex::seconds_in_run(int sample) const {
  const auto s = static_cast<std::size_t>(sample);
  return (m_frame_of[s] - m_frame_of[static_cast<std::size_t>(m_run_first[s])]) * m_frame_time[s];
}

PointValidity MapIndex::validate(const Eigen::Vector2d& p) const {
  if (!p.allFinite()) {
    throw ParameterError("map point (" + format_number(p.x()) + ", " + format_number(p.y()) +
                         ") is not finite");
  }
  PointValidity v;
  v.query = p;
  std::uint32_t idx = 0;
  double d = 0.0;
  nearest(p, 1, &idx, &d);
  v.distance = d;
  v.nearest_sample = m_members[m_member_start[idx]];
  v.point = p;
  if (d > m_reach_distance) {
    v.point = clamp(p, d);
    v.clamped = true;
  }
  return v;
}

MapWeights MapIndex::to_sample_weights(const std::vector<std::pair<int, double>>& point_weights,
                                       const PointValidity& validity) const {
  std::vector<std::pair<int, double>> sw;
  sw.reserve(point_weights.size());
  for (const auto& [p, w] : point_weights) {
    const int b = m_member_start[p], e = m_member_start[static_cast<std::size_t>(p) + 1];
    const double share = w / (e - b);
    for (int s = b; s < e; ++s) sw.emplace_back(m_members[s], share);
  }
  return weights_by_sample(std::move(sw), validity);
}

MapWeights weights_by_sample(std::vector<std::pair<int, double>> entries,
                             const PointValidity& validity) {
  std::sort(entries.begin(), entries.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  MapWeights out;
  out.validity = validity;
  for (const auto& [s, w] : entries) {
    if (!out.samples.empty() && out.samples.back() == s) {
      out.weights.back() += w;
    } else {
      out.samples.push_back(s);
      out.weights.push_back(w);
    }
  }
  return out;
}

void MapIndex::to_sample_weights(const double* point_weights, double* sample_weights) const {
  for (int p = 0; p < num_points(); ++p) {
    const int b = m_member_start[p], e = m_member_start[static_cast<std::size_t>(p) + 1];
    for (int s = b; s < e; ++s) {
      sample_weights[m_members[static_cast<std::size_t>(s)]] = point_weights[p] / (e - b);
    }
  }
}

}  // namespace motionmap::synth::detail
