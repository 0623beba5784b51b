#include "motionmap/pipeline/key_poses.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/rotation.h"

namespace motionmap::pipeline {

namespace {

// The squared deviations of a trajectory from its time-linear interpolation between two of its
// points, for any pair in O(dims), from prefix sums: for keys a < b, L = b − a, the points
// t = a + i (0 < i < L) with s = i/L, u = 1 − s, the cost
//   Σ |p_t − u·p_a − s·p_b|² = Σ|p_t|² − 2 p_a·Σ u p_t − 2 p_b·Σ s p_t
//                              + |p_a|² Σu² + 2 p_a·p_b Σus + |p_b|² Σs²,
// with Σ s p_t = (Σ t p_t − a Σ p_t)/L, Σ u p_t = (b Σ p_t − Σ t p_t)/L, Σs² = Σu² =
// (L−1)(2L−1)/(6L) and Σus = (L−1)(L+1)/(6L).
class ChordCost {
 public:
  explicit ChordCost(const Eigen::MatrixXd& points)
      : m_p(points.rowwise() - points.colwise().mean()) {
    const Eigen::Index n = m_p.rows(), d = m_p.cols();
    m_sum = Eigen::MatrixXd::Zero(n + 1, d);
    m_tsum = Eigen::MatrixXd::Zero(n + 1, d);
    m_sq = Eigen::VectorXd::Zero(n + 1);
    for (Eigen::Index t = 0; t < n; ++t) {
      m_sum.row(t + 1) = m_sum.row(t) + m_p.row(t);
      m_tsum.row(t + 1) = m_tsum.row(t) + double(t) * m_p.row(t);
      m_sq(t + 1) = m_sq(t) + m_p.row(t).squaredNorm();
    }
  }
  double operator()(int a, int b) const {
    const int L = b - a;
    if (L < 2) return 0.0;
    const double s2 = double(L - 1) * (2.0 * L - 1) / (6.0 * L);
    const double us = double(L - 1) * (L + 1.0) / (6.0 * L);
    double cost = m_sq(b) - m_sq(a + 1);
    for (Eigen::Index j = 0; j < m_p.cols(); ++j) {
      const double S = m_sum(b, j) - m_sum(a + 1, j), T = m_tsum(b, j) - m_tsum(a + 1, j);
      const double pa = m_p(a, j), pb = m_p(b, j);
      cost += -2.0 * pa * (double(b) * S - T) / L - 2.0 * pb * (T - double(a) * S) / L +
              (pa * pa + pb * pb) * s2 + 2.0 * pa * pb * us;
    }
    return std::max(cost, 0.0);  // rounding
  }

 private:
  Eigen::MatrixXd m_p, m_sum, m_tsum;
  Eigen::VectorXd m_sq;
};

// The optimal keys of `points` (all of its rows considered), by dynamic programming.
std::vector<int> optimal_keys(const Eigen::MatrixXd& points, int count) {
  const int n = static_cast<int>(points.rows());
  const ChordCost cost(points);
  constexpr double kNone = std::numeric_limits<double>::infinity();
  // best[k·n + b]: the least cost of keys 0 … k with key k at b; from[]: key k − 1 then.
  std::vector<double> best(std::size_t(count) * std::size_t(n), kNone);
  std::vector<int> from(best.size(), -1);
  best[0] = 0.0;
  for (int k = 1; k < count; ++k) {
    const double* previous = best.data() + std::size_t(k - 1) * std::size_t(n);
    double* here = best.data() + std::size_t(k) * std::size_t(n);
    int* back = from.data() + std::size_t(k) * std::size_t(n);
    for (int b = k; b < n; ++b) {
      for (int a = k - 1; a < b; ++a) {
        if (previous[a] == kNone) continue;
        const double c = previous[a] + cost(a, b);
        if (c < here[b]) {
          here[b] = c;
          back[b] = a;
        }
      }
    }
  }
  std::vector<int> keys(static_cast<std::size_t>(count));
  int b = n - 1;
  for (int k = count - 1; k >= 0; --k) {
    keys[std::size_t(k)] = b;
    b = from[std::size_t(k) * std::size_t(n) + std::size_t(b)];
  }
  return keys;
}

}  // namespace

std::vector<int> select_key_poses(const Eigen::MatrixXd& points, int count) {
  const int n = static_cast<int>(points.rows());
  if (count < 2) {
    throw ParameterError("key poses: " + std::to_string(count) +
                         " asked for, expected at least 2 (the first and the last frame)");
  }
  if (n < 2 || points.cols() < 1) {
    throw ParameterError("key poses: a trajectory of " + std::to_string(n) +
                         " points, expected at least 2");
  }
  if (!points.allFinite()) throw ParameterError("key poses: the trajectory has a non-finite point");
  std::vector<int> keys;
  if (count >= n) {
    for (int i = 0; i < n; ++i) keys.push_back(i);
    return keys;
  }
  // Long trajectories: every step-th point (and the last), so that the search stays
  // O(count · kExactPoints²).
  const int step = (n + kExactPoints - 1) / kExactPoints;
  std::vector<int> rows;
  for (int i = 0; i < n; i += step) rows.push_back(i);
  if (rows.back() != n - 1) rows.push_back(n - 1);
  if (count >= static_cast<int>(rows.size())) return rows;
  Eigen::MatrixXd kept(static_cast<Eigen::Index>(rows.size()), points.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) kept.row(Eigen::Index(i)) = points.row(rows[i]);
  keys = optimal_keys(kept, count);
  for (int& k : keys) k = rows[std::size_t(k)];
  return keys;
}

std::vector<int> uniform_key_poses(int frames, int count) {
  if (count < 2 || frames < 2) {
    throw ParameterError("uniform key poses: " + std::to_string(count) + " of " +
                         std::to_string(frames) + " frames, expected at least 2 of at least 2");
  }
  std::vector<int> keys;
  for (int i = 0; i < count; ++i) {
    const int f = static_cast<int>(std::lround(double(i) * (frames - 1) / double(count - 1)));
    if (keys.empty() || f > keys.back()) keys.push_back(f);
  }
  return keys;
}

std::vector<int> clip_rows(const ClipMap& map, int clip) {
  return clip_rows(std::span<const int>(map.features->clip_of), clip);
}

std::vector<int> clip_rows(std::span<const int> clip_of, int clip) {
  std::vector<int> rows;
  for (std::size_t i = 0; i < clip_of.size(); ++i) {
    if (clip_of[i] == clip) rows.push_back(static_cast<int>(i));
  }
  return rows;
}

std::vector<int> clip_key_rows(const ClipMap& map, int clip, int count) {
  const std::vector<int> rows = clip_rows(map, clip);
  if (rows.size() < 2) {
    throw ParameterError("key poses: clip " + std::to_string(clip) + " has " +
                         std::to_string(rows.size()) + " samples in the map, expected at least 2");
  }
  const Eigen::MatrixXd& coords = map.embedding.coordinates;
  Eigen::MatrixXd points(static_cast<Eigen::Index>(rows.size()), coords.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) points.row(Eigen::Index(i)) = coords.row(rows[i]);
  std::vector<int> keys = select_key_poses(points, count);
  for (int& k : keys) k = rows[std::size_t(k)];
  return keys;
}

Motion interpolate_keys(const Motion& motion, std::span<const int> keys) {
  if (keys.empty()) throw ParameterError("interpolate keys: no key frame");
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (keys[i] < 0 || keys[i] >= motion.num_frames || (i > 0 && keys[i] <= keys[i - 1])) {
      throw ParameterError("interpolate keys: key " + std::to_string(keys[i]) +
                           " is out of order or outside the motion's " +
                           std::to_string(motion.num_frames) + " frames");
    }
  }
  Motion out = motion;
  const int J = motion.num_joints;
  auto hold = [&](int from, int to, int key) {
    for (int f = from; f < to; ++f) {
      for (int j = 0; j < J; ++j) {
        out.rotation(f, j) = motion.rotation(key, j);
        out.translation(f, j) = motion.translation(key, j);
      }
    }
  };
  hold(0, keys.front(), keys.front());
  hold(keys.back() + 1, motion.num_frames, keys.back());
  for (std::size_t i = 1; i < keys.size(); ++i) {
    const int a = keys[i - 1], b = keys[i];
    for (int f = a + 1; f < b; ++f) {
      const double s = double(f - a) / double(b - a);
      for (int j = 0; j < J; ++j) {
        out.rotation(f, j) = motion.rotation(a, j).slerp(s, motion.rotation(b, j)).normalized();
        out.translation(f, j) = (1.0 - s) * motion.translation(a, j) + s * motion.translation(b, j);
      }
    }
  }
  return out;
}

double rms_rotation_error(const Motion& a, const Motion& b, int first, int last) {
  if (a.num_frames != b.num_frames || a.num_joints != b.num_joints) {
    throw ParameterError("rotation error: motions of different sizes");
  }
  if (first < 0 || last >= a.num_frames || first > last || a.num_joints < 1) {
    throw ParameterError("rotation error: frames " + std::to_string(first) + "–" +
                         std::to_string(last) + " outside the motion's " +
                         std::to_string(a.num_frames) + " frames");
  }
  double sum = 0.0;
  for (int f = first; f <= last; ++f) {
    for (int j = 0; j < a.num_joints; ++j) {
      const double angle = rotation_angle(a.rotation(f, j), b.rotation(f, j));
      sum += angle * angle;
    }
  }
  const double n = double(last - first + 1) * a.num_joints;
  return rad_to_deg(std::sqrt(sum / n));
}

}  // namespace motionmap::pipeline
