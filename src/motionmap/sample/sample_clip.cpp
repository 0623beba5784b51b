#include "motionmap/sample/sample_clip.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <string>
#include <tuple>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/text_cursor.h"

namespace motionmap::sample {

namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// Joint indices of cmu_like_skeleton(), in the order of CMU's BVH files.
// clang-format off
enum JointIndex : int {
  kHips, kLHipJoint, kLeftUpLeg, kLeftLeg, kLeftFoot, kLeftToeBase,
  kRHipJoint, kRightUpLeg, kRightLeg, kRightFoot, kRightToeBase,
  kLowerBack, kSpine, kSpine1, kNeck, kNeck1, kHead,
  kLeftShoulder, kLeftArm, kLeftForeArm, kLeftHand, kLeftFingerBase, kLeftHandIndex1, kLThumb,
  kRightShoulder, kRightArm, kRightForeArm, kRightHand, kRightFingerBase, kRightHandIndex1, kRThumb,
  kNumJoints
};
// clang-format on

// Proportions (cm): hips 95 high, hip joints 90, knees 48, ankles 8, shoulders 143, head top 172.
constexpr double kHipsHeight = 95.0;
const Vector3d kLeftHipOffset(9.0, -5.0, 0.0);
const Vector3d kThigh(0.0, -42.0, 0.0);
const Vector3d kShin(0.0, -40.0, 0.0);
const Vector3d kFootToBall(0.0, -6.0, 13.0);  // ankle to the ball of the foot (LeftToeBase)
const Vector3d kFootToHeel(0.0, -8.0, -5.0);  // ankle to the back of the heel (not a joint)
constexpr double kAnkleHeight = 8.0;
const Vector3d kLeftShoulderOffset(17.0, 13.0, -2.0);
const Vector3d kUpperArm(32.0, 0.0, 0.0);
const Vector3d kForearm(26.0, 0.0, 0.0);

Vector3d mirror_x(const Vector3d& v) {
  return {-v.x(), v.y(), v.z()};
}

double deg(double degrees) {
  return deg_to_rad(degrees);
}

Quaterniond rot(Axis axis, double degrees) {
  return axis_rotation(axis, deg(degrees));
}

// R = R(axes[0], a0)·R(axes[1], a1)·R(axes[2], a2), angles in degrees.
Quaterniond euler_deg(const std::array<Axis, 3>& axes, double a0, double a1, double a2) {
  const std::array<double, 3> radians{deg(a0), deg(a1), deg(a2)};
  return euler_to_quat(axes, radians);
}

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// Cubic Hermite on [0, 1] between values with end slopes (per unit of s).
double hermite(double p0, double m0, double p1, double m1, double s) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * m1;
}

// Smooth deterministic "natural variation": a sum of incommensurate sines, a different phase per
// channel, amplitude ≈ 1. C∞, so it never spoils the clip's smoothness.
double wobble(int channel, double t) {
  constexpr std::array<double, 3> kHz{0.31, 0.77, 1.43};
  constexpr std::array<double, 3> kAmp{0.6, 0.3, 0.15};
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double phase = std::fmod(0.6180339887 * channel + 0.4142135624 * i, 1.0);
    sum += kAmp[i] * std::sin(2.0 * kPi * (kHz[i] * t + phase));
  }
  return sum;
}

// A keyframed scalar: monotone piecewise-cubic (Fritsch–Carlson) interpolation, C1, no overshoot,
// zero slope at the first/last key and wherever the keys turn (so repeated keys hold still).
class Track {
 public:
  Track(const std::vector<double>& times, std::initializer_list<double> values)
      : Track(times, std::vector<double>(values)) {}
  Track(const std::vector<double>& times, const std::vector<double>& values)
      : m_t(times), m_v(values), m_m(m_t.size(), 0.0) {
    const std::size_t n = std::min(m_t.size(), m_v.size());
    for (std::size_t k = 1; k + 1 < n; ++k) {
      const double h0 = m_t[k] - m_t[k - 1], h1 = m_t[k + 1] - m_t[k];
      const double d0 = (m_v[k] - m_v[k - 1]) / h0, d1 = (m_v[k + 1] - m_v[k]) / h1;
      if (d0 * d1 <= 0.0) continue;
      const double w0 = 2.0 * h1 + h0, w1 = h1 + 2.0 * h0;
      m_m[k] = (w0 + w1) / (w0 / d0 + w1 / d1);
    }
  }

  double operator()(double t) const {
    if (t <= m_t.front()) return m_v.front();
    if (t >= m_t.back()) return m_v.back();
    const auto k =
        static_cast<std::size_t>(std::upper_bound(m_t.begin(), m_t.end(), t) - m_t.begin() - 1);
    const double h = m_t[k + 1] - m_t[k];
    return hermite(m_v[k], m_m[k] * h, m_v[k + 1], m_m[k + 1] * h, (t - m_t[k]) / h);
  }

 private:
  std::vector<double> m_t, m_v, m_m;
};

// One frame under construction: local rotations set parent-first, world transforms kept up to
// date, so inverse kinematics can ask where a joint's parent ended up.
class PoseBuilder {
 public:
  explicit PoseBuilder(const Skeleton& skeleton)
      : m_skeleton(skeleton),
        m_local(kNumJoints, Quaterniond::Identity()),
        m_world_rot(kNumJoints, Quaterniond::Identity()),
        m_world_pos(kNumJoints, Vector3d::Zero()) {}

  void set_root(const Vector3d& position, const Quaterniond& rotation) {
    m_root_position = position;
    m_local[kHips] = rotation.normalized();
    m_world_rot[kHips] = m_local[kHips];
    m_world_pos[kHips] = position;
  }

  void set(int joint, const Quaterniond& local) {
    const int parent = m_skeleton.joints[joint].parent;
    m_local[joint] = local.normalized();
    m_world_pos[joint] = position_of(joint);
    m_world_rot[joint] = (m_world_rot[parent] * m_local[joint]).normalized();
  }

  // Sets `joint` so that its world rotation is `world`.
  void set_world(int joint, const Quaterniond& world) {
    set(joint, m_world_rot[m_skeleton.joints[joint].parent].conjugate() * world);
  }

  // World position of `joint`: depends only on its ancestors, so it is known before it is set.
  Vector3d position_of(int joint) const {
    const Joint& j = m_skeleton.joints[joint];
    if (j.parent < 0) return m_root_position;
    return m_world_pos[j.parent] + m_world_rot[j.parent] * j.offset;
  }

  const Quaterniond& world_rotation(int joint) const { return m_world_rot[joint]; }

  // Writes the frame into `motion`, each quaternion in the hemisphere of the previous frame's.
  void store(Motion& motion, int frame) const {
    for (int j = 0; j < kNumJoints; ++j) {
      const Quaterniond reference =
          frame > 0 ? motion.rotation(frame - 1, j) : Quaterniond::Identity();
      motion.rotation(frame, j) = align_hemisphere(m_local[j], reference);
      motion.translation(frame, j) = j == kHips ? m_root_position : m_skeleton.joints[j].offset;
    }
  }

 private:
  const Skeleton& m_skeleton;
  Vector3d m_root_position = Vector3d::Zero();
  std::vector<Quaterniond> m_local, m_world_rot;
  std::vector<Vector3d> m_world_pos;
};

// A two-bone limb solved analytically: the end joint reaches `target` (or as near as the limb
// allows, with a soft limit so nothing snaps), the middle joint bends towards `pole` and is a pure
// hinge. Local frames: the bone lies along `bone_axis`; the lower bone bends towards `bend_axis`,
// a rotation about `hinge` (bone_axis × bend_axis = hinge_sign · hinge).
struct LimbSpec {
  int upper, middle, end;
  Vector3d bone_axis, bend_axis;
  Axis hinge;
  double hinge_sign;
};

// clang-format off
const LimbSpec kLeftLegLimb {kLeftUpLeg,  kLeftLeg,      kLeftFoot,  {0, -1, 0}, {0, 0, -1}, Axis::X,  1.0};
const LimbSpec kRightLegLimb{kRightUpLeg, kRightLeg,     kRightFoot, {0, -1, 0}, {0, 0, -1}, Axis::X,  1.0};
const LimbSpec kLeftArmLimb {kLeftArm,    kLeftForeArm,  kLeftHand,  {1, 0, 0},  {0, 0, 1},  Axis::Y, -1.0};
const LimbSpec kRightArmLimb{kRightArm,   kRightForeArm, kRightHand, {-1, 0, 0}, {0, 0, 1},  Axis::Y,  1.0};
// clang-format on

// Rotation taking the orthonormal pair (a, b) to (a2, b2).
Quaterniond frame_rotation(const Vector3d& a, const Vector3d& b, const Vector3d& a2,
                           const Vector3d& b2) {
  Matrix3d from, to;
  from << a, b, a.cross(b);
  to << a2, b2, a2.cross(b2);
  return Quaterniond(Matrix3d(to * from.transpose())).normalized();
}

// Unit vector of v's component perpendicular to unit u (or any perpendicular if v ∥ u).
Vector3d perpendicular(const Vector3d& v, const Vector3d& u) {
  Vector3d p = v - v.dot(u) * u;
  if (p.norm() < 1e-9) p = u.unitOrthogonal();
  return p.normalized();
}

void solve_limb(PoseBuilder& pose, const Skeleton& skeleton, const LimbSpec& limb,
                const Vector3d& target, const Vector3d& pole) {
  const double l1 = skeleton.joints[limb.middle].offset.norm();
  const double l2 = skeleton.joints[limb.end].offset.norm();
  const Vector3d p = pose.position_of(limb.upper);
  const Vector3d to_target = target - p;
  const Vector3d u =
      to_target.norm() > 1e-9 ? Vector3d(to_target.normalized()) : Vector3d(0, -1, 0);
  // Soft reach limit: unchanged up to 99 % of the limb length, then easing towards 99.9 %.
  const double soft = 0.99 * (l1 + l2), hard = 0.999 * (l1 + l2);
  double d = std::max(to_target.norm(), std::abs(l1 - l2) + 1.0);
  if (d > soft) d = soft + (hard - soft) * std::tanh((d - soft) / (hard - soft));
  const double along = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
  const double out = std::sqrt(std::max(0.0, l1 * l1 - along * along));
  const Vector3d toward_pole = perpendicular(pole, u);
  const Vector3d middle = p + along * u + out * toward_pole;
  const Vector3d t1 = (middle - p).normalized();
  const Vector3d t2 = (p + d * u - middle).normalized();
  // The lower bone bends away from the pole side of the upper bone.
  const Vector3d bend = perpendicular(-toward_pole, t1);
  pose.set_world(limb.upper, frame_rotation(limb.bone_axis, limb.bend_axis, t1, bend));
  const double angle = std::acos(std::clamp(t1.dot(t2), -1.0, 1.0));
  pose.set(limb.middle, axis_rotation(limb.hinge, limb.hinge_sign * angle));
}

// Sets Neck1 and Head (half each) so that the head's world rotation is `head_world`.
void set_head(PoseBuilder& pose, const Quaterniond& head_world) {
  pose.set(kNeck, Quaterniond::Identity());
  const Quaterniond total = pose.world_rotation(kNeck).conjugate() * head_world;
  const Quaterniond half = Quaterniond::Identity().slerp(0.5, total);
  pose.set(kNeck1, half);
  pose.set(kHead, half);
}

// Spreads a trunk rotation over LowerBack, Spine and Spine1 (30/35/35 %), degrees.
void set_spine(PoseBuilder& pose, double twist, double bend, double side) {
  constexpr std::array<int, 3> kJoints{kLowerBack, kSpine, kSpine1};
  constexpr std::array<double, 3> kShare{0.30, 0.35, 0.35};
  for (int i = 0; i < 3; ++i) {
    pose.set(kJoints[i], euler_deg({Axis::Y, Axis::X, Axis::Z}, kShare[i] * twist, kShare[i] * bend,
                                   kShare[i] * side));
  }
}

// Where the ankle is when a foot rotated to `foot_world` rests on its point `pivot_local` (relative
// to the ankle, in the foot's frame) at `pivot_world`: rolling over the heel or the ball.
Vector3d ankle_for_pivot(const Quaterniond& foot_world, const Vector3d& pivot_local,
                         const Vector3d& pivot_world) {
  return pivot_world - foot_world * pivot_local;
}

// Fingers and thumbs: a relaxed, slightly curled hand (the sample has no finger motion).
void set_hands_rest(PoseBuilder& pose, double curl) {
  pose.set(kLeftFingerBase, rot(Axis::Z, -curl));
  pose.set(kLeftHandIndex1, rot(Axis::Z, -curl));
  pose.set(kLThumb, rot(Axis::Y, 10.0));
  pose.set(kRightFingerBase, rot(Axis::Z, curl));
  pose.set(kRightHandIndex1, rot(Axis::Z, curl));
  pose.set(kRThumb, rot(Axis::Y, -10.0));
}

// ---------------------------------------------------------------------------------------------
// Golf swing. Keys are in the natural 4 s timeline; world: the golfer faces +Z, target on +X.

constexpr double kSwingSeconds = 4.0;

// clang-format off
struct SwingTracks {
  std::vector<double> t{0.00, 0.55, 0.85, 1.20, 1.55, 1.80, 1.95,
                        2.15, 2.30, 2.45, 2.65, 2.85, 3.02, 4.00};
  //                    addr  addr  take  mid   3/4   top   top   down  impact fol  3/4   high  fin   hold
  Track pelvis_yaw{t,   {0,    0,    -12,  -28,  -40,  -45,  -46,  -25,  30,   55,   72,   82,   86,   86}};
  Track pelvis_tilt{t,  {30,   30,   30,   30,   31,   31,   31,   31,   29,   24,   16,   10,   8,    8}};
  Track root_x{t,       {0,    0,    -1.5, -2.5, -3,   -3,   -2.5, 1,    4,    6,    7,    7.5,  7.5,  7.5}};
  Track root_y{t,       {91,   91,   91,   91,   91,   91,   91,   90.5, 90.5, 91,   92,   92.5, 92.5, 92.5}};
  Track root_z{t,       {-9,   -9,   -9,   -9,   -8.5, -8.5, -8.5, -8,   -7,   -5,   -3,   -2,   -2,   -2}};
  Track spine_twist{t,  {0,    0,    -12,  -30,  -44,  -50,  -50,  -24,  -5,   12,   22,   28,   30,   30}};
  Track spine_bend{t,   {12,   12,   12,   12,   12,   12,   12,   12,   13,   10,   5,    -2,   -5,   -5}};
  Track spine_side{t,   {10,   10,   9,    7,    5,    5,    5,    12,   20,   20,   14,   8,    6,    6}};
  Track head_yaw{t,     {0,    0,    -5,   -10,  -15,  -18,  -18,  -10,  0,    20,   50,   75,   82,   82}};
  Track head_pitch{t,   {52,   52,   52,   52,   52,   52,   52,   52,   52,   45,   30,   15,   8,    8}};
  // Hands: elbow flexion of each arm (which fixes how far each wrist is from its shoulder) and
  // where the hands are around the shoulder line, degrees (0: straight out of the chest,
  // -90: down along the spine, +90: up).
  Track lead_flex{t,    {12,   12,   10,   10,   12,   15,   15,   12,   8,    25,   70,   100,  110,  110}};
  Track trail_flex{t,   {20,   20,   30,   55,   85,   100,  100,  80,   25,   8,    12,   30,   45,   45}};
  Track hands_angle{t,  {-48,  -48,  -45,  0,    40,   85,   87,   0,    -48,  -30,  15,   55,   75,   75}};
  // Elbows point down and this far out of the chest (> 0) or back towards it (< 0).
  Track lead_elbow{t,   {-0.3, -0.3, -0.3, -0.2, 0,    0,    0,    0,    -0.3, -0.1, 0.4,  1.0,  1.2,  1.2}};
  Track trail_elbow{t,  {-0.6, -0.6, -0.5, 0,    0.3,  0.5,  0.5,  0.2,  -0.6, 0,    0.3,  0.8,  1.0,  1.0}};
  // Trail (right) foot rolls onto its ball and turns towards the target after impact.
  Track trail_heel{t,   {0,    0,    0,    0,    0,    0,    0,    0,    5,    20,   35,   42,   45,   45}};
  Track trail_yaw{t,    {-5,   -5,   -5,   -5,   -5,   -5,   -5,   -5,   -5,   5,    15,   25,   30,   30}};
  // Club shaft (from the hands towards the head), world; keys less than 90° apart, with two more
  // keys where it turns fastest (cocking halfway to the top, releasing before impact).
  std::vector<double> ts{0.00, 0.55, 0.85, 1.03, 1.20, 1.55, 1.80, 1.95,
                         2.15, 2.23, 2.30, 2.45, 2.65, 2.85, 3.02, 4.00};
  Track shaft_x{ts, {0.05, 0.05, -0.9, -0.75, -0.1, 0.45, 0.95, 0.95, -0.1, -0.8, -0.1, 0.9,  0.3,  -0.3, -0.5, -0.5}};
  Track shaft_y{ts, {-0.83,-0.83,-0.3, 0.6,   0.85, 0.7,  0.15, 0.15, 0.9,  0.05, -0.83,-0.2, 0.9,  0.6,  -0.4, -0.4}};
  Track shaft_z{ts, {0.55, 0.55, 0.3,  -0.1,  -0.5, -0.55,-0.25,-0.25,-0.4, 0.6,  0.55, 0.4,  0.3,  -0.7, -0.75,-0.75}};
};
// clang-format on

// Shoulder-to-wrist distance for an elbow flexion in degrees.
double arm_reach(double flex) {
  const double l1 = kUpperArm.norm(), l2 = kForearm.norm();
  return std::sqrt(l1 * l1 + l2 * l2 + 2.0 * l1 * l2 * std::cos(deg(flex)));
}

// The point at distance ra from a and rb from b (a circle of them) in the direction `hint` from
// the circle's centre. Clamped to the nearest point when the spheres do not meet.
Vector3d grip_point(const Vector3d& a, double ra, const Vector3d& b, double rb,
                    const Vector3d& hint) {
  const Vector3d ab = b - a;
  const double d = std::max(ab.norm(), 1e-9);
  const Vector3d n = ab / d;
  const double x = std::clamp((d * d + ra * ra - rb * rb) / (2.0 * d), -ra, ra);
  const double radius = std::sqrt(std::max(0.0, ra * ra - x * x));
  return a + x * n + radius * perpendicular(hint, n);
}

constexpr double kStanceHalfWidth = 20.0;  // ankles at x = ±20 cm
constexpr double kLeadToeOut = 10.0;       // degrees
constexpr double kGripSpacing = 8.0;       // cm between the wrists along the shaft

void swing_pose(const SwingTracks& k, const Skeleton& skeleton, double t, PoseBuilder& pose) {
  // Pseudo-noise: tenths of a degree / millimetres, plus slow breathing in the spine.
  auto n = [t](int channel, double amplitude) { return amplitude * wobble(channel, t); };
  const double breath = 0.4 * std::sin(2.0 * kPi * 0.25 * t);

  const Vector3d root(k.root_x(t) + n(1, 0.15), k.root_y(t) + n(2, 0.1), k.root_z(t) + n(3, 0.15));
  pose.set_root(root, euler_deg({Axis::Y, Axis::X, Axis::Z}, k.pelvis_yaw(t) + n(4, 0.4),
                                k.pelvis_tilt(t) + n(5, 0.3), n(6, 0.3)));
  pose.set(kLHipJoint, Quaterniond::Identity());
  pose.set(kRHipJoint, Quaterniond::Identity());

  // Feet: the lead foot flat; the trail foot pivots about its ball.
  const Quaterniond lead_foot = rot(Axis::Y, kLeadToeOut);
  const Vector3d lead_ankle(kStanceHalfWidth, kAnkleHeight, 0.0);
  const Quaterniond trail_rest = rot(Axis::Y, -5.0);
  const Vector3d trail_ball =
      Vector3d(-kStanceHalfWidth, kAnkleHeight, 0.0) + trail_rest * kFootToBall;
  const double heel = k.trail_heel(t);
  const Quaterniond trail_foot = rot(Axis::Y, k.trail_yaw(t)) * rot(Axis::X, heel);
  const Vector3d trail_ankle = ankle_for_pivot(trail_foot, kFootToBall, trail_ball);
  // Knees point over the toes, pulled a little towards where the pelvis faces.
  const Quaterniond pelvis_yaw = rot(Axis::Y, k.pelvis_yaw(t));
  const Vector3d pelvis_forward = pelvis_yaw * Vector3d::UnitZ();
  solve_limb(pose, skeleton, kLeftLegLimb, lead_ankle,
             (lead_foot * Vector3d::UnitZ() + 0.5 * pelvis_forward).normalized());
  pose.set_world(kLeftFoot, lead_foot);
  pose.set(kLeftToeBase, Quaterniond::Identity());
  solve_limb(pose, skeleton, kRightLegLimb, trail_ankle,
             (trail_foot * Vector3d::UnitZ() + 0.5 * pelvis_forward).normalized());
  pose.set_world(kRightFoot, trail_foot);
  pose.set(kRightToeBase, rot(Axis::X, -heel));

  set_spine(pose, k.spine_twist(t) + n(7, 0.4), k.spine_bend(t) + breath + n(8, 0.3),
            k.spine_side(t) + n(9, 0.3));
  set_head(pose, euler_deg({Axis::Y, Axis::X, Axis::Z}, k.head_yaw(t) + n(10, 0.6),
                           k.head_pitch(t) + n(11, 0.5), n(12, 0.4)));

  // Arms: each wrist at the distance from its shoulder that the keyed elbow flexion gives, the
  // trail wrist kGripSpacing further down the shaft than the lead one: the lead wrist lies on the
  // circle where two spheres meet, at the keyed angle around the shoulder line.
  pose.set(kLeftShoulder, Quaterniond::Identity());
  pose.set(kRightShoulder, Quaterniond::Identity());
  const Quaterniond chest = pose.world_rotation(kSpine1);
  const Vector3d shaft = Vector3d(k.shaft_x(t), k.shaft_y(t), k.shaft_z(t)).normalized();
  const double angle = deg(k.hands_angle(t) + n(13, 0.5));
  const Vector3d lead_wrist = grip_point(
      pose.position_of(kLeftArm), arm_reach(k.lead_flex(t) + n(14, 0.5)),
      pose.position_of(kRightArm) - kGripSpacing * shaft, arm_reach(k.trail_flex(t) + n(15, 0.5)),
      chest * Vector3d(0.0, std::sin(angle), std::cos(angle)));
  const Vector3d trail_wrist = lead_wrist + kGripSpacing * shaft;
  const Vector3d down(0.0, -1.0, 0.0);
  solve_limb(pose, skeleton, kLeftArmLimb, lead_wrist,
             (down + chest * Vector3d(0.2, 0.0, k.lead_elbow(t))).normalized());
  pose.set(kLeftHand, rot(Axis::Z, -10.0));
  solve_limb(pose, skeleton, kRightArmLimb, trail_wrist,
             (down + chest * Vector3d(-0.2, 0.0, k.trail_elbow(t))).normalized());
  pose.set(kRightHand, rot(Axis::Z, 10.0));
  set_hands_rest(pose, 40.0);
}

// ---------------------------------------------------------------------------------------------
// Walk: a 1 s gait cycle at 1.3 m/s along +Z. A foot's cycle starts at its heel strike: heel
// rocker until 10 %, flat until 40 %, heel rising about the ball until toe-off at 62 %, swing.

constexpr double kWalkSeconds = 4.0;
constexpr double kCycle = 1.0;    // s
constexpr double kSpeed = 130.0;  // cm/s
constexpr double kStride = kSpeed * kCycle;
constexpr double kHeelRockerEnd = 0.10, kFlatEnd = 0.40, kToeOff = 0.62, kToeRelaxed = 0.75;
// Foot pitch at heel strike and at toe-off, degrees (> 0: heel up).
constexpr double kHeelStrikePitch = -15.0, kToeOffPitch = 45.0;
constexpr double kSwingLift = 7.0;      // cm of extra ankle lift in swing
constexpr double kFootHalfWidth = 8.0;  // ankles at x = ±8 cm
constexpr double kToeOut = 6.0;         // degrees

struct FootPose {
  Vector3d ankle;
  Quaterniond rotation;  // world
  double toe_flex;       // degrees the toes bend up (keeps them flat while the heel is up)
};

// A foot at cycle coordinate c (its heel strikes at integer c), walking along +Z at lateral
// position x (the foot plants at z = stride·floor(c) + z0) and turned out by `yaw` degrees.
FootPose walk_foot(double c, double x, double z0, double yaw) {
  const double cycle = std::floor(c), phase = c - cycle;
  const Quaterniond turn = rot(Axis::Y, yaw);
  auto planted = [&](double cycle_index) {
    return Vector3d(x, kAnkleHeight, kStride * cycle_index + z0);
  };
  auto heel_strike_ankle = [&](double cycle_index) {
    const Vector3d heel_world = planted(cycle_index) + turn * kFootToHeel;
    return ankle_for_pivot(turn * rot(Axis::X, kHeelStrikePitch), kFootToHeel, heel_world);
  };
  auto toe_off_ankle = [&](double cycle_index) {
    const Vector3d ball_world = planted(cycle_index) + turn * kFootToBall;
    return ankle_for_pivot(turn * rot(Axis::X, kToeOffPitch), kFootToBall, ball_world);
  };
  FootPose f{planted(cycle), turn, 0.0};
  if (phase < kHeelRockerEnd) {  // heel contact, the foot rolls down onto its sole
    const double pitch = kHeelStrikePitch * (1.0 - smoothstep(phase / kHeelRockerEnd));
    f.rotation = turn * rot(Axis::X, pitch);
    f.ankle = ankle_for_pivot(f.rotation, kFootToHeel, planted(cycle) + turn * kFootToHeel);
  } else if (phase < kFlatEnd) {  // foot flat
  } else if (phase < kToeOff) {   // heel rises, the foot rolls over its ball, toes stay flat
    const double pitch = kToeOffPitch * smoothstep((phase - kFlatEnd) / (kToeOff - kFlatEnd));
    f.rotation = turn * rot(Axis::X, pitch);
    f.ankle = ankle_for_pivot(f.rotation, kFootToBall, planted(cycle) + turn * kFootToBall);
    f.toe_flex = pitch;
  } else {  // swing: from toe-off to the next heel strike, at rest at both ends, lifted between
    const double s = (phase - kToeOff) / (1.0 - kToeOff);
    const double e = smoothstep(s);
    f.ankle = (1.0 - e) * toe_off_ankle(cycle) + e * heel_strike_ankle(cycle + 1.0);
    const double g = 1.0 - (1.0 - s) * (1.0 - s);  // lift peaks early in the swing
    const double bump = std::sin(kPi * g);
    f.ankle.y() += kSwingLift * bump * bump;
    f.rotation = turn * rot(Axis::X, kToeOffPitch + (kHeelStrikePitch - kToeOffPitch) * e);
    const double relax = std::min(1.0, (phase - kToeOff) / (kToeRelaxed - kToeOff));
    f.toe_flex = kToeOffPitch * (1.0 - smoothstep(relax));
  }
  return f;
}

void walk_pose(const Skeleton& skeleton, double t, PoseBuilder& pose) {
  // The left heel strikes at t = 0.5 s (+ whole cycles), the right one half a cycle apart.
  const double c_left = t / kCycle + 0.5;
  const double c_right = c_left + 0.5;
  const double w = 2.0 * kPi * c_left;  // gait angle, 0 at the left heel strike
  // Pelvis: over the stance foot at mid-stance (≈ 30 % of its cycle); lowest just after each heel
  // strike, highest at mid-stance; swaying towards the stance side; the swing side's hip leads.
  const double mid_left = w - 2.0 * kPi * 0.30;
  const Vector3d root(2.0 * std::cos(mid_left), 91.2 + 2.4 * std::cos(2.0 * w - kPi),
                      kStride * c_left - 0.30 * kStride + 6.0);
  const double yaw = -5.0 * std::cos(w);
  const double roll = 3.0 * std::cos(mid_left);
  const double tilt = 6.0 + 1.0 * std::cos(2.0 * mid_left);
  pose.set_root(root, euler_deg({Axis::Y, Axis::X, Axis::Z}, yaw, tilt, roll));
  pose.set(kLHipJoint, Quaterniond::Identity());
  pose.set(kRHipJoint, Quaterniond::Identity());

  const Quaterniond heading = rot(Axis::Y, yaw);
  const FootPose left = walk_foot(c_left, kFootHalfWidth, 0.0, kToeOut);
  const FootPose right = walk_foot(c_right, -kFootHalfWidth, -0.5 * kStride, -kToeOut);
  for (const auto& [limb, foot, toe] : {std::tuple{kLeftLegLimb, left, kLeftToeBase},
                                        std::tuple{kRightLegLimb, right, kRightToeBase}}) {
    const Vector3d knee_pole = (foot.rotation * Vector3d::UnitZ() + heading * Vector3d::UnitZ());
    solve_limb(pose, skeleton, limb, foot.ankle, Vector3d(knee_pole.x(), 0.0, knee_pole.z()));
    pose.set_world(limb.end, foot.rotation);
    pose.set(toe, rot(Axis::X, -foot.toe_flex));
  }

  // Trunk upright above the tilting pelvis, shoulders counter-rotating; head looks ahead.
  set_spine(pose, -1.6 * yaw, 2.0 - tilt, -roll);
  set_head(pose, euler_deg({Axis::Y, Axis::X, Axis::Z}, 0.0, 4.0, 0.0));

  // Arms swing opposite to the legs: the left arm is furthest forward at the right heel strike.
  const double left_swing = 3.0 + 18.0 * std::cos(w - kPi);  // degrees forward
  const double right_swing = 3.0 + 18.0 * std::cos(w);
  pose.set(kLeftShoulder, Quaterniond::Identity());
  pose.set(kRightShoulder, Quaterniond::Identity());
  pose.set(kLeftArm, rot(Axis::X, -left_swing) * rot(Axis::Z, -82.0));
  pose.set(kLeftForeArm, rot(Axis::Y, -(18.0 + 0.6 * left_swing)));
  pose.set(kLeftHand, rot(Axis::Z, -5.0));
  pose.set(kRightArm, rot(Axis::X, -right_swing) * rot(Axis::Z, 82.0));
  pose.set(kRightForeArm, rot(Axis::Y, 18.0 + 0.6 * right_swing));
  pose.set(kRightHand, rot(Axis::Z, 5.0));
  set_hands_rest(pose, 20.0);
}

}  // namespace

std::string_view sample_kind_name(SampleKind kind) {
  return kind == SampleKind::Swing ? "swing" : "walk";
}

std::optional<SampleKind> parse_sample_kind(std::string_view name) {
  const std::string lower = ascii_lower(name);
  if (lower == "swing") return SampleKind::Swing;
  if (lower == "walk") return SampleKind::Walk;
  return std::nullopt;
}

Skeleton cmu_like_skeleton() {
  struct Spec {
    const char* name;
    int parent;
    Vector3d offset;
    std::vector<Vector3d> end_sites;
  };
  const Vector3d zero = Vector3d::Zero();
  const Vector3d hip = kLeftHipOffset, ball = kFootToBall, toe_tip(0.0, 0.0, 7.0);
  const Vector3d shoulder = kLeftShoulderOffset, upper = kUpperArm, fore = kForearm;
  const Vector3d finger(8.0, 0.0, 0.0), finger_tip(5.0, 0.0, 0.0), thumb_tip(3.0, 0.0, 3.0);
  const std::vector<Spec> specs{
      {"Hips", -1, {0.0, kHipsHeight, 0.0}, {}},
      {"LHipJoint", kHips, zero, {}},
      {"LeftUpLeg", kLHipJoint, hip, {}},
      {"LeftLeg", kLeftUpLeg, kThigh, {}},
      {"LeftFoot", kLeftLeg, kShin, {}},
      {"LeftToeBase", kLeftFoot, ball, {toe_tip}},
      {"RHipJoint", kHips, zero, {}},
      {"RightUpLeg", kRHipJoint, mirror_x(hip), {}},
      {"RightLeg", kRightUpLeg, kThigh, {}},
      {"RightFoot", kRightLeg, kShin, {}},
      {"RightToeBase", kRightFoot, ball, {toe_tip}},
      {"LowerBack", kHips, zero, {}},
      {"Spine", kLowerBack, {0.0, 15.0, 0.0}, {}},
      {"Spine1", kSpine, {0.0, 20.0, 0.0}, {}},
      {"Neck", kSpine1, zero, {}},
      {"Neck1", kNeck, {0.0, 16.0, -1.0}, {}},
      {"Head", kNeck1, {0.0, 10.0, 1.0}, {{0.0, 16.0, 0.0}}},
      {"LeftShoulder", kSpine1, zero, {}},
      {"LeftArm", kLeftShoulder, shoulder, {}},
      {"LeftForeArm", kLeftArm, upper, {}},
      {"LeftHand", kLeftForeArm, fore, {}},
      {"LeftFingerBase", kLeftHand, zero, {}},
      {"LeftHandIndex1", kLeftFingerBase, finger, {finger_tip}},
      {"LThumb", kLeftHand, zero, {thumb_tip}},
      {"RightShoulder", kSpine1, zero, {}},
      {"RightArm", kRightShoulder, mirror_x(shoulder), {}},
      {"RightForeArm", kRightArm, mirror_x(upper), {}},
      {"RightHand", kRightForeArm, mirror_x(fore), {}},
      {"RightFingerBase", kRightHand, zero, {}},
      {"RightHandIndex1", kRightFingerBase, mirror_x(finger), {mirror_x(finger_tip)}},
      {"RThumb", kRightHand, zero, {mirror_x(thumb_tip)}},
  };
  const std::vector<ChannelType> root_channels{ChannelType::Xposition, ChannelType::Yposition,
                                               ChannelType::Zposition, ChannelType::Zrotation,
                                               ChannelType::Yrotation, ChannelType::Xrotation};
  const std::vector<ChannelType> joint_channels{ChannelType::Zrotation, ChannelType::Yrotation,
                                                ChannelType::Xrotation};
  Skeleton skeleton;
  for (const Spec& s : specs) {
    skeleton.joints.push_back(
        {s.name, s.parent, s.offset, s.parent < 0 ? root_channels : joint_channels, s.end_sites});
  }
  return skeleton;
}

Clip make_sample_clip(SampleKind kind, const SampleOptions& options) {
  const double fps = options.fps, seconds = options.seconds;
  if (!(fps > 0.0 && fps <= kMaxSampleFps)) {
    throw ParameterError("sample fps must be in (0, " + format_number(kMaxSampleFps) + "], got " +
                         format_number(fps));
  }
  if (!(seconds >= 0.0 && seconds <= kMaxSampleSeconds)) {
    throw ParameterError("sample seconds must be in [0, " + format_number(kMaxSampleSeconds) +
                         "] (0: the natural length), got " + format_number(seconds));
  }
  const double natural = kind == SampleKind::Swing ? kSwingSeconds : kWalkSeconds;
  const double length = seconds > 0.0 ? seconds : natural;
  const double frames = std::round(length * fps);
  if (frames < 1.0 || frames > static_cast<double>(kMaxSampleFrames)) {
    throw ParameterError("sample of " + format_number(length) + " s at " + format_number(fps) +
                         " fps has " + std::to_string(static_cast<long long>(frames)) +
                         " frames; the frame count must be in [1, " +
                         std::to_string(kMaxSampleFrames) + "]");
  }

  Clip clip;
  clip.path = "sample:" + std::string(sample_kind_name(kind));
  clip.skeleton = cmu_like_skeleton();
  clip.motion.frame_time = 1.0 / fps;
  clip.motion.resize(static_cast<int>(frames), kNumJoints);
  PoseBuilder pose(clip.skeleton);
  if (kind == SampleKind::Swing) {
    const SwingTracks keys;
    const double scale = kSwingSeconds / length;  // the choreography fills the clip
    for (int f = 0; f < clip.motion.num_frames; ++f) {
      swing_pose(keys, clip.skeleton, f / fps * scale, pose);
      pose.store(clip.motion, f);
    }
  } else {
    for (int f = 0; f < clip.motion.num_frames; ++f) {
      walk_pose(clip.skeleton, f / fps, pose);
      pose.store(clip.motion, f);
    }
  }
  return clip;
}

}  // namespace motionmap::sample
