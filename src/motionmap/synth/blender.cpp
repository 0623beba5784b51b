// MapBlender glues the pieces of synth/detail together: the map index (merged map points, k-d
// tree, reach), the kriging systems (global or local), the root motion of every sample, and the
// weighted blend of the samples' poses.
#include "motionmap/synth/blender.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/names.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/synth/detail/kriging.h"
#include "motionmap/synth/detail/map_index.h"
#include "motionmap/synth/detail/root_motion.h"

namespace motionmap::synth {

namespace {

// Local systems pick neighbours at least this fraction of the median step apart, so 120 fps
// samples almost on top of each other do not make them ill-conditioned.
constexpr double kSeparationFraction = 0.25;
// A distance below this fraction of the partition radius counts as a hit on the sample (the
// Franke–Little weight would overflow; the weights it replaces differ by < 1e-24).
constexpr double kHitFraction = 1e-12;
// Kriging queries are solved in blocks of this many points (bounds the right-hand-side memory).
constexpr int kKrigingBlock = 64;

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

// The constructor's checks of its arguments (see blender.h for what they reject).
void check_inputs(std::span<const Clip> clips, const features::FeatureSet& samples,
                  const Eigen::MatrixXd& coords, const BlendOptions& options) {
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
    check_clip(clip);
  }
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
}

}  // namespace

namespace {
constexpr EnumName<BlendMode> kBlendModes[] = {
    {BlendMode::Local, "local"}, {BlendMode::Kriging, "kriging"}, {BlendMode::Idw, "idw"}};
}  // namespace

std::string_view blend_mode_name(BlendMode mode) {
  return enum_name(kBlendModes, mode);
}

std::optional<BlendMode> parse_blend_mode(std::string_view name) {
  return parse_enum(kBlendModes, name);
}

const std::vector<BlendMode>& all_blend_modes() {
  static const std::vector<BlendMode> modes = enum_values(kBlendModes);
  return modes;
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

  // Per sample, precomputed so a query only sums.
  std::vector<Eigen::Quaterniond> rotations;  // #samples × #joints; the motion root's is its tilt
  std::vector<int> moving;  // joints other than the motion root whose translation varies
  std::vector<Eigen::Vector3d> moving_translations;  // #samples × moving.size()
  // #joints: sample 0's, the motion root's zeroed (its height is blended)
  std::vector<Eigen::Vector3d> fixed_translations;
  std::vector<double> height;
  std::vector<Eigen::Vector3d> velocity;  // heading-local floor velocity, units/s
  std::vector<double> yaw_rate;           // rad/s

  std::optional<detail::MapIndex> index;
  std::optional<detail::LocalKriging> local;     // local mode
  std::optional<detail::GlobalKriging> kriging;  // kriging mode

  void build_samples(std::span<const Clip> clips, const features::FeatureSet& samples);
  // Point weights (point index, weight) at v.point; sets v.variance. Not for kriging.
  void point_weights(PointValidity& v, std::vector<std::pair<int, double>>& out) const;
  // Kriging weights of the points out[c].validity.point, into out.
  void kriging_block(std::span<MapWeights> out) const;
};

void MapBlender::Impl::build_samples(std::span<const Clip> clips,
                                     const features::FeatureSet& samples) {
  const int J = joints;
  const auto uJ = static_cast<std::size_t>(J);
  motion_root = detail::shared_motion_root(clips);
  const int r = motion_root;

  const auto un = static_cast<std::size_t>(n);
  rotations.resize(un * uJ);
  height.resize(un);
  velocity.resize(un);
  yaw_rate.resize(un);
  for (int i = 0; i < n; ++i) {
    const Motion& m = clips[samples.clip_of[i]].motion;
    const int f = samples.frame_of[i];
    const auto row = static_cast<std::size_t>(i) * uJ;
    for (int j = 0; j < J; ++j)
      rotations[row + static_cast<std::size_t>(j)] = m.rotation(f, j).normalized();
    const detail::RootSample root = detail::root_sample(m, f, r, options.up);
    rotations[row + static_cast<std::size_t>(r)] = root.tilt;
    height[i] = root.height;
    velocity[i] = root.velocity;
    yaw_rate[i] = root.yaw_rate;
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

void MapBlender::Impl::point_weights(PointValidity& v,
                                     std::vector<std::pair<int, double>>& out) const {
  out.clear();
  const int np = index->num_points();
  const bool is_local = options.mode == BlendMode::Local;
  const int count = std::min(is_local ? kLocalPartitionSize : options.neighbors, np);
  std::vector<std::uint32_t> idx(static_cast<std::size_t>(count + 1));
  std::vector<double> dist(static_cast<std::size_t>(count + 1)),
      phi(static_cast<std::size_t>(count));
  const int found = index->nearest(v.point, count + 1, idx.data(), dist.data());
  // The partition radius: the next point's distance (a point leaving the set has weight 0);
  // with no next point, twice the farthest.
  const double R =
      found > count ? dist[count] : 2.0 * dist[found - 1] + std::numeric_limits<double>::min();
  partition_weights(dist.data(), count, R, phi.data());
  if (!is_local) {
    for (int i = 0; i < count; ++i) {
      if (phi[i] != 0.0) out.emplace_back(static_cast<int>(idx[i]), phi[i]);
    }
    v.variance = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  v.variance = 0.0;
  std::vector<double> rhs(static_cast<std::size_t>(local->max_hood() + 1)), sol(rhs.size());
  for (int i = 0; i < count; ++i) {
    if (phi[i] == 0.0) continue;
    const double var =
        local->predict(*index, static_cast<int>(idx[i]), v.point, phi[i], out, rhs, sol);
    v.variance += phi[i] * var;
  }
}

void MapBlender::Impl::kriging_block(std::span<MapWeights> out) const {
  const std::size_t m = out.size();
  std::vector<Eigen::Vector2d> queries(m);
  for (std::size_t c = 0; c < m; ++c) queries[c] = out[c].validity.point;
  std::vector<double> variance(m);
  const Eigen::MatrixXd x = kriging->solve(queries, variance);
  std::vector<double> dense(static_cast<std::size_t>(n));
  for (std::size_t c = 0; c < m; ++c) {
    MapWeights& w = out[c];
    w.validity.variance = variance[c];
    std::fill(dense.begin(), dense.end(), 0.0);
    index->to_sample_weights(x.col(static_cast<Eigen::Index>(c)).data(), dense.data());
    w.samples.resize(static_cast<std::size_t>(n));
    w.weights = dense;
    for (int s = 0; s < n; ++s) w.samples[s] = s;
  }
}

MapBlender::MapBlender(std::span<const Clip> clips, const features::FeatureSet& samples,
                       const Eigen::MatrixXd& coords, const BlendOptions& options,
                       const Control& control)
    : m(std::make_unique<Impl>()) {
  check_inputs(clips, samples, coords, options);
  const int n = samples.num_samples();
  const Skeleton& skeleton = clips.front().skeleton;
  Impl& s = *m;
  s.options = options;
  s.skeleton = skeleton;
  s.frame_time = clips.front().motion.frame_time;
  s.joints = skeleton.num_joints();
  s.n = n;
  s.build_samples(clips, samples);
  std::vector<Eigen::Vector2d> points(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) points[i] = Eigen::Vector2d(coords(i, 0), coords(i, 1));
  s.index.emplace(clips, samples, std::move(points), options.reach);

  if (options.mode == BlendMode::Local) {
    s.local.emplace(*s.index, options.neighbors, kSeparationFraction * s.index->median_step(),
                    control.stage("kriging set-up", 0.0, 1.0));
  } else if (options.mode == BlendMode::Kriging) {
    const int np = s.index->num_points();
    if (np > kMaxKrigingSamples) {
      throw ParameterError("blend: kriging over " + std::to_string(np) +
                           " distinct map points exceeds the limit of " +
                           std::to_string(kMaxKrigingSamples) +
                           " (a dense (N+1)² system); use the local mode or a frame stride");
    }
    s.kriging.emplace(s.index->points(), control.stage("kriging set-up", 0.0, 1.0));
  } else {
    control.check();
  }
}

MapBlender::~MapBlender() = default;
MapBlender::MapBlender(MapBlender&&) noexcept = default;
MapBlender& MapBlender::operator=(MapBlender&&) noexcept = default;

MapWeights MapBlender::locate(const Eigen::Vector2d& p) const {
  if (m->options.mode == BlendMode::Kriging)
    return std::move(locate(std::span<const Eigen::Vector2d>(&p, 1)).front());
  PointValidity v = m->index->validate(p);
  std::vector<std::pair<int, double>> pw;
  m->point_weights(v, pw);
  return m->index->to_sample_weights(pw, v);
}

std::vector<MapWeights> MapBlender::locate(std::span<const Eigen::Vector2d> pts) const {
  std::vector<MapWeights> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) out[i].validity = m->index->validate(pts[i]);
  if (m->options.mode != BlendMode::Kriging) {
    std::vector<std::pair<int, double>> pw;
    for (auto& w : out) {
      PointValidity v = w.validity;
      m->point_weights(v, pw);
      w = m->index->to_sample_weights(pw, v);
    }
    return out;
  }
  for (std::size_t b = 0; b < pts.size(); b += kKrigingBlock) {
    const std::size_t e = std::min(pts.size(), b + kKrigingBlock);
    m->kriging_block(std::span<MapWeights>(out).subspan(b, e - b));
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
  const std::size_t count = w.samples.size();
  BlendedFrame out;
  // Rotations: per joint, the weighted average aligned to the largest-weight sample's.
  const Eigen::Quaterniond* qref =
      s.rotations.data() + static_cast<std::size_t>(w.samples[ref]) * J;
  std::vector<Eigen::Quaterniond> q(count);
  out.rotations.resize(J);
  for (std::size_t j = 0; j < J; ++j) {
    for (std::size_t k = 0; k < count; ++k)
      q[k] = s.rotations[static_cast<std::size_t>(w.samples[k]) * J + j];
    out.rotations[j] = weighted_average(q, w.weights, qref[j]);
  }
  // A blend of heading-free tilts can keep a trace of heading: remove it, so the pose faces
  // heading 0 exactly (a no-op at samples).
  Eigen::Quaterniond& tilt = out.rotations[static_cast<std::size_t>(s.motion_root)];
  tilt = detail::remove_heading(tilt, s.options.up);

  // Translations, height and root motion: weighted sums.
  const std::size_t mv = s.moving.size();
  std::vector<Eigen::Vector3d> tsum(mv, Eigen::Vector3d::Zero());
  double height = 0.0, yaw = 0.0;
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < count; ++k) {
    const auto i = static_cast<std::size_t>(w.samples[k]);
    const double wk = w.weights[k];
    const Eigen::Vector3d* t = s.moving_translations.data() + i * mv;
    for (std::size_t k2 = 0; k2 < mv; ++k2) tsum[k2] += wk * t[k2];
    height += wk * s.height[i];
    yaw += wk * s.yaw_rate[i];
    vel += wk * s.velocity[i];
  }
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

Motion MapBlender::pose(const MapWeights& weights, const RootPlacement& placement) const {
  Motion out = pose(weights);
  place_root(out, m->motion_root, placement, m->options.up);
  return out;
}

void place_root(Motion& pose, int root, const RootPlacement& placement, Axis up) {
  if (!std::isfinite(placement.heading) || !placement.floor.allFinite())
    throw ParameterError("place_root: the root placement is not finite");
  if (pose.num_frames < 1 || root < 0 || root >= pose.num_joints) {
    throw ParameterError("place_root: joint " + std::to_string(root) + " of a pose of " +
                         std::to_string(pose.num_frames) + " frames and " +
                         std::to_string(pose.num_joints) + " joints");
  }
  const int u = static_cast<int>(up);
  // The pose faces heading 0 (its root's tilt has no heading), so turning it by the placement's
  // heading gives exactly that heading.
  Eigen::Quaterniond& q = pose.rotation(0, root);
  q = (axis_rotation(up, placement.heading) * q).normalized();
  Eigen::Vector3d& t = pose.translation(0, root);
  const double height = t[u];
  t = placement.floor;
  t[u] = height;
}

RootPlacement root_placement(const Motion& motion, int frame, int root, Axis up) {
  if (frame < 0 || frame >= motion.num_frames || root < 0 || root >= motion.num_joints) {
    throw ParameterError("root_placement: frame " + std::to_string(frame) + " or joint " +
                         std::to_string(root) + " is out of range (" +
                         std::to_string(motion.num_frames) + " frames, " +
                         std::to_string(motion.num_joints) + " joints)");
  }
  RootPlacement p;
  p.heading = features::heading_angle(motion.rotation(frame, root).normalized(), up);
  p.floor = motion.translation(frame, root);
  p.floor[static_cast<int>(up)] = 0.0;
  return p;
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
  return m->index->num_points();
}
double MapBlender::frame_time() const {
  return m->frame_time;
}
int MapBlender::motion_root() const {
  return m->motion_root;
}
double MapBlender::median_step() const {
  return m->index->median_step();
}
double MapBlender::reach_distance() const {
  return m->index->reach_distance();
}
double MapBlender::median_speed() const {
  return m->index->median_speed();
}
Eigen::Vector2d MapBlender::sample_point(int i) const {
  if (i < 0 || i >= m->n) {
    throw ParameterError("sample " + std::to_string(i) + " is out of range [0, " +
                         std::to_string(m->n) + ")");
  }
  return m->index->sample_point(i);
}

}  // namespace motionmap::synth
