#include "motionmap/synth/blender.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/LU>
#include <nanoflann.hpp>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/features/point_cloud.h"

namespace motionmap::synth {

namespace {

// Samples closer than this fraction of the map's extent share one map point.
constexpr double kMergeFraction = 1e-9;
// Local systems pick neighbours at least this fraction of the median step apart, so 120 fps
// samples almost on top of each other do not make them ill-conditioned.
constexpr double kSeparationFraction = 0.25;
// A distance below this fraction of the partition radius counts as a hit on the sample (the
// Franke–Little weight would overflow; the weights it replaces differ by < 1e-24).
constexpr double kHitFraction = 1e-12;
// Kriging queries are solved in blocks of this many points (bounds the right-hand-side memory).
constexpr int kKrigingBlock = 64;

struct PointSet {
  std::vector<Eigen::Vector2d> points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return points[i][static_cast<Eigen::Index>(d)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>,
                                                   PointSet, 2, std::uint32_t>;

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * kPi);
  return a <= -kPi ? a + 2.0 * kPi : a;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Franke–Little partition-of-unity weights of `count` points at sorted distances d (not squared),
// falling to 0 at radius R: ((R − d)/(R·d))², normalised; 1 on a point hit exactly.
void partition_weights(const double* d, int count, double R, double* phi) {
  std::fill(phi, phi + count, 0.0);
  if (count == 1 || d[0] <= kHitFraction * R) {
    phi[0] = 1.0;
    return;
  }
  double sum = 0.0;
  for (int i = 0; i < count; ++i) {
    const double t = std::max(R - d[i], 0.0) / (R * d[i]);
    phi[i] = t * t;
    sum += phi[i];
  }
  if (sum > 0.0) {
    for (int i = 0; i < count; ++i) phi[i] /= sum;
    return;
  }
  // Every point exactly at R (a tie with the next one): share equally between the nearest.
  int ties = 0;
  while (ties < count && d[ties] == d[0]) ++ties;
  for (int i = 0; i < ties; ++i) phi[i] = 1.0 / ties;
}

bool same_translation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() <= 1e-12 * (1.0 + a.norm());
}

}  // namespace

std::string_view blend_mode_name(BlendMode mode) {
  switch (mode) {
    case BlendMode::Kriging:
      return "kriging";
    case BlendMode::Local:
      return "local";
    case BlendMode::Idw:
      return "idw";
  }
  return "?";
}

std::optional<BlendMode> parse_blend_mode(std::string_view name) {
  for (BlendMode m : {BlendMode::Kriging, BlendMode::Local, BlendMode::Idw}) {
    if (name == blend_mode_name(m)) return m;
  }
  return std::nullopt;
}

void BlendOptions::validate(int num_samples) const {
  if (mode != BlendMode::Kriging && (neighbors < 1 || neighbors > num_samples)) {
    throw ParameterError("neighbors: " + std::to_string(neighbors) +
                         " is out of range (must be in [1, " + std::to_string(num_samples) +
                         "], the map's sample count)");
  }
  if (!(reach > 0.0) || !std::isfinite(reach)) {
    throw ParameterError("reach: " + format_number(reach) +
                         " is out of range (must be a finite number > 0)");
  }
  if (up != Axis::X && up != Axis::Y && up != Axis::Z) throw ParameterError("up: not an axis");
}

struct MapBlender::Impl {
  BlendOptions options;
  Skeleton skeleton;
  double frame_time = 0.0;
  int joints = 0;
  int motion_root = 0;
  int n = 0;  // samples
  std::vector<Eigen::Vector2d> sample_points;

  // Per sample, precomputed so a query only sums.
  std::vector<Eigen::Quaterniond> rotations;  // #samples × #joints; the motion root's is its tilt
  std::vector<int> moving;  // joints other than the motion root whose translation varies
  std::vector<Eigen::Vector3d> moving_translations;  // #samples × moving.size()
  std::vector<Eigen::Vector3d>
      fixed_translations;  // #joints: sample 0's, motion root's floor zeroed
  std::vector<double> height;
  std::vector<Eigen::Vector3d> velocity;  // heading-local floor velocity, units/s
  std::vector<double> yaw_rate;           // rad/s

  // Distinct map points ("points"): merged samples.
  PointSet points;
  std::unique_ptr<KdTree> tree;
  std::vector<int> member_start,
      members;  // members of point j: members[member_start[j] … member_start[j+1])
  // The trajectory: segments between consecutive samples of a clip, and isolated samples as
  // segments of length 0 (start, end sample).
  std::vector<std::pair<int, int>> segments;
  double median_step = 0.0, median_speed = 0.0, reach_distance = 0.0;

  // Local mode: per point, its neighbourhood (point indices) and the inverse of its bordered
  // variogram matrix ((k+1)², column-major).
  std::vector<int> hood_start, hood;
  std::vector<std::size_t> inverse_start;
  std::vector<double> inverses;

  // Kriging mode: the LU factors of [A 1; 1ᵀ 0] in place, and the row permutation.
  Eigen::MatrixXd lu;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;

  int max_hood = 0;  // largest local neighbourhood

  int num_points() const { return static_cast<int>(points.points.size()); }

  // The k nearest points to p: indices and (non-squared) distances, nearest first.
  int nearest(const Eigen::Vector2d& p, int k, std::uint32_t* idx, double* dist) const {
    const auto found =
        static_cast<int>(tree->knnSearch(p.data(), static_cast<std::size_t>(k), idx, dist));
    for (int i = 0; i < found; ++i) dist[i] = std::sqrt(dist[i]);
    return found;
  }

  void build_samples(std::span<const Clip> clips, const features::FeatureSet& samples);
  void build_points(std::span<const Clip> clips, const features::FeatureSet& samples);
  void build_local();
  void build_kriging();

  // Where an outside point is evaluated (see clamp's definition).
  Eigen::Vector2d clamp(const Eigen::Vector2d& p) const;
  // Validity of p and the point to evaluate.
  PointValidity validate_point(const Eigen::Vector2d& p) const;
  // Point weights (point index, weight) at v.point; sets v.variance. Not for kriging.
  void point_weights(PointValidity& v, std::vector<std::pair<int, double>>& out) const;
  // Point weights → sample weights, sorted and merged.
  MapWeights expand(const std::vector<std::pair<int, double>>& point_w,
                    const PointValidity& v) const;
  void kriging_block(std::span<const Eigen::Vector2d> pts, std::span<MapWeights> out) const;
};

void MapBlender::Impl::build_samples(std::span<const Clip> clips,
                                     const features::FeatureSet& samples) {
  const Axis up = options.up;
  const int J = joints;
  const auto uJ = static_cast<std::size_t>(J);

  // The shallowest motion root over the clips: a joint that moves in any clip carries motion.
  motion_root = std::numeric_limits<int>::max();
  for (const Clip& clip : clips)
    motion_root = std::min(motion_root, motionmap::motion_root(clip.skeleton, clip.motion));

  const auto un = static_cast<std::size_t>(n);
  rotations.resize(un * uJ);
  height.resize(un);
  velocity.resize(un);
  yaw_rate.resize(un);
  const int r = motion_root;
  const Eigen::Vector3d e_up = Eigen::Vector3d::Unit(static_cast<int>(up));
  auto floor = [&](Eigen::Vector3d v) {
    v[static_cast<int>(up)] = 0.0;
    return v;
  };
  for (int i = 0; i < n; ++i) {
    const Motion& m = clips[samples.clip_of[i]].motion;
    const int f = samples.frame_of[i];
    const auto row = static_cast<std::size_t>(i) * uJ;
    for (int j = 0; j < J; ++j)
      rotations[row + static_cast<std::size_t>(j)] = m.rotation(f, j).normalized();
    const Eigen::Quaterniond q = m.rotation(f, r).normalized();
    const double heading = features::heading_angle(q, up);
    rotations[row + static_cast<std::size_t>(r)] = (axis_rotation(up, -heading) * q).normalized();
    height[i] = m.translation(f, r).dot(e_up);
    // Forward difference to the next frame (the last frame repeats its predecessor's), so that
    // integrating the samples' own velocities retraces the clip exactly.
    const int a = m.num_frames == 1 ? f : (f + 1 < m.num_frames ? f : f - 1);
    const int b = m.num_frames == 1 ? f : a + 1;
    const double ha = features::heading_angle(m.rotation(a, r).normalized(), up);
    const double hb = features::heading_angle(m.rotation(b, r).normalized(), up);
    const double dt = m.frame_time;
    velocity[i] = axis_rotation(up, -ha) * floor(m.translation(b, r) - m.translation(a, r)) / dt;
    yaw_rate[i] = wrap_angle(hb - ha) / dt;
  }

  // Translations: blend only joints whose translation differs between samples (animated
  // position channels, or clips with different offsets).
  const Motion& m0 = clips[samples.clip_of[0]].motion;
  fixed_translations.resize(uJ);
  for (int j = 0; j < J; ++j) {
    fixed_translations[j] = m0.translation(samples.frame_of[0], j);
    if (j == r) continue;
    bool varies = false;
    for (int i = 1; i < n && !varies; ++i) {
      const Motion& m = clips[samples.clip_of[i]].motion;
      varies = !same_translation(m.translation(samples.frame_of[i], j), fixed_translations[j]);
    }
    if (varies) moving.push_back(j);
  }
  fixed_translations[r] = Eigen::Vector3d::Zero();
  const std::size_t mv = moving.size();
  moving_translations.resize(un * mv);
  for (int i = 0; i < n; ++i) {
    const Motion& m = clips[samples.clip_of[i]].motion;
    for (std::size_t k = 0; k < mv; ++k) {
      moving_translations[static_cast<std::size_t>(i) * mv + k] =
          m.translation(samples.frame_of[i], moving[k]);
    }
  }
}

void MapBlender::Impl::build_points(std::span<const Clip> clips,
                                    const features::FeatureSet& samples) {
  Eigen::Vector2d lo = sample_points.front(), hi = lo;
  for (const auto& c : sample_points) {
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
    PointSet all{sample_points};
    KdTree sample_tree(2, all, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    std::vector<std::pair<std::uint32_t, double>> found;
    for (int i = 0; i < n; ++i) {
      if (point_of[i] >= 0) continue;
      const int id = static_cast<int>(groups.size());
      groups.emplace_back();
      sample_tree.radiusSearch(sample_points[i].data(), tol * tol, found,
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
  member_start.push_back(0);
  for (const auto& g : groups) {
    points.points.push_back(sample_points[g.front()]);
    members.insert(members.end(), g.begin(), g.end());
    member_start.push_back(static_cast<int>(members.size()));
  }
  tree = std::make_unique<KdTree>(2, points, nanoflann::KDTreeSingleIndexAdaptorParams(16));

  // Median step and speed over consecutive samples of a clip that do not share a map point.
  std::vector<double> steps, speeds;
  for (int i = 0; i + 1 < n; ++i) {
    if (samples.clip_of[i] != samples.clip_of[i + 1] ||
        samples.frame_of[i + 1] <= samples.frame_of[i])
      continue;
    const double step = (sample_points[i + 1] - sample_points[i]).norm();
    if (step <= tol || step == 0.0) continue;
    const double dt = (samples.frame_of[i + 1] - samples.frame_of[i]) *
                      clips[samples.clip_of[i]].motion.frame_time;
    steps.push_back(step);
    speeds.push_back(step / dt);
  }
  std::vector<char> on_segment(static_cast<std::size_t>(n), 0);
  for (int i = 0; i + 1 < n; ++i) {
    if (samples.clip_of[i] != samples.clip_of[i + 1] ||
        samples.frame_of[i + 1] <= samples.frame_of[i])
      continue;
    segments.emplace_back(i, i + 1);
    on_segment[i] = on_segment[i + 1] = 1;
  }
  for (int i = 0; i < n; ++i) {
    if (!on_segment[i]) segments.emplace_back(i, i);
  }
  median_step = median(steps);
  median_speed = median(speeds);
  reach_distance = options.reach * median_step;
}

void MapBlender::Impl::build_local() {
  const int np = num_points();
  const int K = std::min(options.neighbors, np);
  const double separation = kSeparationFraction * median_step;
  hood_start.push_back(0);
  inverse_start.push_back(0);
  std::vector<std::uint32_t> idx;
  std::vector<double> dist;
  std::vector<int> chosen;
  for (int j = 0; j < np; ++j) {
    const Eigen::Vector2d& cj = points.points[j];
    // Greedy: nearest first, skipping candidates closer than `separation` to one already chosen;
    // widen the candidate list while too few are far enough apart.
    int candidates = std::min(np, 4 * K);
    for (;;) {
      idx.resize(static_cast<std::size_t>(candidates));
      dist.resize(static_cast<std::size_t>(candidates));
      const int found = nearest(cj, candidates, idx.data(), dist.data());
      chosen.assign(1, j);
      for (int c = 0; c < found && static_cast<int>(chosen.size()) < K; ++c) {
        const int cand = static_cast<int>(idx[c]);
        if (cand == j) continue;
        const Eigen::Vector2d& pc = points.points[cand];
        bool apart = true;
        for (int s : chosen) apart = apart && (pc - points.points[s]).norm() >= separation;
        if (apart) chosen.push_back(cand);
      }
      // Give up widening at 64·K candidates (a crowd of samples closer than the separation):
      // a smaller system is still exact at its own sample, and set-up stays O(N·K log N).
      if (static_cast<int>(chosen.size()) == K || candidates == np || candidates >= 64 * K) break;
      candidates = static_cast<int>(std::min<long long>(np, 4LL * candidates));
    }
    const auto k = static_cast<Eigen::Index>(chosen.size());
    Eigen::MatrixXd M(k + 1, k + 1);
    for (Eigen::Index a = 0; a < k; ++a) {
      for (Eigen::Index b = 0; b < k; ++b) {
        M(a, b) = (points.points[chosen[a]] - points.points[chosen[b]]).norm();
      }
      M(a, k) = M(k, a) = 1.0;
    }
    M(k, k) = 0.0;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(M);
    if (!(lu.rcond() > 1e-13)) {
      throw NumericalError("local kriging system of map point " + std::to_string(j) +
                           " is singular (reciprocal condition " + format_number(lu.rcond()) + ")");
    }
    const Eigen::MatrixXd inv = lu.inverse();
    max_hood = std::max(max_hood, static_cast<int>(k));
    hood.insert(hood.end(), chosen.begin(), chosen.end());
    hood_start.push_back(static_cast<int>(hood.size()));
    inverses.insert(inverses.end(), inv.data(), inv.data() + inv.size());
    inverse_start.push_back(inverses.size());
  }
}

void MapBlender::Impl::build_kriging() {
  const int np = num_points();
  if (np > kMaxKrigingSamples) {
    throw ParameterError("blend: kriging over " + std::to_string(np) +
                         " distinct map points exceeds the limit of " +
                         std::to_string(kMaxKrigingSamples) +
                         " (a dense (N+1)² system); use the local mode or a frame stride");
  }
  lu.resize(np + 1, np + 1);
  for (int b = 0; b < np; ++b) {
    for (int a = 0; a < np; ++a) {
      lu(a, b) = (points.points[a] - points.points[b]).norm();
    }
    lu(np, b) = lu(b, np) = 1.0;
  }
  lu(np, np) = 0.0;
  // In place: the (N+1)² factors replace the matrix, no second copy.
  const Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd>> factor(lu);
  const double rcond = factor.rcond();
  if (!(rcond > 1e-15)) {
    throw NumericalError("the kriging system is singular (reciprocal condition " +
                         format_number(rcond) + "); use the local mode");
  }
  perm = factor.permutationP();
}

Eigen::Vector2d MapBlender::Impl::clamp(const Eigen::Vector2d& p) const {
  // The nearest point q of the trajectory, then back towards p by s(q) = √(r² − e²), e = the
  // distance from q to the nearer end of its segment: at most r from that sample, and
  // continuous in p (unlike the nearest point of the union of reach disks, which jumps at every
  // boundary between two samples' Voronoi cells); it jumps only where two stretches of
  // trajectory are equally near. Linear in #samples, for outside points only.
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d q = p;
  double e = 0.0;
  for (const auto& [a, b] : segments) {
    const Eigen::Vector2d& ca = sample_points[a];
    const Eigen::Vector2d d = sample_points[b] - ca;
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
  const double s = std::sqrt(std::max(0.0, reach_distance * reach_distance - e * e));
  const double dist = std::sqrt(best);
  return dist > s ? Eigen::Vector2d(q + (p - q) * (s / dist)) : p;
}

PointValidity MapBlender::Impl::validate_point(const Eigen::Vector2d& p) const {
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
  v.nearest_sample = members[member_start[idx]];
  v.point = p;
  if (d > reach_distance) {
    v.point = clamp(p);
    v.clamped = true;
  }
  return v;
}

void MapBlender::Impl::point_weights(PointValidity& v,
                                     std::vector<std::pair<int, double>>& out) const {
  out.clear();
  const int np = num_points();
  const bool local = options.mode == BlendMode::Local;
  const int count = std::min(local ? kLocalPartitionSize : options.neighbors, np);
  std::vector<std::uint32_t> idx(static_cast<std::size_t>(count + 1));
  std::vector<double> dist(static_cast<std::size_t>(count + 1)),
      phi(static_cast<std::size_t>(count));
  const int found = nearest(v.point, count + 1, idx.data(), dist.data());
  // The partition radius: the next point's distance (a point leaving the set has weight 0);
  // with no next point, twice the farthest.
  const double R =
      found > count ? dist[count] : 2.0 * dist[found - 1] + std::numeric_limits<double>::min();
  partition_weights(dist.data(), count, R, phi.data());
  if (!local) {
    for (int i = 0; i < count; ++i) {
      if (phi[i] != 0.0) out.emplace_back(static_cast<int>(idx[i]), phi[i]);
    }
    v.variance = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  v.variance = 0.0;
  std::vector<double> rhs(static_cast<std::size_t>(max_hood + 1)), sol(rhs.size());
  for (int i = 0; i < count; ++i) {
    if (phi[i] == 0.0) continue;
    const auto j = static_cast<std::size_t>(idx[i]);
    const int begin = hood_start[j];
    const int k = hood_start[j + 1] - begin;
    for (int a = 0; a < k; ++a) {
      rhs[a] = (points.points[hood[static_cast<std::size_t>(begin + a)]] - v.point).norm();
    }
    rhs[k] = 1.0;
    const Eigen::Map<const Eigen::MatrixXd> inv(inverses.data() + inverse_start[j], k + 1, k + 1);
    Eigen::Map<Eigen::VectorXd> x(sol.data(), k + 1);
    x.noalias() = inv * Eigen::Map<const Eigen::VectorXd>(rhs.data(), k + 1);
    double var = x[k];
    for (int a = 0; a < k; ++a) {
      var += x[a] * rhs[a];
      out.emplace_back(hood[begin + a], phi[i] * x[a]);
    }
    v.variance += phi[i] * var;
  }
}

MapWeights MapBlender::Impl::expand(const std::vector<std::pair<int, double>>& point_w,
                                    const PointValidity& v) const {
  std::vector<std::pair<int, double>> sw;
  sw.reserve(point_w.size());
  for (const auto& [p, w] : point_w) {
    const int b = member_start[p], e = member_start[static_cast<std::size_t>(p) + 1];
    const double share = w / (e - b);
    for (int s = b; s < e; ++s) sw.emplace_back(members[s], share);
  }
  std::sort(sw.begin(), sw.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  MapWeights out;
  out.validity = v;
  for (const auto& [s, w] : sw) {
    if (!out.samples.empty() && out.samples.back() == s) {
      out.weights.back() += w;
    } else {
      out.samples.push_back(s);
      out.weights.push_back(w);
    }
  }
  return out;
}

void MapBlender::Impl::kriging_block(std::span<const Eigen::Vector2d> pts,
                                     std::span<MapWeights> out) const {
  const int np = num_points();
  const auto m = static_cast<Eigen::Index>(pts.size());
  Eigen::MatrixXd rhs(np + 1, m);
  for (Eigen::Index c = 0; c < m; ++c) {
    const Eigen::Vector2d& p = out[c].validity.point;
    for (int a = 0; a < np; ++a) rhs(a, c) = (points.points[a] - p).norm();
    rhs(np, c) = 1.0;
  }
  Eigen::MatrixXd x = perm * rhs;
  lu.triangularView<Eigen::UnitLower>().solveInPlace(x);
  lu.triangularView<Eigen::Upper>().solveInPlace(x);
  std::vector<double> dense(static_cast<std::size_t>(n));
  for (Eigen::Index c = 0; c < m; ++c) {
    MapWeights& w = out[c];
    w.validity.variance = x.col(c).head(np).dot(rhs.col(c).head(np)) + x(np, c);
    std::fill(dense.begin(), dense.end(), 0.0);
    for (int p = 0; p < np; ++p) {
      const int b = member_start[p], e = member_start[static_cast<std::size_t>(p) + 1];
      for (int s = b; s < e; ++s) dense[members[static_cast<std::size_t>(s)]] = x(p, c) / (e - b);
    }
    w.samples.resize(static_cast<std::size_t>(n));
    w.weights = dense;
    for (int s = 0; s < n; ++s) w.samples[s] = s;
  }
}

MapBlender::MapBlender(std::span<const Clip> clips, const features::FeatureSet& samples,
                       const Eigen::MatrixXd& coords, const BlendOptions& options)
    : m(std::make_unique<Impl>()) {
  const int n = samples.num_samples();
  if (n < 1) throw ParameterError("map: the feature set has no samples");
  options.validate(n);
  if (clips.empty()) throw ParameterError("map: no clip given");
  if (static_cast<int>(samples.clip_of.size()) != n) {
    throw ParameterError("map: the feature set has " + std::to_string(samples.clip_of.size()) +
                         " clip indices for " + std::to_string(n) + " samples");
  }
  if (coords.rows() != n) {
    throw ParameterError("map: it has " + std::to_string(coords.rows()) +
                         " rows but the features have " + std::to_string(n) +
                         " samples; the map does not belong to these clips");
  }
  if (coords.cols() < 2) {
    throw ParameterError("map: it has " + std::to_string(coords.cols()) +
                         " column(s); at least 2 are needed");
  }
  const Skeleton& skeleton = clips.front().skeleton;
  for (const Clip& clip : clips) {
    if (!clip.skeleton.same_hierarchy(skeleton)) {
      throw ParameterError(clip.path + ": its joint hierarchy differs from " + clips.front().path +
                           "'s; clips blended together must share one");
    }
    const Motion& mo = clip.motion;
    const auto size =
        static_cast<std::size_t>(mo.num_frames) * static_cast<std::size_t>(mo.num_joints);
    if (mo.num_joints != skeleton.num_joints() || mo.rotations.size() != size ||
        mo.translations.size() != size) {
      throw ParameterError(clip.path + ": its motion does not fit its skeleton (" +
                           std::to_string(mo.num_joints) + " joints for " +
                           std::to_string(skeleton.num_joints()) + ")");
    }
    if (!(mo.frame_time > 0.0) || !std::isfinite(mo.frame_time)) {
      throw ParameterError(clip.path + ": frame time " + format_number(mo.frame_time) +
                           " is not > 0");
    }
    for (std::size_t k = 0; k < size; ++k) {
      if (!mo.rotations[k].coeffs().allFinite() || !mo.translations[k].allFinite() ||
          mo.rotations[k].norm() < 1e-6) {
        throw NumericalError(clip.path + ": frame " +
                             std::to_string(k / static_cast<std::size_t>(mo.num_joints)) +
                             " holds a NaN, infinite or zero value");
      }
    }
  }
  if (skeleton.num_joints() < 1) throw ParameterError("map: the skeleton has no joint");
  for (int i = 0; i < n; ++i) {
    const int c = samples.clip_of[i];
    if (c < 0 || c >= static_cast<int>(clips.size())) {
      throw ParameterError("map: sample " + std::to_string(i) + " belongs to clip " +
                           std::to_string(c) + " but only " + std::to_string(clips.size()) +
                           " clip(s) were given");
    }
    const int f = samples.frame_of[i];
    const Clip& clip = clips[c];
    if (f < 0 || f >= clip.motion.num_frames) {
      throw ParameterError("map: sample " + std::to_string(i) + " is frame " + std::to_string(f) +
                           " of " + clip.path + ", which has " +
                           std::to_string(clip.motion.num_frames) +
                           " frames; the map does not belong to these clips");
    }
    if (!std::isfinite(coords(i, 0)) || !std::isfinite(coords(i, 1))) {
      throw NumericalError("map: row " + std::to_string(i) + " holds a NaN or infinite coordinate");
    }
  }

  Impl& s = *m;
  s.options = options;
  s.skeleton = skeleton;
  s.frame_time = clips.front().motion.frame_time;
  s.joints = skeleton.num_joints();
  s.n = n;
  s.sample_points.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) s.sample_points[i] = Eigen::Vector2d(coords(i, 0), coords(i, 1));
  s.build_samples(clips, samples);
  s.build_points(clips, samples);
  if (options.mode == BlendMode::Local) s.build_local();
  if (options.mode == BlendMode::Kriging) s.build_kriging();
}

MapBlender::~MapBlender() = default;
MapBlender::MapBlender(MapBlender&&) noexcept = default;
MapBlender& MapBlender::operator=(MapBlender&&) noexcept = default;

MapWeights MapBlender::locate(const Eigen::Vector2d& p) const {
  if (m->options.mode == BlendMode::Kriging)
    return std::move(locate(std::span<const Eigen::Vector2d>(&p, 1)).front());
  PointValidity v = m->validate_point(p);
  std::vector<std::pair<int, double>> pw;
  m->point_weights(v, pw);
  return m->expand(pw, v);
}

std::vector<MapWeights> MapBlender::locate(std::span<const Eigen::Vector2d> pts) const {
  std::vector<MapWeights> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) out[i].validity = m->validate_point(pts[i]);
  if (m->options.mode != BlendMode::Kriging) {
    std::vector<std::pair<int, double>> pw;
    for (auto& w : out) {
      PointValidity v = w.validity;
      m->point_weights(v, pw);
      w = m->expand(pw, v);
    }
    return out;
  }
  for (std::size_t b = 0; b < pts.size(); b += kKrigingBlock) {
    const std::size_t e = std::min(pts.size(), b + kKrigingBlock);
    m->kriging_block(pts.subspan(b, e - b), std::span<MapWeights>(out).subspan(b, e - b));
  }
  return out;
}

BlendedFrame MapBlender::blend(const MapWeights& w) const {
  const Impl& s = *m;
  if (w.samples.size() != w.weights.size() || w.samples.empty()) {
    throw ParameterError("blend: " + std::to_string(w.samples.size()) + " sample indices for " +
                         std::to_string(w.weights.size()) +
                         " weights (need equal, non-zero counts)");
  }
  std::size_t ref = 0;
  double total = 0.0;
  for (std::size_t k = 0; k < w.samples.size(); ++k) {
    if (w.samples[k] < 0 || w.samples[k] >= s.n) {
      throw ParameterError("blend: sample index " + std::to_string(w.samples[k]) +
                           " is out of range [0, " + std::to_string(s.n) + ")");
    }
    if (!std::isfinite(w.weights[k]))
      throw ParameterError("blend: weight " + std::to_string(k) + " is not finite");
    if (w.weights[k] > w.weights[ref]) ref = k;
    total += w.weights[k];
  }
  if (!(std::abs(total) > 1e-12))
    throw ParameterError("blend: the weights sum to " + format_number(total) + ", not about 1");

  const auto J = static_cast<std::size_t>(s.joints);
  const std::size_t mv = s.moving.size();
  std::vector<Eigen::Vector4d> qsum(J, Eigen::Vector4d::Zero());
  std::vector<Eigen::Vector3d> tsum(mv, Eigen::Vector3d::Zero());
  const Eigen::Quaterniond* qref =
      s.rotations.data() + static_cast<std::size_t>(w.samples[ref]) * J;
  BlendedFrame out;
  double height = 0.0, yaw = 0.0;
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < w.samples.size(); ++k) {
    const auto i = static_cast<std::size_t>(w.samples[k]);
    const double wk = w.weights[k];
    const Eigen::Quaterniond* q = s.rotations.data() + i * J;
    for (std::size_t j = 0; j < J; ++j) {
      const Eigen::Vector4d& c = q[j].coeffs();
      qsum[j] += (c.dot(qref[j].coeffs()) < 0.0 ? -wk : wk) * c;
    }
    const Eigen::Vector3d* t = s.moving_translations.data() + i * mv;
    for (std::size_t k2 = 0; k2 < mv; ++k2) tsum[k2] += wk * t[k2];
    height += wk * s.height[i];
    yaw += wk * s.yaw_rate[i];
    vel += wk * s.velocity[i];
  }
  out.rotations.resize(J);
  for (std::size_t j = 0; j < J; ++j) {
    const double norm = qsum[j].norm();
    // Weights that cancel (e.g. negative weights on opposite rotations): keep the reference's.
    out.rotations[j] =
        norm > 1e-12 * std::abs(total) ? Eigen::Quaterniond(qsum[j] / norm) : qref[j];
  }
  // A blend of heading-free tilts can keep a trace of heading: remove it, so the pose faces
  // heading 0 exactly (a no-op at samples).
  Eigen::Quaterniond& tilt = out.rotations[static_cast<std::size_t>(s.motion_root)];
  tilt = (axis_rotation(s.options.up, -features::heading_angle(tilt, s.options.up)) * tilt)
             .normalized();
  out.translations = s.fixed_translations;
  for (std::size_t k = 0; k < mv; ++k) out.translations[s.moving[k]] = tsum[k] / total;
  out.translations[s.motion_root][static_cast<int>(s.options.up)] = height / total;
  out.velocity = vel / total;
  out.yaw_rate = yaw / total;
  return out;
}

Motion MapBlender::pose_at(const Eigen::Vector2d& p) const {
  return pose(locate(p));
}

Motion MapBlender::pose(const MapWeights& weights) const {
  const BlendedFrame b = blend(weights);
  Motion pose;
  pose.frame_time = m->frame_time;
  pose.resize(1, m->joints);
  pose.rotations = b.rotations;
  pose.translations = b.translations;
  return pose;
}

const Skeleton& MapBlender::skeleton() const {
  return m->skeleton;
}
const BlendOptions& MapBlender::options() const {
  return m->options;
}
int MapBlender::num_samples() const {
  return m->n;
}
int MapBlender::num_points() const {
  return m->num_points();
}
double MapBlender::frame_time() const {
  return m->frame_time;
}
int MapBlender::motion_root() const {
  return m->motion_root;
}
double MapBlender::median_step() const {
  return m->median_step;
}
double MapBlender::reach_distance() const {
  return m->reach_distance;
}
double MapBlender::median_speed() const {
  return m->median_speed;
}
Eigen::Vector2d MapBlender::sample_point(int i) const {
  if (i < 0 || i >= m->n) {
    throw ParameterError("sample " + std::to_string(i) + " is out of range [0, " +
                         std::to_string(m->n) + ")");
  }
  return m->sample_points[i];
}

}  // namespace motionmap::synth
