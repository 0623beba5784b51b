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

void check_joints(const char* what, int num_joints, int root, std::span<const int> joints,
                  const char* kind = "moving joint") {
  if (root < 0 || root >= num_joints) {
    throw ParameterError(std::string(what) + ": the motion root " + std::to_string(root) +
                         " is not a joint of " + std::to_string(num_joints));
  }
  for (const int j : joints) {
    if (j < 0 || j >= num_joints) {
      throw ParameterError(std::string(what) + ": the " + kind + " " + std::to_string(j) +
                           " is not a joint of " + std::to_string(num_joints));
    }
  }
}

}  // namespace

bool SampleState::finite() const {
  if (!std::isfinite(height) || !std::isfinite(yaw_rate) || !std::isfinite(heading_offset) ||
      !velocity.allFinite())
    return false;
  for (const Eigen::Quaterniond& q : rotations) {
    if (!q.coeffs().allFinite()) return false;
  }
  for (const Eigen::Vector3d& t : translations) {
    if (!t.allFinite()) return false;
  }
  return true;
}

RootTransform root_transform(const Motion& m, int f, int root, std::span<const int> ancestors) {
  const int J = m.num_joints;
  if (f < 0 || f >= m.num_frames) {
    throw ParameterError("root_transform: frame " + std::to_string(f) + " is out of range [0, " +
                         std::to_string(m.num_frames) + ")");
  }
  check_joints("root_transform", J, root, ancestors, "ancestor");
  if (ancestors.empty()) return {m.rotation(f, root), m.translation(f, root)};
  RootTransform out;
  for (const int j : ancestors) {
    out.translation += out.rotation * m.translation(f, j);
    out.rotation = (out.rotation * m.rotation(f, j).normalized()).normalized();
  }
  out.translation += out.rotation * m.translation(f, root);
  out.rotation = out.rotation * m.rotation(f, root);
  return out;
}

std::vector<int> root_ancestors(const Skeleton& skeleton, int root) {
  if (root < 0 || root >= skeleton.num_joints()) {
    throw ParameterError("root_ancestors: joint " + std::to_string(root) + " is not one of " +
                         std::to_string(skeleton.num_joints()));
  }
  std::vector<int> out;
  for (int j = skeleton.joints[root].parent; j >= 0; j = skeleton.joints[j].parent)
    out.insert(out.begin(), j);
  return out;
}

void fold_root(Motion& m, int f, int root, std::span<const int> ancestors) {
  const RootTransform t = root_transform(m, f, root, ancestors);
  for (const int j : ancestors) {
    m.rotation(f, j) = Eigen::Quaterniond::Identity();
    m.translation(f, j) = Eigen::Vector3d::Zero();
  }
  m.rotation(f, root) = t.rotation;
  m.translation(f, root) = t.translation;
}

void sample_state(const Motion& m, int f, int root, Axis up, std::span<const int> moving,
                  std::span<const int> ancestors, Eigen::Quaterniond* rotations,
                  Eigen::Vector3d* translations, double& height, Eigen::Vector3d& velocity,
                  double& yaw_rate, double& heading_offset) {
  const int J = m.num_joints;
  if (f < 0 || f >= m.num_frames) {
    throw ParameterError("sample_state: frame " + std::to_string(f) + " is out of range [0, " +
                         std::to_string(m.num_frames) + ")");
  }
  check_joints("sample_state", J, root, moving);
  check_joints("sample_state", J, root, ancestors, "ancestor");  // before they are written
  for (int j = 0; j < J; ++j) rotations[j] = m.rotation(f, j).normalized();
  for (const int j : ancestors) rotations[j] = Eigen::Quaterniond::Identity();
  const detail::RootSample r = detail::root_sample(m, f, root, up, ancestors);
  rotations[root] = r.tilt;
  height = r.height;
  velocity = r.velocity;
  yaw_rate = r.yaw_rate;
  heading_offset = r.heading_offset;
  for (std::size_t k = 0; k < moving.size(); ++k) translations[k] = m.translation(f, moving[k]);
}

SampleState sample_state(const Motion& m, int f, int root, Axis up, std::span<const int> moving,
                         std::span<const int> ancestors) {
  SampleState s;
  s.rotations.resize(static_cast<std::size_t>(std::max(m.num_joints, 0)));
  s.translations.resize(moving.size());
  sample_state(m, f, root, up, moving, ancestors, s.rotations.data(), s.translations.data(),
               s.height, s.velocity, s.yaw_rate, s.heading_offset);
  return s;
}

SampleState clip_sample_state(const Clip& clip, int frame, int root, Axis up,
                              std::span<const int> moving, std::span<const int> ancestors) {
  SampleState s = sample_state(clip.motion, frame, root, up, moving, ancestors);
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
                          std::span<const int> moving, int motion_root, Axis up,
                          std::span<const int> ancestors) {
  if (states.size() != weights.size() || states.empty()) {
    throw ParameterError("blend: " + std::to_string(states.size()) + " samples for " +
                         std::to_string(weights.size()) + " weights (need equal, non-zero counts)");
  }
  const std::size_t J = fixed_translations.size();
  check_joints("blend", static_cast<int>(J), motion_root, moving);
  check_joints("blend", static_cast<int>(J), motion_root, ancestors, "ancestor");
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
  double height = 0.0, yaw = 0.0, sway = 0.0;
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < count; ++k) {
    const SampleStateView& s = states[k];
    const double wk = weights[k];
    for (std::size_t k2 = 0; k2 < mv; ++k2) tsum[k2] += wk * s.translations[k2];
    height += wk * s.height;
    yaw += wk * s.yaw_rate;
    sway += wk * s.heading_offset;
    vel += wk * s.velocity;
  }
  out.translations.assign(fixed_translations.begin(), fixed_translations.end());
  for (std::size_t k = 0; k < mv; ++k) out.translations[moving[k]] = tsum[k] / total;
  Eigen::Vector3d& root = out.translations[static_cast<std::size_t>(motion_root)];
  root = Eigen::Vector3d::Zero();
  root[static_cast<int>(up)] = height / total;
  out.velocity = vel / total;
  out.yaw_rate = yaw / total;
  out.heading_offset = sway / total;
  for (const int j : ancestors) {
    out.rotations[static_cast<std::size_t>(j)] = Eigen::Quaterniond::Identity();
    out.translations[static_cast<std::size_t>(j)] = Eigen::Vector3d::Zero();
  }
  return out;
}

}  // namespace motionmap::synth
