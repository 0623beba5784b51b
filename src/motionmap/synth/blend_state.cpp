// One definition of the blend's arithmetic (blend_state.h): MapBlender's two ways of keeping
// sample states and SavedMap::pose_at all blend through blend_states().
#include "motionmap/synth/blend_state.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/synth/detail/root_motion.h"

namespace motionmap::synth {

namespace {

void check_joints(const char* what, int num_joints, int root, std::span<const int> moving) {
  if (root < 0 || root >= num_joints) {
    throw ParameterError(std::string(what) + ": the motion root " + std::to_string(root) +
                         " is not a joint of " + std::to_string(num_joints));
  }
  for (const int j : moving) {
    if (j < 0 || j >= num_joints) {
      throw ParameterError(std::string(what) + ": the moving joint " + std::to_string(j) +
                           " is not a joint of " + std::to_string(num_joints));
    }
  }
}

}  // namespace

bool SampleState::finite() const {
  if (!std::isfinite(height) || !std::isfinite(yaw_rate) || !velocity.allFinite()) return false;
  for (const Eigen::Quaterniond& q : rotations) {
    if (!q.coeffs().allFinite()) return false;
  }
  for (const Eigen::Vector3d& t : translations) {
    if (!t.allFinite()) return false;
  }
  return true;
}

void sample_state(const Motion& m, int f, int root, Axis up, std::span<const int> moving,
                  Eigen::Quaterniond* rotations, Eigen::Vector3d* translations, double& height,
                  Eigen::Vector3d& velocity, double& yaw_rate) {
  const int J = m.num_joints;
  if (f < 0 || f >= m.num_frames) {
    throw ParameterError("sample_state: frame " + std::to_string(f) + " is out of range [0, " +
                         std::to_string(m.num_frames) + ")");
  }
  check_joints("sample_state", J, root, moving);
  for (int j = 0; j < J; ++j) rotations[j] = m.rotation(f, j).normalized();
  const detail::RootSample r = detail::root_sample(m, f, root, up);
  rotations[root] = r.tilt;
  height = r.height;
  velocity = r.velocity;
  yaw_rate = r.yaw_rate;
  for (std::size_t k = 0; k < moving.size(); ++k) translations[k] = m.translation(f, moving[k]);
}

SampleState sample_state(const Motion& m, int f, int root, Axis up, std::span<const int> moving) {
  SampleState s;
  s.rotations.resize(static_cast<std::size_t>(std::max(m.num_joints, 0)));
  s.translations.resize(moving.size());
  sample_state(m, f, root, up, moving, s.rotations.data(), s.translations.data(), s.height,
               s.velocity, s.yaw_rate);
  return s;
}

SampleState clip_sample_state(const Clip& clip, int frame, int root, Axis up,
                              std::span<const int> moving) {
  SampleState s = sample_state(clip.motion, frame, root, up, moving);
  // The values blended must be finite (a blender given the clips checks every frame).
  if (!s.finite()) {
    throw NumericalError(clip.path + ": frame " + std::to_string(frame) +
                         " (or the next) holds a NaN or infinite value");
  }
  return s;
}

void check_blend_joints(int motion_root, std::span<const int> moving, int joints,
                        const std::string& named_by, const std::string& clip_path) {
  if (motion_root < 0 || motion_root >= joints) {
    throw ParameterError(named_by + " names joint " + std::to_string(motion_root) +
                         " as the motion root, but " + clip_path + " has " +
                         std::to_string(joints) + " joints");
  }
  for (std::size_t k = 0; k < moving.size(); ++k) {
    const int j = moving[k];
    if (j < 0 || j >= joints || j == motion_root || (k > 0 && j <= moving[k - 1])) {
      throw ParameterError(named_by + " lists joint " + std::to_string(j) +
                           " as moving; expected increasing joints of " + clip_path +
                           " other than the motion root");
    }
  }
}

BlendedFrame blend_states(std::span<const SampleStateView> states, std::span<const double> weights,
                          std::span<const Eigen::Vector3d> fixed_translations,
                          std::span<const int> moving, int motion_root, Axis up) {
  if (states.size() != weights.size() || states.empty()) {
    throw ParameterError("blend: " + std::to_string(states.size()) + " samples for " +
                         std::to_string(weights.size()) + " weights (need equal, non-zero counts)");
  }
  const std::size_t J = fixed_translations.size();
  check_joints("blend", static_cast<int>(J), motion_root, moving);
  std::size_t ref = 0;
  double total = 0.0;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    if (!std::isfinite(weights[k]))
      throw ParameterError("blend: weight " + std::to_string(k) + " is not finite");
    if (weights[k] > weights[ref]) ref = k;
    total += weights[k];
  }
  if (!(std::abs(total) > 1e-12))
    throw ParameterError("blend: the weights sum to " + format_number(total) + ", not about 1");

  const std::size_t count = states.size();
  const std::size_t mv = moving.size();
  BlendedFrame out;
  // Rotations: per joint, the weighted average aligned to the largest-weight sample's.
  const Eigen::Quaterniond* qref = states[ref].rotations;
  std::vector<Eigen::Quaterniond> q(count);
  out.rotations.resize(J);
  for (std::size_t j = 0; j < J; ++j) {
    for (std::size_t k = 0; k < count; ++k) q[k] = states[k].rotations[j];
    out.rotations[j] = weighted_average(q, weights, qref[j]);
  }
  // A blend of heading-free tilts can keep a trace of heading: remove it, so the pose faces
  // heading 0 exactly (a no-op at samples).
  Eigen::Quaterniond& tilt = out.rotations[static_cast<std::size_t>(motion_root)];
  tilt = detail::remove_heading(tilt, up);

  // Translations, height and root motion: weighted sums.
  std::vector<Eigen::Vector3d> tsum(mv, Eigen::Vector3d::Zero());
  double height = 0.0, yaw = 0.0;
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < count; ++k) {
    const SampleStateView& s = states[k];
    const double wk = weights[k];
    for (std::size_t k2 = 0; k2 < mv; ++k2) tsum[k2] += wk * s.translations[k2];
    height += wk * s.height;
    yaw += wk * s.yaw_rate;
    vel += wk * s.velocity;
  }
  out.translations.assign(fixed_translations.begin(), fixed_translations.end());
  for (std::size_t k = 0; k < mv; ++k) out.translations[moving[k]] = tsum[k] / total;
  Eigen::Vector3d& root = out.translations[static_cast<std::size_t>(motion_root)];
  root = Eigen::Vector3d::Zero();
  root[static_cast<int>(up)] = height / total;
  out.velocity = vel / total;
  out.yaw_rate = yaw / total;
  return out;
}

}  // namespace motionmap::synth
