#pragma once
// A map's own probabilistic inverse: at every point of a 2-D map, the weights of the map's frames
// in the pose there and how sure it is of that pose. A GP-LVM map's Gaussian process
// (embed::GplvmMap) is one; synth::MapBlender blends with it (BlendMode::Gp) and takes its rule
// of where the map is valid (synth::BlendOptions::gplvm). Here, in core, so that embed (which
// fits the model) and synth (which blends with it) share it without depending on each other.
#include <Eigen/Core>

namespace motionmap {

class MapGp {
 public:
  virtual ~MapGp() = default;
  /// The frames the weights are over (the map's rows).
  virtual int num_frames() const = 0;
  /// The model's variance at map point x (≥ 0), in its own units. @throws ParameterError if x is
  /// not finite.
  virtual double variance(const Eigen::Vector2d& x) const = 0;
  /// Where the map is valid: variance(x) ≤ threshold().
  virtual double threshold() const = 0;
  /// The scale (map units) on which the variance changes.
  virtual double lengthscale() const = 0;
  /// The weights of the frames in the pose at map point x: num_frames() values summing to 1.
  /// @throws ParameterError if x is not finite.
  virtual Eigen::VectorXd frame_weights(const Eigen::Vector2d& x) const = 0;

  /// variance(x) ≤ threshold(): x is inside the data.
  bool inside(const Eigen::Vector2d& x) const { return variance(x) <= threshold(); }

  /// From a point `in` inside to a point `out` outside: the largest t ∈ [0, 1] found inside on
  /// in + t·(out − in), by bisection to 1e-9 of the segment (where the region's edge crosses it).
  double edge_fraction(const Eigen::Vector2d& in, const Eigen::Vector2d& out) const {
    double lo = 0.0, hi = 1.0;  // inside at t = lo, outside at t = hi
    while (hi - lo > 1e-9) {
      const double t = 0.5 * (lo + hi);
      (inside(in + t * (out - in)) ? lo : hi) = t;
    }
    return lo;
  }
};

}  // namespace motionmap
