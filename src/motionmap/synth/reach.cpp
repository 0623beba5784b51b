// Reaching: scores every candidate sample's own pose against the goal, then refines the best few
// map points (and a drag's previous answer) with a capped Nelder–Mead over the map coordinates,
// each evaluation a locate + blend + forward kinematics (reach.h has the objective).
#include "motionmap/synth/reach.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/core/stats.h"
#include "motionmap/core/text_cursor.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::synth {

namespace {

// Samples whose poses are blended per chunk of the set-up (a blender reading on demand reads
// their clips first, a clip at a time).
constexpr int kSetupChunk = 2048;
// Best-scoring samples looked at for starts.
constexpr int kShortlist = 256;
// A local optimum this close to the target (× height) ends the search: nothing can do better.
constexpr double kExactFraction = 1e-9;

// "LeftHand", "Hand_L", "lHand" → the same key: joint_name_words(), left/right as l/r, sorted.
std::string name_key(std::string_view name) {
  std::vector<std::string> words = joint_name_words(name);
  for (std::string& w : words) {
    if (w == "left") w = "l";
    if (w == "right") w = "r";
  }
  std::sort(words.begin(), words.end());
  std::string key;
  for (const std::string& w : words) key += w + ' ';
  return key;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

bool near_match(std::string_view asked, std::string_view name) {
  const std::string a = ascii_lower(asked), n = ascii_lower(name);
  if (name_key(asked) == name_key(name)) return true;
  if (edit_distance(a, n) <= 2) return true;
  const std::string& shorter = a.size() < n.size() ? a : n;
  const std::string& longer = a.size() < n.size() ? n : a;
  return shorter.size() >= 3 && longer.find(shorter) != std::string::npos;
}

void check_finite(const Eigen::Vector3d& v, const std::string& what) {
  if (!v.allFinite()) {
    throw ParameterError("reach: " + what + " (" + format_number(v.x()) + ", " +
                         format_number(v.y()) + ", " + format_number(v.z()) +
                         ") is not a finite point");
  }
}

// The objective of reach.h at map point p, in the frame of MapBlender::pose (placement zero).
class Objective {
 public:
  struct Term {
    int joint = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double weight = 1.0;
  };

  Objective(const MapBlender& blender, std::vector<Term> terms, double lambda)
      : m_blender(blender), m_terms(std::move(terms)), m_lambda(lambda) {}

  double operator()(const Eigen::Vector2d& p) {
    ++m_evaluations;
    const MapWeights w = m_blender.locate(p);
    const Motion pose = m_blender.pose(w);
    forward_kinematics(m_blender.skeleton(), pose.pose(0), m_world);
    double e = m_lambda * (p - w.validity.point).squaredNorm();
    for (const Term& t : m_terms)
      e += t.weight * (m_world.positions[std::size_t(t.joint)] - t.position).squaredNorm();
    return e;
  }
  int evaluations() const { return m_evaluations; }

 private:
  const MapBlender& m_blender;
  std::vector<Term> m_terms;
  double m_lambda;
  WorldPose m_world;
  int m_evaluations = 0;
};

struct Vertex {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  double f = 0.0;
};

// Nelder–Mead in 2-D from `start` (its value known), initial edges `step` along the axes, until
// the simplex is smaller than `tolerance` or `budget` more evaluations are spent.
Vertex nelder_mead(Objective& f, const Vertex& start, double step, double tolerance, int budget) {
  const int stop = f.evaluations() + budget;
  std::array<Vertex, 3> s;
  s[0] = start;
  for (int k = 1; k < 3 && f.evaluations() < stop; ++k) {
    s[k].p = start.p + step * Eigen::Vector2d::Unit(k - 1);
    s[k].f = f(s[k].p);
  }
  if (f.evaluations() >= stop) {
    return *std::min_element(s.begin(), s.end(),
                             [](const Vertex& a, const Vertex& b) { return a.f < b.f; });
  }
  const auto by_value = [](const Vertex& a, const Vertex& b) { return a.f < b.f; };
  while (f.evaluations() < stop) {
    std::sort(s.begin(), s.end(), by_value);
    if ((s[1].p - s[0].p).norm() < tolerance && (s[2].p - s[0].p).norm() < tolerance) break;
    if (s[0].f == 0.0) break;
    const Eigen::Vector2d c = 0.5 * (s[0].p + s[1].p);
    Vertex r{c + (c - s[2].p), 0.0};
    r.f = f(r.p);
    if (r.f < s[0].f) {
      if (f.evaluations() >= stop) {
        s[2] = r;
        break;
      }
      Vertex e{c + 2.0 * (c - s[2].p), 0.0};
      e.f = f(e.p);
      s[2] = e.f < r.f ? e : r;
      continue;
    }
    if (r.f < s[1].f) {
      s[2] = r;
      continue;
    }
    if (f.evaluations() >= stop) break;
    const bool outside = r.f < s[2].f;
    Vertex k{
        outside ? Eigen::Vector2d(c + 0.5 * (r.p - c)) : Eigen::Vector2d(c + 0.5 * (s[2].p - c)),
        0.0};
    k.f = f(k.p);
    if (k.f < (outside ? r.f : s[2].f)) {
      s[2] = k;
      continue;
    }
    // Shrink towards the best vertex.
    for (int i = 1; i < 3 && f.evaluations() < stop; ++i) {
      s[i].p = s[0].p + 0.5 * (s[i].p - s[0].p);
      s[i].f = f(s[i].p);
    }
  }
  return *std::min_element(s.begin(), s.end(), by_value);
}

Eigen::Isometry3d joint_transform(const WorldPose& world, int joint) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = world.rotations[std::size_t(joint)].normalized().toRotationMatrix();
  t.translation() = world.positions[std::size_t(joint)];
  return t;
}

}  // namespace

void ReachOptions::validate() const {
  if (starts < 1 || starts > 64)
    throw ParameterError("reach: starts = " + format_number(starts) + " must be in [1, 64]");
  if (max_evaluations < 8 || max_evaluations > 1000000) {
    throw ParameterError("reach: max_evaluations = " + format_number(max_evaluations) +
                         " must be in [8, 1000000]");
  }
  if (!(keep_margin >= 0.0 && keep_margin <= 1.0))
    throw ParameterError("reach: keep_margin = " + format_number(keep_margin) +
                         " must be in [0, 1]");
  if (!(tolerance > 0.0 && tolerance <= 1.0))
    throw ParameterError("reach: tolerance = " + format_number(tolerance) + " must be in (0, 1]");
}

int find_joint(const Skeleton& skeleton, std::string_view name) {
  if (const int exact = skeleton.find(name); exact >= 0) return exact;
  int found = -1, count = 0;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    if (ascii_iequals(skeleton.joints[std::size_t(j)].name, name)) {
      found = j;
      ++count;
    }
  }
  if (count == 1) return found;
  std::string near, all;
  for (const Joint& joint : skeleton.joints) {
    all += (all.empty() ? "" : ", ") + joint.name;
    if (near_match(name, joint.name)) near += (near.empty() ? "" : ", ") + joint.name;
  }
  throw ParameterError("no joint named '" + std::string(name) + "' in the skeleton" +
                       (near.empty() ? std::string() : "; did you mean " + near + "?") +
                       " (its joints: " + all + ")");
}

struct Reacher::Impl {
  const MapBlender* blender = nullptr;
  double height = 1.0;
  int joints = 0;
  std::vector<int> candidates;
  /// candidates.size() × joints positions, in MapBlender::pose's frame.
  std::vector<Eigen::Vector3f> positions;
};

Reacher::Reacher(const MapBlender& blender, const Control& control) : m(std::make_unique<Impl>()) {
  m->blender = &blender;
  const Skeleton& skeleton = blender.skeleton();
  m->joints = skeleton.num_joints();
  const int n = blender.num_samples();
  const int stride = (n + kMaxCandidates - 1) / kMaxCandidates;
  for (int i = 0; i < n; i += std::max(1, stride)) m->candidates.push_back(i);
  const int count = static_cast<int>(m->candidates.size());
  m->positions.resize(std::size_t(count) * std::size_t(m->joints));
  std::vector<double> extents(std::size_t(count), 0.0);
  const int up = static_cast<int>(blender.options().up);
  const Control setup = control.stage("reach set-up", 0.0, 1.0);
  for (int begin = 0; begin < count; begin += kSetupChunk) {
    const int end = std::min(count, begin + kSetupChunk);
    std::vector<MapWeights> weights;
    for (int k = begin; k < end; ++k)
      weights.push_back(MapWeights::of_sample(m->candidates[std::size_t(k)]));
    if (blender.reads_on_demand()) blender.prefetch(weights);
    parallel_for(end - begin, [&](int k) {
      const Motion pose = blender.pose(weights[std::size_t(k)]);
      WorldPose world;
      forward_kinematics(skeleton, pose.pose(0), world);
      const std::size_t row = std::size_t(begin + k) * std::size_t(m->joints);
      for (int j = 0; j < m->joints; ++j)
        m->positions[row + std::size_t(j)] = world.positions[std::size_t(j)].cast<float>();
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto* points : {&world.positions, &world.end_sites}) {
        for (const Eigen::Vector3d& p : *points) {
          lo = std::min(lo, p[up]);
          hi = std::max(hi, p[up]);
        }
      }
      extents[std::size_t(begin + k)] = hi - lo;
    });
    setup.update(static_cast<double>(end) / count);
  }
  const double height = count > 0 ? median(std::move(extents)) : 0.0;
  m->height = height > 0.0 && std::isfinite(height) ? height : 1.0;
  setup.finish();
}

Reacher::~Reacher() = default;
Reacher::Reacher(Reacher&&) noexcept = default;
Reacher& Reacher::operator=(Reacher&&) noexcept = default;

const MapBlender& Reacher::blender() const {
  return *m->blender;
}
double Reacher::height() const {
  return m->height;
}
int Reacher::num_candidates() const {
  return static_cast<int>(m->candidates.size());
}

ReachResult Reacher::reach(const ReachGoal& goal, const ReachOptions& options,
                           const Control& control) const {
  options.validate();
  const MapBlender& blender = *m->blender;
  const Skeleton& skeleton = blender.skeleton();
  const int joints = m->joints;
  const auto check_joint = [&](int j, const std::string& what) {
    if (j < 0 || j >= joints) {
      throw ParameterError("reach: " + what + " " + std::to_string(j) +
                           " is not a joint of the skeleton (0 … " + std::to_string(joints - 1) +
                           ")");
    }
  };
  check_joint(goal.joint, "joint");
  check_finite(goal.target, "the target");
  for (std::size_t k = 0; k < goal.pins.size(); ++k) {
    const ReachPin& pin = goal.pins[k];
    check_joint(pin.joint, "pin " + std::to_string(k) + "'s joint");
    check_finite(pin.position, "pin " + std::to_string(k) + "'s position");
    if (!(pin.weight >= 0.0) || !std::isfinite(pin.weight)) {
      throw ParameterError("reach: pin " + std::to_string(k) + "'s weight " +
                           format_number(pin.weight) + " must be finite and ≥ 0");
    }
  }
  if (!std::isfinite(goal.placement.heading) || !goal.placement.floor.allFinite())
    throw ParameterError("reach: the root placement is not finite");
  if (goal.start && !goal.start->allFinite())
    throw ParameterError("reach: the start point is not finite");

  // The placed frame is the pose's frame turned and moved with its motion root: T = W_placed ·
  // W_pose⁻¹ at the motion root, the same for every pose (the joints above it are constant).
  const int root = blender.motion_root();
  const MapWeights first = MapWeights::of_sample(m->candidates.front());
  WorldPose world;
  forward_kinematics(skeleton, blender.pose(first).pose(0), world);
  const Eigen::Isometry3d unplaced = joint_transform(world, root);
  forward_kinematics(skeleton, blender.pose(first, goal.placement).pose(0), world);
  const Eigen::Isometry3d placed = joint_transform(world, root);
  const Eigen::Isometry3d to_pose = unplaced * placed.inverse();

  std::vector<Objective::Term> terms;
  terms.push_back({goal.joint, to_pose * goal.target, 1.0});
  for (const ReachPin& pin : goal.pins)
    terms.push_back({pin.joint, to_pose * pin.position, pin.weight});

  const double height = m->height;
  const double reach_distance = blender.reach_distance();
  double step = blender.median_step();
  if (!(step > 0.0)) step = reach_distance > 0.0 ? reach_distance : 1e-3;
  const double lambda = std::pow(height / (reach_distance > 0.0 ? reach_distance : step), 2);
  Objective objective(blender, terms, lambda);

  // Score every candidate's own pose.
  const int count = num_candidates();
  std::vector<double> score(std::size_t(count), 0.0);
  for (int c = 0; c < count; ++c) {
    const Eigen::Vector3f* row = &m->positions[std::size_t(c) * std::size_t(joints)];
    double e = 0.0;
    for (const Objective::Term& t : terms)
      e += t.weight * (row[t.joint].cast<double>() - t.position).squaredNorm();
    score[std::size_t(c)] = e;
  }
  std::vector<int> order(static_cast<std::size_t>(count));
  for (int c = 0; c < count; ++c) order[std::size_t(c)] = c;
  const int shortlist = std::min(count, kShortlist);
  std::partial_sort(order.begin(), order.begin() + shortlist, order.end(), [&](int a, int b) {
    return score[std::size_t(a)] < score[std::size_t(b)] ||
           (score[std::size_t(a)] == score[std::size_t(b)] && a < b);
  });
  std::vector<Eigen::Vector2d> starts;
  for (int k = 0; k < shortlist && static_cast<int>(starts.size()) < options.starts; ++k) {
    const Eigen::Vector2d p =
        blender.sample_point(m->candidates[std::size_t(order[std::size_t(k)])]);
    const bool apart = std::all_of(starts.begin(), starts.end(), [&](const Eigen::Vector2d& s) {
      return (s - p).norm() >= reach_distance;
    });
    if (apart) starts.push_back(p);
  }
  // A start outside the data (a stale point) begins at the data's edge instead.
  if (goal.start) starts.insert(starts.begin(), blender.locate(*goal.start).validity.point);

  const double tolerance = options.tolerance * step;
  Vertex best{Eigen::Vector2d::Zero(), std::numeric_limits<double>::infinity()};
  Vertex from_start = best;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    control.check();
    const int left = options.max_evaluations - objective.evaluations();
    if (left <= 0) break;
    const int budget = left / static_cast<int>(starts.size() - k);
    Vertex v{starts[k], 0.0};
    v.f = objective(v.p);
    if (budget > 1) v = nelder_mead(objective, v, step, tolerance, budget - 1);
    if (goal.start && k == 0) from_start = v;
    if (v.f < best.f) best = v;
    if (std::sqrt(best.f) <= kExactFraction * height) break;
  }
  bool kept = false;
  if (goal.start && std::isfinite(from_start.f) &&
      std::sqrt(from_start.f) <= std::sqrt(best.f) + options.keep_margin * height) {
    best = from_start;
    kept = true;
  }

  ReachResult out;
  // The point evaluated at best.p; on the data's edge, rounding can put it a hair beyond the
  // reach, so it is pulled towards its nearest sample until locate() takes it as it is.
  Eigen::Vector2d q = blender.locate(best.p).validity.point;
  MapWeights weights = blender.locate(q);
  for (double shrink = 1e-12; weights.validity.clamped && shrink <= 1e-3; shrink *= 10.0) {
    const Eigen::Vector2d s = blender.sample_point(weights.validity.nearest_sample);
    q = s + (1.0 - shrink) * (q - s);
    weights = blender.locate(q);
  }
  out.point = weights.validity.point;
  out.validity = weights.validity;
  out.pose = blender.pose(weights, goal.placement);
  forward_kinematics(skeleton, out.pose.pose(0), world);
  out.reached = world.positions[std::size_t(goal.joint)];
  out.error = (out.reached - goal.target).norm();
  out.height = height;
  out.error_fraction = out.error / height;
  for (const ReachPin& pin : goal.pins)
    out.pin_errors.push_back((world.positions[std::size_t(pin.joint)] - pin.position).norm());
  out.evaluations = objective.evaluations();
  out.from_start = kept;
  return out;
}

ReachResult reach(const MapBlender& blender, const ReachGoal& goal, const ReachOptions& options,
                  const Control& control) {
  return Reacher(blender, control).reach(goal, options, control);
}

}  // namespace motionmap::synth
