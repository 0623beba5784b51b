#include "motionmap/synth/synthesize.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <functional>
#include <iterator>
#include <optional>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/synth/detail/outside_route.h"
#include "motionmap/synth/detail/root_motion.h"
#include "motionmap/synth/detail/smoothing.h"

namespace motionmap::synth {

namespace {

// Frames blended per block (between progress reports and cancel polls), and located at a time
// in the local mode.
constexpr int kBlockFrames = 256;
// Blocks whose samples a blender reading its clips on demand reads together; no further block is
// added once they hold over kMaxSpanWeights weights (dense kriging weights: after one or two).
constexpr int kPrefetchBlocks = 8;
constexpr std::size_t kMaxSpanWeights = 4'000'000;
constexpr std::size_t kLocateFrames = 1024;
// Most kriging weights the smoothing window may hold (each a dense vector over the samples).
constexpr long long kMaxWindowWeights = 50'000'000;

// The motion of `frames` frames at `dt` whose weights weights_of(first, count) gives (frames
// first, first + 1, …: at least count of them, more if it likes), asked for block by block as the
// smoothing window moves on (see the top of synthesize.h).
SynthResult synthesize_frames(
    const MapBlender& blender, long long frames, double dt,
    const std::function<std::vector<MapWeights>(long long, long long)>& weights_of,
    const SynthOptions& options, const Control& control);

}  // namespace

void SynthOptions::validate() const {
  if (!(speed >= 0.0) || !std::isfinite(speed)) {
    throw ParameterError("speed: " + format_number(speed) +
                         " is out of range (map units per second, ≥ 0; 0 = the clip's)");
  }
  if (!(fps >= 0.0 && fps <= 1000.0)) {
    throw ParameterError("fps: " + format_number(fps) +
                         " is out of range (must be in (0, 1000]; 0 = the clip's)");
  }
  if (!(smooth >= 0.0 && smooth <= kMaxSmoothSeconds)) {
    throw ParameterError("smooth: " + format_number(smooth) +
                         " s is out of range (must be in [0, " + format_number(kMaxSmoothSeconds) +
                         "])");
  }
}

std::string outside_frames_note(const SynthResult& result) {
  std::string note;
  const int edge = result.clamped_frames - result.routed_frames;
  if (result.routed_frames > 0) {
    note +=
        std::to_string(result.routed_frames) + " play the clips' own frames along the path there";
  }
  if (edge > 0) {
    note += (note.empty() ? "" : ", ") + std::to_string(edge) +
            " were blended at the nearest edge of the data";
  }
  return note;
}

SynthResult synthesize(const MapBlender& blender, const MapPath& path, const SynthOptions& options,
                       const Control& control) {
  options.validate();
  path.validate();
  double speed = options.speed;
  if (!path.timed() && speed == 0.0) {
    speed = blender.median_speed();
    if (!(speed > 0.0)) {
      throw ParameterError(
          "speed: the map has no motion to take a default speed from; give one (map units per "
          "second)");
    }
  }
  // 0 fps keeps the clip's exact frame time, so a path timed like the clip hits its samples.
  const double dt = options.fps > 0.0 ? 1.0 / options.fps : blender.frame_time();
  const std::vector<Eigen::Vector2d> points = blender.path_points(path, dt, speed, kMaxSynthFrames);
  const auto frames = static_cast<long long>(points.size());
  if (blender.options().mode != BlendMode::Local) {
    // Every frame blended where it is (routes are the local mode's), located block by block: the
    // kriging's weights are dense.
    return synthesize_frames(
        blender, frames, dt,
        [&](long long first, long long count) {
          return blender.locate_path(points, dt, static_cast<std::size_t>(first),
                                     static_cast<std::size_t>(first + count));
        },
        options, control);
  }
  // Every frame located first, kLocateFrames at a time (each call reads the frames around it
  // too: MapBlender::path_neighbours), so that the frames where a gait's blend stalls are known.
  const Control locating = control.part(0.0, 0.1);
  std::vector<MapWeights> located;
  located.reserve(points.size());
  PathFits fits;
  for (std::size_t first = 0; first < points.size(); first += kLocateFrames) {
    locating.check();
    const std::size_t end = std::min(points.size(), first + kLocateFrames);
    for (MapWeights& w : blender.locate_path(points, dt, first, end, &fits))
      located.push_back(std::move(w));
    locating.update(static_cast<double>(end) / static_cast<double>(points.size()));
  }
  // Runs of frames outside the data, far inside it, or around a stall follow the clips' own
  // frames.
  std::vector<char> stalled = detail::stalled_frames(blender, points, dt, located);
  const detail::OutsideRuns runs = detail::outside_runs(
      blender, points, stalled, detail::stall_spread(dt), blender.follow_neighbours(dt));
  const detail::OutsideRoutes outside(blender, points, dt, runs, 0, points.size(),
                                      control.part(0.1, 0.2), located);
  for (std::size_t k = 0; k < located.size(); ++k) outside.apply(k, located[k]);
  SynthResult result = synthesize_frames(
      blender, frames, dt,
      [&](long long first, long long count) {
        return std::vector<MapWeights>(std::make_move_iterator(located.begin() + first),
                                       std::make_move_iterator(located.begin() + first + count));
      },
      options, control.part(0.2, 1.0));
  result.routed_frames = detail::routed_outside(runs, result.validity);
  if (std::string note = detail::stalled_note(stalled, result.validity); !note.empty())
    result.notes.insert(result.notes.begin(), std::move(note));
  result.stalled = std::move(stalled);
  result.fits = std::move(fits);
  return result;
}

SynthResult synthesize(const MapBlender& blender, std::span<const MapWeights> weights,
                       const SynthOptions& options, const Control& control) {
  options.validate();
  if (weights.empty()) throw ParameterError("synthesize: no frames' weights given");
  if (static_cast<long long>(weights.size()) > kMaxSynthFrames) {
    throw ParameterError("synthesize: " + std::to_string(weights.size()) +
                         " frames, more than the limit of " + std::to_string(kMaxSynthFrames));
  }
  for (std::size_t k = 0; k < weights.size(); ++k) {
    const MapWeights& w = weights[k];
    bool fine = !w.samples.empty() && w.samples.size() == w.weights.size();
    for (std::size_t i = 0; fine && i < w.samples.size(); ++i) {
      fine = w.samples[i] >= 0 && w.samples[i] < blender.num_samples() &&
             (i == 0 || w.samples[i] > w.samples[i - 1]) && std::isfinite(w.weights[i]);
    }
    if (!fine) {
      throw ParameterError("synthesize: frame " + std::to_string(k) +
                           "'s weights are not one finite weight per sample of the map, the "
                           "samples increasing");
    }
  }
  const double dt = options.fps > 0.0 ? 1.0 / options.fps : blender.frame_time();
  return synthesize_frames(
      blender, static_cast<long long>(weights.size()), dt,
      [&](long long first, long long count) {
        return std::vector<MapWeights>(weights.begin() + first, weights.begin() + first + count);
      },
      options, control);
}

namespace {

SynthResult synthesize_frames(
    const MapBlender& blender, long long frames, double dt,
    const std::function<std::vector<MapWeights>(long long, long long)>& weights_of,
    const SynthOptions& options, const Control& control) {
  // The Gaussian kernel over ±3σ frames.
  const std::vector<double> kernel = detail::smoothing_kernel(options.smooth, dt, frames);
  const auto half = static_cast<long long>(kernel.size() / 2);
  if (blender.options().mode == BlendMode::Kriging && half > 0 &&
      (2 * half + 1 + kBlockFrames) * blender.num_samples() > kMaxWindowWeights) {
    throw ParameterError("smooth: " + format_number(options.smooth) + " s spans " +
                         std::to_string(2 * half + 1) + " frames of dense kriging weights over " +
                         std::to_string(blender.num_samples()) +
                         " samples, more than the limit of " + std::to_string(kMaxWindowWeights) +
                         " weights; use less smoothing or the local mode");
  }

  const Skeleton& skeleton = blender.skeleton();
  const int J = skeleton.num_joints();
  SynthResult result;
  // Feet to clean: the blending takes the first 90 % of the progress, the clean-up the rest.
  std::optional<Feet> feet;
  if (options.clean_feet) {
    std::string why;
    feet = try_find_feet(skeleton, blender.options().up, &why);
    if (!feet) result.notes.push_back("feet not cleaned: " + why);
  }
  const Control blending = feet ? control.part(0.0, 0.9) : control;
  result.motion.frame_time = dt;
  result.motion.resize(static_cast<int>(frames), J);
  result.validity.resize(static_cast<std::size_t>(frames));
  std::vector<Eigen::Vector3d> velocity(static_cast<std::size_t>(frames));
  std::vector<double> yaw_rate(static_cast<std::size_t>(frames));
  result.heading_offsets.resize(static_cast<std::size_t>(frames));
  std::vector<std::array<double, 2>> shares(static_cast<std::size_t>(frames));
  std::atomic<bool> shares_known = true;

  // Raw weights of frames [raw_first, raw_first + raw.size()), computed ahead as the window needs.
  std::deque<MapWeights> raw;
  long long raw_first = 0;
  // The weights blended at frames [span_first, span_first + blended.size()) and those frames'
  // validity (of their own, raw weights): the smoothing moves each neighbour's weights along its
  // clips, onto samples of its own. One block's, or on a blender reading its clips on demand up
  // to kPrefetchBlocks blocks', whose samples are read together first, each clip once (a
  // sketch's consecutive blocks blend mostly the same clips; of the raw weights only, the samples
  // the smoothing moves onto would be read frame by frame, a whole clip each).
  std::vector<MapWeights> blended;
  std::vector<PointValidity> span_validity;
  long long span_first = 0;
  const auto add_block = [&](long long k0, long long k1) {
    const long long need_first = std::max(0LL, k0 - half), need_end = std::min(frames, k1 + half);
    while (raw_first < need_first && !raw.empty()) {
      raw.pop_front();
      ++raw_first;
    }
    const long long have_end = raw_first + static_cast<long long>(raw.size());
    if (have_end < need_end) {
      for (auto& w : weights_of(have_end, need_end - have_end)) raw.push_back(std::move(w));
    }
    const std::size_t at = blended.size();
    blended.resize(at + static_cast<std::size_t>(k1 - k0));
    for (long long k = k0; k < k1; ++k)
      span_validity.push_back(raw[static_cast<std::size_t>(k - raw_first)].validity);
    if (half > 0) {
      parallel_for(static_cast<int>(k1 - k0), [&](int i) {
        blended[at + static_cast<std::size_t>(i)] =
            detail::smoothed(raw, raw_first, k0 + i, frames, kernel, dt, blender);
      });
    } else {
      // No later block reads these (the window is the block itself).
      std::move(raw.begin() + static_cast<std::ptrdiff_t>(k0 - raw_first),
                raw.begin() + static_cast<std::ptrdiff_t>(k1 - raw_first), blended.begin() + at);
    }
  };
  const long long span_frames =
      static_cast<long long>(blender.reads_on_demand() ? kPrefetchBlocks : 1) * kBlockFrames;
  for (long long k0 = 0; k0 < frames; k0 += kBlockFrames) {
    blending.check();
    const long long k1 = std::min(frames, k0 + kBlockFrames);
    if (k0 >= span_first + static_cast<long long>(blended.size())) {
      span_first = k0;
      blended.clear();
      span_validity.clear();
      const long long span_end = std::min(frames, k0 + span_frames);
      std::size_t held = 0;  // weights in `blended`
      for (long long b0 = k0; b0 < span_end && held <= kMaxSpanWeights; b0 += kBlockFrames) {
        if (b0 > k0) blending.check();
        const std::size_t at = blended.size();
        add_block(b0, std::min(span_end, b0 + kBlockFrames));
        for (std::size_t i = at; i < blended.size(); ++i) held += blended[i].samples.size();
      }
      if (blender.reads_on_demand()) blender.prefetch(blended);
    }
    parallel_for(static_cast<int>(k1 - k0), [&](int i) {
      const long long k = k0 + i;
      const auto at = static_cast<std::size_t>(k - span_first);
      const MapWeights& weights = blended[at];
      const BlendedFrame b = blender.blend(weights);
      if (const auto share = blender.contact_share(weights)) {
        shares[static_cast<std::size_t>(k)] = *share;
      } else {
        shares_known = false;
      }
      for (int j = 0; j < J; ++j) {
        result.motion.rotation(static_cast<int>(k), j) = b.rotations[j];
        result.motion.translation(static_cast<int>(k), j) = b.translations[j];
      }
      velocity[static_cast<std::size_t>(k)] = b.velocity;
      yaw_rate[static_cast<std::size_t>(k)] = b.yaw_rate;
      result.heading_offsets[static_cast<std::size_t>(k)] = b.heading_offset;
      result.validity[static_cast<std::size_t>(k)] = span_validity[at];
    });
    blending.update(static_cast<double>(k1) / static_cast<double>(frames));
  }

  // Root motion: integrate the heading-local velocity and yaw rate from the origin, facing
  // heading 0 (the turning starts at minus frame 0's sway).
  const int root = blender.motion_root();
  const Axis up = blender.options().up;
  // With clean feet, a planted foot stays where it stands and the root moves with it (the blend
  // of several stances glides over the floor: its velocity is not what its legs do).
  const std::vector<detail::FeetFrame> standing =
      feet && shares_known ? detail::feet_frames(skeleton, result.motion, root, *feet, shares)
                           : std::vector<detail::FeetFrame>{};
  result.options = options;
  result.root_positions.resize(static_cast<std::size_t>(frames));
  result.headings.resize(static_cast<std::size_t>(frames));
  const detail::RootState start{Eigen::Vector3d::Zero(),
                                frames > 0 ? -result.heading_offsets.front() : 0.0};
  detail::integrate_root(start, velocity, yaw_rate, result.heading_offsets, dt, standing, up,
                         result.root_positions, result.headings);
  for (long long k = 0; k < frames; ++k) {
    const auto ks = static_cast<std::size_t>(k);
    Eigen::Quaterniond& q = result.motion.rotation(static_cast<int>(k), root);
    q = (axis_rotation(up, result.headings[ks]) * q).normalized();
    result.motion.translation(static_cast<int>(k), root) += result.root_positions[ks];
  }
  for (const PointValidity& v : result.validity) result.clamped_frames += v.clamped ? 1 : 0;
  if (shares_known) result.contact_shares = std::move(shares);

  if (feet) {
    CleanFeetOptions clean;
    clean.contacts.up = up;
    // Contacts from the blend weights when the blender knows its samples' contacts.
    CleanFeetResult cleaned =
        result.contact_shares.empty()
            ? clean_feet(skeleton, result.motion, *feet, clean, control.part(0.9, 1.0))
            : clean_feet_from_shares(skeleton, result.motion, *feet, result.contact_shares, clean,
                                     control.part(0.9, 1.0));
    result.motion = std::move(cleaned.motion);
    result.feet_cleaned = true;
    result.contacts.assign(cleaned.contacts.begin(), cleaned.contacts.end());
    result.feet_frames_changed = cleaned.frames_changed;
    result.feet_changed = std::move(cleaned.changed);
    if (std::string note = unreachable_feet_note(cleaned); !note.empty()) {
      result.notes.push_back(std::move(note));
    }
  }
  return result;
}

}  // namespace

}  // namespace motionmap::synth
