#pragma once
// How faithful a map is: neighbourhood preservation (trustworthiness and continuity, Venna &
// Kaski 2001), distance preservation (normalised stress) and smoothness in time (jump score).
//
//   auto q = neighborhood_quality(D, map.coordinates);  // q.trustworthiness, q.continuity ∈ [0, 1]
//   double jumps = jump_score(map.coordinates);         // ≈1 smooth; ≫1 the map tears the motion
#include <algorithm>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"

namespace motionmap::embed {

/// Neighbourhood preservation at k neighbours, both in [0, 1] (1 = perfect).
struct NeighborhoodQuality {
  double trustworthiness = 0.0;  ///< are the map's neighbours true neighbours?
  double continuity = 0.0;       ///< are the true neighbours still neighbours on the map?
};

/// Trustworthiness exactly as sklearn.manifold.trustworthiness(D, Y, n_neighbors=k,
/// metric="precomputed"):
///   T = 1 − 2/(n·k·(2n − 3k − 1)) · Σ_i Σ_{j ∈ U_i} (r(i, j) − k),
/// U_i = frame i's k nearest on the map that are not among its k nearest by D, r(i, j) = the rank
/// of j among i's neighbours by D (1 = nearest). Continuity is the same with the roles of D and
/// the map swapped (true neighbours missing on the map, ranked by map distance). Ties in either
/// space go to the smaller frame index. D: #frames by #frames (column i = distances from i);
/// Y: #frames by #dims map. O(#frames²), parallel.
/// @throws ParameterError unless 1 ≤ k < #frames / 2, D is square with Y's row count, and both
///   are finite; Cancelled (`control` is polled and told the fraction of frames done).
NeighborhoodQuality neighborhood_quality(const Eigen::MatrixXd& D, const Eigen::MatrixXd& Y,
                                         int k = 10, const Control& control = {});

/// neighborhood_quality(D, Y, k).trustworthiness. @throws as neighborhood_quality.
double trustworthiness(const Eigen::MatrixXd& D, const Eigen::MatrixXd& Y, int k = 10);

/// neighborhood_quality(D, Y, k).continuity. @throws as neighborhood_quality.
double continuity(const Eigen::MatrixXd& D, const Eigen::MatrixXd& Y, int k = 10);

/// Normalised stress of map Y against target distances T (#frames by #frames, lower triangle
/// read) over the pairs i < j, after the optimal scale s of the map distances e_ij:
///   stress = sqrt(Σ (t_ij − s·e_ij)² / Σ t_ij²),   s = Σ t_ij·e_ij / Σ e_ij²  (the minimiser),
/// i.e. sqrt(1 − (Σ t·e)² / (Σ t²·Σ e²)). 0 = distances preserved up to scale; 1 when the map
/// is a single point. 0 when every target distance is 0.
/// @throws ParameterError unless T is square with Y's row count; Cancelled (`control` is polled
///   and told the fraction of columns done).
double normalized_stress(const Eigen::MatrixXd& T, const Eigen::MatrixXd& Y,
                         const Control& control = {});

/// Jump score: the 95th percentile of the steps ‖Y(f+1) − Y(f)‖ between consecutive frames
/// divided by their median (percentiles interpolated linearly, like numpy). ≈1 when the map
/// moves evenly; large when a few steps jump across the map. 1 when every step is 0, +inf when
/// the median is 0 but not the 95th percentile.
/// @throws ParameterError for fewer than 2 frames.
double jump_score(const Eigen::MatrixXd& Y);

/// The voters of knn_label_vote(), gathered as candidates are met: the k smallest (distance,
/// index) pairs offered (ties to the smaller index), whatever the order they are offered in, so
/// a search that skips candidates that cannot be among them (label_accuracy's) votes as a scan
/// of every distance does.
class NearestVoters {
 public:
  /// @throws ParameterError if k < 1.
  explicit NearestVoters(int k);
  /// Candidate `index` at `distance` (finite; the caller has chosen the candidates).
  void offer(double distance, int index) {
    const std::pair<double, int> candidate(distance, index);
    if (int(m_heap.size()) < m_k) {
      m_heap.push_back(candidate);
      std::push_heap(m_heap.begin(), m_heap.end());
    } else if (candidate < m_heap.front()) {
      std::pop_heap(m_heap.begin(), m_heap.end());
      m_heap.back() = candidate;
      std::push_heap(m_heap.begin(), m_heap.end());
    }
  }
  /// Whether k candidates are kept: then a candidate farther than bound() cannot enter.
  bool full() const { return int(m_heap.size()) == m_k; }
  /// The farthest distance kept (+inf until full()).
  double bound() const {
    return full() ? m_heap.front().first : std::numeric_limits<double>::infinity();
  }
  /// The code that wins the vote of the candidates kept (codes[index] each), by
  /// knn_label_vote()'s rule; −1 when none was offered.
  int vote(std::span<const int> codes) const;

 private:
  int m_k;
  std::vector<std::pair<double, int>> m_heap;  ///< a max-heap: the farthest on top
};

/// The label a k-nearest-neighbour vote gives a query frame, from its distances to every frame
/// (`distances[j]`, j < #frames): the candidates are the frames j with codes[j] ≥ 0 (labelled)
/// and groups[j] ≠ `group` (other clips than the query's); the k nearest are the k smallest
/// distances, ties to the smaller index j; each votes for its code, and the code with the most
/// votes wins; a tied vote goes to the tied code whose nearest voter is nearest (so k = 1 is the
/// nearest candidate's code). Returns −1 when there is no candidate; fewer than k candidates
/// all vote. Non-finite distances are not candidates.
/// @throws ParameterError if the sizes differ or k < 1.
int knn_label_vote(std::span<const double> distances, std::span<const int> codes,
                   std::span<const int> groups, int group, int k);

}  // namespace motionmap::embed
