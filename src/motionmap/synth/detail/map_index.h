#pragma once
// Where the samples of a map lie: their distinct map points (samples closer than 1e-9 × the map's
// extent merged into one), a k-d tree over those points for nearest-neighbour queries, the
// trajectory (consecutive samples of a clip), its median step and speed, and what lies outside
// the data (farther than reach_radius() from every sample) and where such a point is moved.
//
//   MapIndex index(frame_times, samples, sample_points, /*reach=*/3.0);
//   PointValidity v = index.validate({0.3, -1.2});  // nearest sample, clamped point
//   index.nearest(v.point, 5, idx, dist);           // the 5 nearest map points
//
// A MapIndex is immutable once built; its const member functions are thread-safe.
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "motionmap/features/features.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blender.h"

namespace motionmap::synth::detail {

/// Weights given as (sample, weight) entries, any order, repeats allowed → MapWeights: sorted by
/// sample, repeats summed, with `validity`.
MapWeights weights_by_sample(std::vector<std::pair<int, double>> entries,
                             const PointValidity& validity);

class MapIndex {
 public:
  /// Indexes `sample_points` (one map point per sample of `samples`, whose clip_of and frame_of
  /// say which frame of which clip each is; checked by the caller). `frame_times`: seconds per
  /// frame of each clip. `reach` > 0.
  MapIndex(std::span<const double> frame_times, const features::FeatureSet& samples,
           std::vector<Eigen::Vector2d> sample_points, double reach);
  ~MapIndex();
  MapIndex(MapIndex&&) noexcept;
  MapIndex& operator=(MapIndex&&) noexcept;

  int num_samples() const { return static_cast<int>(m_sample_points.size()); }
  /// Distinct map points (samples after merging).
  int num_points() const { return static_cast<int>(m_points.size()); }
  const Eigen::Vector2d& sample_point(int sample) const { return m_sample_points[sample]; }
  /// The distinct map points; point j is the map point of its first member.
  std::span<const Eigen::Vector2d> points() const { return m_points; }
  /// The samples that share map point j, increasing.
  std::span<const int> members(int j) const {
    return std::span<const int>(m_members).subspan(
        static_cast<std::size_t>(m_member_start[j]),
        static_cast<std::size_t>(m_member_start[j + 1] - m_member_start[j]));
  }

  /// Median of the non-zero map steps between consecutive samples of a clip (upper_median; 0 if
  /// none), the same over map speeds (step / time between the frames), and reach_radius().
  double median_step() const { return m_median_step; }
  double median_speed() const { return m_median_speed; }
  double reach_distance() const { return m_reach_distance; }

  /// The (up to) k nearest map points to p, nearest first: their indices and distances (not
  /// squared). Returns how many were found (min(k, num_points())).
  int nearest(const Eigen::Vector2d& p, int k, std::uint32_t* idx, double* dist) const;

  /// Where p is evaluated: p itself within the reach of a sample, else moved onto the reach of
  /// the trajectory (see blender.h). Sets query, point, clamped, distance and nearest_sample;
  /// variance is left 0. @throws ParameterError if p is not finite.
  PointValidity validate(const Eigen::Vector2d& p) const;

  /// Weights over map points (index, weight; repeats allowed) → weights over samples: each
  /// point's weight shared equally between its members, sorted by sample, repeats summed.
  MapWeights to_sample_weights(const std::vector<std::pair<int, double>>& point_weights,
                               const PointValidity& validity) const;
  /// Dense weights over all points (num_points() values) → over all samples (num_samples()).
  void to_sample_weights(const double* point_weights, double* sample_weights) const;

  /// Where sample `sample`'s clip is `seconds` later (earlier when negative), among the samples of
  /// its run (consecutive samples of the clip, frames increasing): the sample at that time, or the
  /// two around it weighted linearly by time; the run's first or last sample beyond its ends.
  /// `samples` and `weights` take up to 2 entries; returns how many (1 or 2).
  int later_in_clip(int sample, double seconds, int* samples, double* weights) const;

  /// Where sample `sample`'s clip is `seconds` later on the map, as later_in_clip() finds that
  /// time: the point (the run's samples' points interpolated linearly), and in `velocity` the
  /// map velocity there (per second; that of the segment ahead at a sample, of the last segment at
  /// the run's last sample; 0 for a run of one sample).
  Eigen::Vector2d trajectory_at(int sample, double seconds, Eigen::Vector2d& velocity) const;
  /// The seconds from the first sample of `sample`'s run to it.
  double seconds_in_run(int sample) const;
  /// The seconds from the first sample of `sample`'s run to its last.
  double run_seconds(int sample) const {
    return seconds_in_run(m_run_last[static_cast<std::size_t>(sample)]);
  }
  /// The frame time of `sample`'s clip.
  double frame_time(int sample) const { return m_frame_time[static_cast<std::size_t>(sample)]; }
  /// The first sample of `sample`'s run (consecutive samples of its clip, frames increasing).
  int run_of(int sample) const { return m_run_first[static_cast<std::size_t>(sample)]; }
  /// The next sample of `sample`'s run, −1 at its last.
  int next_in_run(int sample) const {
    return sample < m_run_last[static_cast<std::size_t>(sample)] ? sample + 1 : -1;
  }
  /// The frame of its clip that `sample` is.
  int frame_of(int sample) const { return m_frame_of[static_cast<std::size_t>(sample)]; }

  /// The map point that sample `s` shares with its merged samples.
  int point_of(int sample) const { return m_point_of[static_cast<std::size_t>(sample)]; }

  /// A piece of the trajectory near a map point: the segment from sample `first` to the next
  /// sample of its clip, `second`, the parameter t ∈ [0, 1] of its point nearest the map point
  /// (first + t·(second − first)), that point's distance to it, and the seconds between the two
  /// samples' frames.
  struct TrajectoryHit {
    int first = 0, second = 0;
    double t = 0.0, distance = 0.0, seconds = 0.0;
  };
  /// The segments between consecutive samples of a clip at most `max_seconds` apart in time that
  /// pass within `radius` (exclusive) of p, nearest first (ties in the order of the samples).
  void trajectory_near(const Eigen::Vector2d& p, double radius, double max_seconds,
                       std::vector<TrajectoryHit>& out) const;
  /// Where a hit's point is in its clip: the run (its first sample) and the seconds into it.
  std::pair<int, double> clip_time(const TrajectoryHit& hit) const {
    return {run_of(hit.first), seconds_in_run(hit.first) + hit.t * hit.seconds};
  }

 private:
  // later_in_clip() for sample index s; `frame`: the frame of s's clip `seconds` later (not
  // snapped to a whole frame, as the samples found are).
  int time_in_run(std::size_t s, double seconds, double& frame, int* samples,
                  double* weights) const;
  // The point of the trajectory nearest p, moved back towards p (see validate());
  // `nearest_distance`: p's distance to its nearest map point.
  Eigen::Vector2d clamp(const Eigen::Vector2d& p, double nearest_distance) const;

  struct Tree;  // nanoflann's k-d tree over m_points
  std::vector<Eigen::Vector2d> m_sample_points;
  std::vector<Eigen::Vector2d> m_points;
  std::unique_ptr<Tree> m_tree;
  // Members of point j: m_members[m_member_start[j] … m_member_start[j+1]).
  std::vector<int> m_member_start, m_members;
  std::vector<int> m_point_of;  // sample → map point
  // Per sample: its frame, its clip's frame time, and the first and last sample of its run.
  std::vector<int> m_frame_of, m_run_first, m_run_last;
  std::vector<int> m_run_stride;  // per sample: the frames between its run's samples, 0 if uneven
  std::vector<double> m_frame_time;
  // The trajectory: segments between consecutive samples of a clip, and isolated samples as
  // segments of length 0 (start, end sample).
  std::vector<std::pair<int, int>> m_segments;
  std::vector<double> m_segment_seconds;  // per segment: the time between its samples (0: isolated)
  // clamp()'s search: the segments by length, each tier's midpoints in a k-d tree.
  struct SegmentTier {
    std::vector<int> segments;  // indices into m_segments, increasing
    double half_length = 0.0;   // the longest one's, halved
    std::unique_ptr<Tree> midpoints;
  };
  std::vector<SegmentTier> m_tiers;
  double m_search_slack = 0.0;
  double m_median_step = 0.0, m_median_speed = 0.0, m_reach_distance = 0.0;
};

}  // namespace motionmap::synth::detail
