#pragma once
// Ordinary kriging with a linear variogram γ(h) = h over 2-D map points: the weights w (summing
// to 1) that predict a value at p from the values at the points, minimising the variance of the
// error. With A_ij = ‖c_i − c_j‖ and a_i = ‖c_i − p‖:
//
//   [A  1] [w]   [a]
//   [1ᵀ 0] [μ] = [1],     variance at p = wᵀ·a + μ (0 at every point, growing away from them).
//
// GlobalKriging solves it over all N points ((N+1)² dense, LU-factored once with BlockedLu).
// LocalKriging gives every point its own small system over K mutually separated neighbours
// (itself included), inverted once; the blender blends the predictions of nearby points'
// systems with partition-of-unity weights (see blender.h).
#include <cstddef>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/synth/detail/blocked_lu.h"
#include "motionmap/synth/detail/map_index.h"

namespace motionmap::synth::detail {

class GlobalKriging {
 public:
  /// Builds and factors the system over `points` (N ≥ 1 distinct points): about (2/3)·N³ flops,
  /// 8·(N+1)² bytes. Reports fractions 0…1 of `control`'s range (filling the matrix, factoring,
  /// estimating its condition) and polls it between chunks of a few ms of work.
  /// @throws NumericalError "the kriging system is singular (reciprocal condition …); use the
  ///         local mode" when its reciprocal condition estimate is not > 1e-15; Cancelled.
  GlobalKriging(std::span<const Eigen::Vector2d> points, const Control& control = {});

  int num_points() const { return static_cast<int>(m_points.size()); }

  /// The weights of `queries` over the points: column c holds w (N values) then μ for
  /// queries[c]; variance[c] receives that query's kriging variance.
  Eigen::MatrixXd solve(std::span<const Eigen::Vector2d> queries, std::span<double> variance) const;

 private:
  std::vector<Eigen::Vector2d> m_points;
  BlockedLu m_lu;
};

class LocalKriging {
 public:
  /// A system for every point of `index`: its K = min(neighbors, #points) nearest points that
  /// lie at least `separation` from each other (greedily, nearest first; fewer when a crowd of
  /// points closer than that leaves too few), itself included. O(N·K·log N). Reports fractions
  /// 0…1 of `control`'s range and polls it every few dozen points.
  /// With `lazy`, no system is built here: each is built the first time predict() needs it
  /// (the same system, bit for bit) and kept, so that a map of 10⁶ points costs only the systems
  /// its queries touch; `control` is then only polled once.
  /// @throws NumericalError "local kriging system of map point j is singular (reciprocal
  ///         condition …)" when one's reciprocal condition estimate is not > 1e-13 (lazy: from
  ///         the predict() that builds it); Cancelled.
  LocalKriging(const MapIndex& index, int neighbors, double separation, const Control& control = {},
               bool lazy = false);
  ~LocalKriging();
  LocalKriging(LocalKriging&&) noexcept;
  LocalKriging& operator=(LocalKriging&&) noexcept;

  /// Largest neighbourhood (the size of scratch space predict() needs, plus one): K when lazy.
  int max_hood() const { return m_max_hood; }
  /// Systems built so far (all points unless lazy).
  int num_built() const;

  /// Adds point j's system's weights at p, times `scale`, to `out` (point index, weight) and
  /// returns its kriging variance at p. `index` is the one the systems were built from; `rhs`
  /// and `sol` are scratch space of at least max_hood() + 1 values. Thread-safe.
  double predict(const MapIndex& index, int j, const Eigen::Vector2d& p, double scale,
                 std::vector<std::pair<int, double>>& out, std::span<double> rhs,
                 std::span<double> sol) const;

 private:
  // One point's neighbourhood (point indices) and the inverse of its bordered variogram matrix
  // ((k+1)², column-major).
  struct System {
    std::vector<int> hood;
    std::vector<double> inverse;
  };
  System build(const MapIndex& index, int j) const;

  int m_neighbors = 0;
  double m_separation = 0.0;
  // Eager: every point's system, packed.
  std::vector<int> m_hood_start, m_hood;
  std::vector<std::size_t> m_inverse_start;
  std::vector<double> m_inverses;
  int m_max_hood = 0;
  // Lazy: the systems built so far, by point.
  struct Lazy;
  std::unique_ptr<Lazy> m_lazy;
};

}  // namespace motionmap::synth::detail
