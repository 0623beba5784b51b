#pragma once
// The temporal smoothing of blend weights that synthesize() and edit_path() share: a Gaussian
// over ±3σ frames, renormalised where the window passes the motion's ends; and the smoothstep
// fade the synth stages share.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "motionmap/synth/blender.h"

namespace motionmap::synth::detail {

/// 1 − smoothstep(x): 1 at and below 0, falling as 1 − (3x² − 2x³) to 0 at and above 1 (the
/// clean-up's fades, the trajectory's share along a path).
inline double falloff(double x) {
  if (x >= 1.0) return 0.0;
  if (x <= 0.0) return 1.0;
  return 1.0 - x * x * (3.0 - 2.0 * x);
}

/// The kernel g_j, j = −half…half (half = ⌈3σ⌉ frames, at most `frames`), σ = smooth / dt
/// frames; {1} for smooth = 0.
inline std::vector<double> smoothing_kernel(double smooth, double dt, long long frames) {
  std::vector<double> kernel{1.0};
  if (smooth > 0.0) {
    const double sigma = smooth / dt;
    const auto half = static_cast<long long>(
        std::min<double>(std::ceil(3.0 * sigma), static_cast<double>(frames)));
    kernel.assign(static_cast<std::size_t>(2 * half + 1), 0.0);
    for (long long j = -half; j <= half; ++j) {
      kernel[static_cast<std::size_t>(j + half)] = std::exp(-0.5 * (j / sigma) * (j / sigma));
    }
  }
  return kernel;
}

/// Most frames a window reads on either side of its centre: a wider window reads only the frames
/// of the motion that are multiples of its stride ⌈half / kMaxSmoothingTaps⌉, fixed in the motion
/// and not moving with the frame smoothed, so a jump is still softened frame by frame over the
/// whole window and not in stairs. Smoothing so costs about the same per frame at 120 fps as at
/// 30 (each frame read moves its weights in their clips): at 120 fps and σ = 0.05 s, frames 4
/// apart (0.67σ).
inline constexpr long long kMaxSmoothingTaps = 5;

/// Σ g_j·w'_{k+j} / Σ g_j over the frames of the window that exist (0 ≤ k + j < frames), where
/// w'_{k+j} = blender.later_in_clip(w_{k+j}, −j·dt): each neighbour's weights moved back in their
/// clips by its distance in time, so that frames playing a clip average to that clip's frame
/// (a path along a clip at its pace keeps its motion: smoothing softens where the path jumps
/// between clips, not the clip's own motion). `raw` holds the raw weights of frames raw_first,
/// raw_first + 1, … (a deque or a vector); dt: the path's frame time. Of a window wider than
/// ±kMaxSmoothingTaps frames, only the frames k + j that are multiples of its stride (above) are
/// read.
template <class Weights>
MapWeights smoothed(const Weights& raw, long long raw_first, long long k, long long frames,
                    const std::vector<double>& kernel, double dt, const MapBlender& blender) {
  const auto half = static_cast<long long>(kernel.size() / 2);
  const long long stride = std::max(1LL, (half + kMaxSmoothingTaps - 1) / kMaxSmoothingTaps);
  // Per thread, kept between calls: a frame touches a few dozen of a map's samples, and zeroing
  // a sum for every sample of the map per frame took a sixth of a smoothed synthesis's time on a
  // 10 000-sample map. The samples touched are cleared again on the way out, an exception's too.
  const auto num_samples = static_cast<std::size_t>(blender.num_samples());
  thread_local std::vector<double> acc;
  thread_local std::vector<char> seen;
  if (acc.size() < num_samples) {
    acc.assign(num_samples, 0.0);
    seen.assign(num_samples, 0);
  }
  std::vector<int> touched;
  struct Clear {
    const std::vector<int>& touched;
    ~Clear() {
      for (const int s : touched) {
        acc[static_cast<std::size_t>(s)] = 0.0;
        seen[static_cast<std::size_t>(s)] = 0;
      }
    }
  } clear{touched};
  double gsum = 0.0, pace = 0.0;
  for (long long j = -half; j <= half; ++j) {
    const long long f = k + j;
    if (f < 0 || f >= frames || f % stride != 0) continue;
    const double g = kernel[static_cast<std::size_t>(j + half)];
    gsum += g;
    const MapWeights& own = raw[static_cast<std::size_t>(f - raw_first)];
    pace += g * own.pace;
    const MapWeights moved = j == 0 ? MapWeights{} : blender.later_in_clip(own, -j * dt);
    const MapWeights& w = j == 0 ? own : moved;
    for (std::size_t e = 0; e < w.samples.size(); ++e) {
      const int s = w.samples[e];
      if (!seen[s]) {
        seen[s] = 1;
        touched.push_back(s);
      }
      acc[s] += g * w.weights[e];
    }
  }
  std::sort(touched.begin(), touched.end());
  MapWeights out;
  out.validity = raw[static_cast<std::size_t>(k - raw_first)].validity;
  out.samples = touched;
  out.weights.reserve(touched.size());
  for (int s : touched) out.weights.push_back(acc[s] / gsum);
  out.pace = pace / gsum;
  return out;
}

}  // namespace motionmap::synth::detail
