// MapBlender glues the pieces of synth/detail together: the map index (merged map points, k-d
// tree, reach), the kriging systems (global or local), the root motion of every sample, and the
// weighted blend of the samples' poses.
#include "motionmap/synth/blender.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/synth/detail/gait_phase.h"
#include "motionmap/synth/detail/kriging.h"
#include "motionmap/synth/detail/map_index.h"
#include "motionmap/synth/detail/smoothing.h"
#include "motionmap/synth/detail/strokes.h"

namespace motionmap::synth {

namespace {

// A path's frame time, checked for `who` (locate_path, path_neighbours).
void check_frame_time(const char* who, double frame_time) {
  if (!(frame_time > 0.0) || !std::isfinite(frame_time)) {
    throw ParameterError(std::string(who) + ": frame time " + format_number(frame_time) +
                         " is not positive and finite");
  }
}

// The half-width, in frames, of the window locate_path() fits clip times to.
long long follow_half_window(double dt) {
  return std::max(1LL, std::llround(std::min(kFollowSeconds / dt, 1e9)));
}

// Local systems pick neighbours at least this fraction of the median step apart, so 120 fps
// samples almost on top of each other do not make them ill-conditioned.
constexpr double kSeparationFraction = 0.25;
// Kriging queries are solved in blocks of this many points (bounds the right-hand-side memory).
constexpr int kKrigingBlock = 64;

// Where the runs of one clip start in `items` (sorted by clip), and items.size() last: items
// [starts[g], starts[g + 1]) are one clip's.
template <class Items, class ClipOf>
std::vector<std::size_t> clip_groups(const Items& items, ClipOf clip_of) {
  std::vector<std::size_t> starts{0};
  for (std::size_t i = 1; i < items.size(); ++i)
    if (clip_of(items[i]) != clip_of(items[i - 1])) starts.push_back(i);
  starts.push_back(items.size());
  return starts;
}

bool same_translation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() <= 1e-12 * (1.0 + a.norm());
}

// The map rows' checks of both constructors: as many clip and frame indices and coordinate rows as
// samples, each sample a frame of a clip there is (`frames[c]`: clip c's frame count; `name(c)`:
// how an error names it; `clips_held`: the clips there are, in words), finite coordinates.
void check_rows(const features::FeatureSet& samples, const Eigen::MatrixXd& coords,
                std::span<const int> frames, const std::function<std::string(int)>& name,
                const std::string& clips_held) {
  const int n = samples.num_samples();
  const int num_clips = static_cast<int>(frames.size());
  if (static_cast<int>(samples.clip_of.size()) != n ||
      static_cast<int>(samples.frame_of.size()) != n) {
    throw ParameterError("map: the feature set has " + std::to_string(samples.clip_of.size()) +
                         " clip and " + std::to_string(samples.frame_of.size()) +
                         " frame indices for " + std::to_string(n) + " samples");
  }
  if (coords.rows() != n) {
    throw ParameterError("map: it has " + std::to_string(coords.rows()) +
                         " rows but the features have " + std::to_string(n) +
                         " samples; the map does not belong to these clips");
  }
  if (coords.cols() < 2) {
    throw ParameterError("map: it has " + std::to_string(coords.cols()) +
                         " column(s); at least 2 are needed");
  }
  for (int i = 0; i < n; ++i) {
    const int c = samples.clip_of[std::size_t(i)];
    if (c < 0 || c >= num_clips) {
      throw ParameterError("map: sample " + std::to_string(i) + " belongs to clip " +
                           std::to_string(c) + " but " + clips_held);
    }
    const int f = samples.frame_of[std::size_t(i)];
    if (f < 0 || f >= frames[std::size_t(c)]) {
      throw ParameterError("map: sample " + std::to_string(i) + " is frame " + std::to_string(f) +
                           " of " + name(c) + ", which has " +
                           std::to_string(frames[std::size_t(c)]) +
                           " frames; the map does not belong to these clips");
    }
    if (!std::isfinite(coords(i, 0)) || !std::isfinite(coords(i, 1))) {
      throw NumericalError("map: row " + std::to_string(i) + " holds a NaN or infinite coordinate");
    }
  }
}

// The constructor's checks of its arguments (see blender.h for what they reject).
void check_inputs(std::span<const Clip> clips, const features::FeatureSet& samples,
                  const Eigen::MatrixXd& coords, const BlendOptions& options) {
  const int n = samples.num_samples();
  if (n < 1) throw ParameterError("map: the feature set has no samples");
  options.validate(n);
  if (clips.empty()) throw ParameterError("map: no clip given");
  const Skeleton& skeleton = clips.front().skeleton;
  for (const Clip& clip : clips) {
    if (!clip.skeleton.same_hierarchy(skeleton)) {
      throw ParameterError(clip.path + ": its joint hierarchy differs from " + clips.front().path +
                           "'s; clips blended together must share one");
    }
    check_clip(clip);
  }
  std::vector<int> frames;
  for (const Clip& clip : clips) frames.push_back(clip.motion.num_frames);
  check_rows(
      samples, coords, frames, [&](int c) { return clips[std::size_t(c)].path; },
      "only " + std::to_string(clips.size()) + " clip(s) were given");
}

}  // namespace

namespace {
constexpr EnumName<BlendMode> kBlendModes[] = {{BlendMode::Local, "local"},
                                               {BlendMode::Kriging, "kriging"},
                                               {BlendMode::Idw, "idw"},
                                               {BlendMode::Gp, "gp"}};
}  // namespace

std::string_view blend_mode_name(BlendMode mode) {
  return enum_name(kBlendModes, mode);
}

std::optional<BlendMode> parse_blend_mode(std::string_view name) {
  return parse_enum(kBlendModes, name);
}

const std::vector<BlendMode>& all_blend_modes() {
  static const std::vector<BlendMode> modes = enum_values(kBlendModes);
  return modes;
}

double reach_radius(double reach, double median_step, double map_size) {
  return std::max(reach * median_step, kMinReachFraction * map_size);
}

void franke_little_weights(const double* d, int count, double R, double* phi) {
  // A distance below this fraction of R counts as a hit on the sample (the weight would
  // overflow; the weights it replaces differ by < 1e-24).
  constexpr double kHitFraction = 1e-12;
  std::fill(phi, phi + count, 0.0);
  if (count == 1 || d[0] <= kHitFraction * R) {
    phi[0] = 1.0;
    return;
  }
  double sum = 0.0;
  for (int i = 0; i < count; ++i) {
    const double t = std::max(R - d[i], 0.0) / (R * d[i]);
    phi[i] = t * t;
    sum += phi[i];
  }
  if (sum > 0.0) {
    for (int i = 0; i < count; ++i) phi[i] /= sum;
    return;
  }
  // Every point exactly at R (a tie with the next one): share equally between the nearest.
  int ties = 0;
  while (ties < count && d[ties] == d[0]) ++ties;
  for (int i = 0; i < ties; ++i) phi[i] = 1.0 / ties;
}

void BlendOptions::validate(int num_samples) const {
  if (mode == BlendMode::Gp && !gplvm) {
    throw ParameterError(
        "blend: the gp mode blends with a GP-LVM map's predictive mean; this map is not a GP-LVM "
        "map (use local, kriging or idw)");
  }
  if (gplvm && gplvm->num_frames() != num_samples) {
    throw ParameterError("blend: the GP-LVM map's GP has " + std::to_string(gplvm->num_frames()) +
                         " frames but the map " + std::to_string(num_samples) + " samples");
  }
  if ((mode == BlendMode::Local || mode == BlendMode::Idw) &&
      (neighbors < 1 || neighbors > num_samples)) {
    throw ParameterError("neighbors: " + std::to_string(neighbors) +
                         " is out of range (must be in [1, " + std::to_string(num_samples) +
                         "], the map's sample count)");
  }
  if (!(reach > 0.0) || !std::isfinite(reach)) {
    throw ParameterError("reach: " + format_number(reach) +
                         " is out of range (must be a finite number > 0)");
  }
  if (up != Axis::X && up != Axis::Y && up != Axis::Z) throw ParameterError("up: not an axis");
  if (kept_states < 1) {
    throw ParameterError("kept_states: " + std::to_string(kept_states) +
                         " is out of range (must be ≥ 1)");
  }
}

ClipsSummary summarize_clips(int num_clips,
                             const std::function<std::shared_ptr<const Clip>(int)>& clip_at,
                             const features::FeatureSet& samples, const Control& control) {
  if (num_clips < 1) throw ParameterError("map: no clip given");
  const int n = samples.num_samples();
  if (n < 1 || samples.clip_of.size() != samples.frame_of.size())
    throw ParameterError("map: the feature set has no samples, or not one clip per frame index");
  for (int i = 0; i < n; ++i) {
    if (samples.clip_of[i] < 0 || samples.clip_of[i] >= num_clips) {
      throw ParameterError("map: sample " + std::to_string(i) + " belongs to clip " +
                           std::to_string(samples.clip_of[i]) + " but only " +
                           std::to_string(num_clips) + " clip(s) were given");
    }
  }
  ClipsSummary out;
  // Translations are compared with the first sample's (as the blender keeps them).
  const std::shared_ptr<const Clip> first = clip_at(samples.clip_of[0]);
  const std::shared_ptr<const Clip> clip0 = samples.clip_of[0] == 0 ? first : clip_at(0);
  const Skeleton& skeleton = clip0->skeleton;
  const int J = skeleton.num_joints();
  std::vector<Eigen::Vector3d> t0(static_cast<std::size_t>(J));
  for (int j = 0; j < J; ++j) t0[j] = first->motion.translation(samples.frame_of[0], j);
  // The samples of each clip (counting sort by clip).
  std::vector<int> start(static_cast<std::size_t>(num_clips) + 1, 0);
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) ++start[static_cast<std::size_t>(samples.clip_of[i]) + 1];
  for (int c = 0; c < num_clips; ++c) start[c + 1] += start[c];
  {
    std::vector<int> next(start.begin(), start.end() - 1);
    for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(next[samples.clip_of[i]]++)] = i;
  }
  // Per clip, on the pool's threads (a clip read each): its frames, frame time, motion root and
  // the joints whose translation varies from the first sample's; combined in clip order (of
  // several clips it cannot use, parallel_for throws the first one's error).
  struct Of {
    int frames = 0, root = 0;
    double frame_time = 0.0;
    std::vector<char> varies;
  };
  std::vector<Of> of(static_cast<std::size_t>(num_clips));
  parallel_for(
      num_clips,
      [&](int c) {
        const std::shared_ptr<const Clip> clip = c == 0 ? clip0 : clip_at(c);
        if (!clip->skeleton.same_hierarchy(skeleton)) {
          throw ParameterError(clip->path + ": its joint hierarchy differs from " + clip0->path +
                               "'s; clips blended together must share one");
        }
        Of& o = of[static_cast<std::size_t>(c)];
        o.frames = clip->motion.num_frames;
        o.frame_time = clip->motion.frame_time;
        o.root = motion_root(clip->skeleton, clip->motion);
        o.varies.assign(static_cast<std::size_t>(J), 0);
        for (int k = start[c]; k < start[c + 1]; ++k) {
          const int i = order[k];
          if (samples.frame_of[i] < 0 || samples.frame_of[i] >= clip->motion.num_frames) {
            throw ParameterError("map: sample " + std::to_string(i) + " is frame " +
                                 std::to_string(samples.frame_of[i]) + " of " + clip->path +
                                 ", which has " + std::to_string(clip->motion.num_frames) +
                                 " frames");
          }
          for (int j = 0; j < J; ++j) {
            if (!o.varies[j]) {
              o.varies[j] =
                  !same_translation(clip->motion.translation(samples.frame_of[i], j), t0[j]);
            }
          }
        }
      },
      control.stage("summarising clips", 0.0, 1.0));
  // The deepest of the clips' motion roots: each clip's lies on the chain from the skeleton's
  // root down to it, so folding its ancestors into it (blend_state.h) carries every clip's
  // travel, whichever joint of the chain a clip moves.
  int root = 0;
  std::vector<char> varies(static_cast<std::size_t>(J), 0);
  for (int c = 0; c < num_clips; ++c) {
    const Of& o = of[static_cast<std::size_t>(c)];
    out.frames.push_back(o.frames);
    out.frame_times.push_back(o.frame_time);
    root = c == 0 ? o.root : std::max(root, o.root);
    for (int j = 0; j < J; ++j) varies[j] = varies[j] || o.varies[j];
  }
  out.motion_root = root;
  const std::vector<int> ancestors = root_ancestors(skeleton, root);
  for (int j = 0; j < J; ++j) {
    if (j != root && varies[j] &&
        std::find(ancestors.begin(), ancestors.end(), j) == ancestors.end())
      out.moving.push_back(j);
  }
  return out;
}

ClipsSummary summarize_clips(std::span<const Clip> clips, const features::FeatureSet& samples) {
  return summarize_clips(
      static_cast<int>(clips.size()),
      [&](int c) {
        // Not owned: the clips outlive the call.
        return std::shared_ptr<const Clip>(std::shared_ptr<const Clip>(), &clips[c]);
      },
      samples);
}

namespace {

// The clip times a path frame follows (locate_path): each's run (its first sample), seconds into
// it and share of the clips' part (the shares sum to 1), and that part of the blend (0: the
// kriging's alone).
struct FollowFit {
  int run = 0;
  double seconds = 0.0, share = 0.0;
};
struct Follow {
  double share = 0.0;
  std::vector<FollowFit> fits;
};

std::uint64_t next_blender_id() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

bool same_points(std::span<const Eigen::Vector2d> a, std::span<const Eigen::Vector2d> b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Eigen::Vector2d)) == 0);
}

}  // namespace

namespace detail {

struct PathFitsData {
  std::uint64_t blender = 0;
  double dt = 0.0;
  std::vector<Eigen::Vector2d> points;
  // Per frame: whether it was fitted, and if so where it was evaluated and its blend's sources
  // (not registered).
  std::vector<char> known;
  std::vector<PointValidity> validity;
  std::vector<std::vector<PhaseSource>> sources;
};

}  // namespace detail

std::size_t PathFits::size() const {
  return m ? static_cast<std::size_t>(std::count(m->known.begin(), m->known.end(), 1)) : 0;
}

struct MapBlender::Impl {
  // Which blender made a PathFits (ids are never reused).
  std::uint64_t id = next_blender_id();
  BlendOptions options;
  Skeleton skeleton;
  double frame_time = 0.0;
  int joints = 0;
  int motion_root = 0;
  int n = 0;  // samples

  // Per sample, precomputed so a query only sums (given every clip; empty with a source).
  std::vector<Eigen::Quaterniond> rotations;  // #samples × #joints; the motion root's is its tilt
  std::vector<int> moving;     // joints other than the motion root whose translation varies
  std::vector<int> ancestors;  // the motion root's, folded into it (blend_state.h)
  std::vector<Eigen::Vector3d> moving_translations;  // #samples × moving.size()
  // #joints: sample 0's (blend_states() sets the motion root's and its ancestors')
  std::vector<Eigen::Vector3d> fixed_translations;
  std::vector<double> height;
  std::vector<Eigen::Vector3d> velocity;  // heading-local floor velocity, units/s
  std::vector<double> yaw_rate;           // rad/s
  std::vector<double> heading_offset;     // rad
  // The skeleton's feet (none: no contacts are known). Per sample: bit 0 the left foot, bit 1 the
  // right foot in contact with the floor in its clip (detect_contacts); read on demand, in the
  // sample's state instead.
  std::optional<Feet> feet;
  std::vector<std::uint8_t> contacts;
  // Given every clip: per clip, its feet's contacts, for its gait phase (detail/gait_phase.h).
  std::vector<std::array<FootContacts, 2>> clip_contacts;
  // Whether a clip may have a gait phase (given every clip: one has; from a source: the skeleton
  // has feet), so that locate_path() registers phases.
  bool gait = false;
  // The gait phase of each run of samples (by its first sample) followed so far.
  mutable std::mutex phase_mutex;
  mutable std::unordered_map<int, detail::GaitPhase> phases;

  // Each sample's clip. Made from a ClipSource: the clips, read when a blend needs their frames,
  // each sample's frame and each clip's frame count.
  std::vector<int> clip_of;
  std::shared_ptr<const ClipSource> source;
  std::vector<int> frame_of, clip_frames;
  // The states of the samples blended so far (read from their clips), by sample.
  struct KeptState {
    SampleState state;
    std::uint8_t contact = 0;  // as `contacts`
  };
  mutable std::mutex state_mutex;
  mutable std::unordered_map<int, KeptState> states;

  std::optional<detail::MapIndex> index;
  std::optional<detail::LocalKriging> local;     // local mode
  std::optional<detail::GlobalKriging> kriging;  // kriging mode

  void build_samples(std::span<const Clip> clips, const features::FeatureSet& samples);
  // Where p is evaluated, by the map's one rule (blender.h): the GP's on a GP-LVM map, else the
  // index's reach.
  PointValidity validate(const Eigen::Vector2d& p) const;
  // The gp mode's weights at v.point (blender.h).
  MapWeights gp_weights(const PointValidity& v) const;
  // Point weights (point index, weight) at v.point; sets v.variance (not on a GP-LVM map, whose
  // variance is the GP's). Not for kriging.
  void point_weights(PointValidity& v, std::vector<std::pair<int, double>>& out) const;
  // locate_path()'s clips (blender.h): the clip times whose trajectory the path `points` (one
  // every dt seconds) follows around frame k, and their share of the blend there.
  Follow follow_clips(std::span<const Eigen::Vector2d> points, std::size_t k, double dt) const;
  // Frame k of a path located (local mode): where it was evaluated, and its blend (the clip times
  // followed and the kriging's samples) as `sources`, not registered (detail/gait_phase.h).
  PointValidity path_frame(std::span<const Eigen::Vector2d> points, std::size_t k, double dt,
                           detail::PhaseFrame& sources) const;
  // locate_path() in the local mode: frames [first, end) of a path located, their gait phases
  // registered (detail/gait_phase.h); with `fits` (for these points), the frames it knows taken
  // from it and the others added to it.
  std::vector<MapWeights> locate_path(std::span<const Eigen::Vector2d> points, std::size_t first,
                                      std::size_t end, double dt, detail::PathFitsData* fits) const;
  // The fits of `held` that hold for the path `points` (frame time dt, this blender), in data the
  // caller alone holds: all of them where held describes this path; else those of the frames
  // whose points within follow_half_window(dt) are the same in both paths.
  std::shared_ptr<detail::PathFitsData> fits_for(
      const std::shared_ptr<const detail::PathFitsData>& held,
      std::span<const Eigen::Vector2d> points, double dt) const;
  // The contacts of a clip's feet (the skeleton has feet).
  std::array<FootContacts, 2> feet_contacts(const Clip& clip) const {
    ContactOptions co;
    co.up = options.up;
    return detect_contacts(clip.skeleton, clip.motion, *feet, co);
  }
  // The gait phase of the run of samples starting at sample `run` (none without feet).
  const detail::GaitPhase& phase_of(int run) const;
  // Made from a ClipSource: the gait phases of these runs not known yet, each clip read once, the
  // clips on the pool's threads (so register_phases() then reads none).
  void read_phases(std::vector<int> runs) const;
  // The weights at v.point in every mode but kriging (the gp mode's or the point weights').
  MapWeights weights(const PointValidity& v) const;
  // Kriging weights of the points out[c].validity.point, into out.
  void kriging_block(std::span<MapWeights> out) const;
  // With a source: the state of `samples` (as sample_state() gives it, one after another),
  // reading the clips of those not read before, each once, on the pool's threads, and keeping
  // their states.
  void read_samples(std::span<const int> samples, std::vector<Eigen::Quaterniond>& rotations,
                    std::vector<Eigen::Vector3d>& translations, std::vector<double>& heights,
                    std::vector<Eigen::Vector3d>& velocities, std::vector<double>& yaw_rates,
                    std::vector<double>& heading_offsets) const;
  // The index, and the local systems or the kriging system (`lazy`: local systems on demand).
  void build_systems(const Eigen::MatrixXd& coords, const features::FeatureSet& samples,
                     std::span<const double> frame_times, bool lazy, const Control& control);
};

void MapBlender::Impl::build_samples(std::span<const Clip> clips,
                                     const features::FeatureSet& samples) {
  const int J = joints;
  const auto uJ = static_cast<std::size_t>(J);
  const ClipsSummary summary = summarize_clips(clips, samples);
  motion_root = summary.motion_root;
  moving = summary.moving;
  ancestors = synth::root_ancestors(clips.front().skeleton, motion_root);
  const int r = motion_root;

  const auto un = static_cast<std::size_t>(n);
  const std::size_t mv = moving.size();
  rotations.resize(un * uJ);
  height.resize(un);
  velocity.resize(un);
  yaw_rate.resize(un);
  heading_offset.resize(un);
  moving_translations.resize(un * mv);
  parallel_for(n, [&](int i) {
    const auto ui = static_cast<std::size_t>(i);
    sample_state(clips[samples.clip_of[i]].motion, samples.frame_of[i], r, options.up, moving,
                 ancestors, rotations.data() + ui * uJ, moving_translations.data() + ui * mv,
                 height[ui], velocity[ui], yaw_rate[ui], heading_offset[ui]);
  });
  // The samples' contacts, from their own clips (captured feet are found reliably there).
  feet = try_find_feet(clips.front().skeleton, options.up);
  if (feet) {
    std::vector<std::array<FootContacts, 2>> by_clip(clips.size());
    parallel_for(static_cast<int>(clips.size()), [&](int c) {
      by_clip[static_cast<std::size_t>(c)] = feet_contacts(clips[static_cast<std::size_t>(c)]);
    });
    contacts.resize(un);
    clip_contacts = by_clip;
    for (std::size_t c = 0; c < clips.size() && !gait; ++c)
      gait = detail::gait_phase(by_clip[c], clips[c].motion.frame_time, 0, 0.0).known();
    for (int i = 0; i < n; ++i) {
      const auto& fc = by_clip[static_cast<std::size_t>(samples.clip_of[i])];
      contacts[static_cast<std::size_t>(i)] =
          static_cast<std::uint8_t>((fc[0].in_contact(samples.frame_of[i]) ? 1 : 0) |
                                    (fc[1].in_contact(samples.frame_of[i]) ? 2 : 0));
    }
  }
  const Motion& m0 = clips[samples.clip_of[0]].motion;
  fixed_translations.resize(uJ);
  for (int j = 0; j < J; ++j) fixed_translations[j] = m0.translation(samples.frame_of[0], j);
}

void MapBlender::Impl::read_samples(std::span<const int> samples,
                                    std::vector<Eigen::Quaterniond>& rots,
                                    std::vector<Eigen::Vector3d>& translations,
                                    std::vector<double>& heights,
                                    std::vector<Eigen::Vector3d>& velocities,
                                    std::vector<double>& yaw_rates,
                                    std::vector<double>& heading_offsets) const {
  const std::size_t count = samples.size(), uJ = static_cast<std::size_t>(joints),
                    mv = moving.size();
  rots.resize(count * uJ);
  translations.resize(count * mv);
  heights.resize(count);
  velocities.resize(count);
  yaw_rates.resize(count);
  heading_offsets.resize(count);
  // Entry k of the outputs: `st`.
  const auto put = [&](std::size_t k, const SampleState& st) {
    std::copy(st.rotations.begin(), st.rotations.end(), rots.begin() + k * uJ);
    std::copy(st.translations.begin(), st.translations.end(), translations.begin() + k * mv);
    heights[k] = st.height;
    velocities[k] = st.velocity;
    yaw_rates[k] = st.yaw_rate;
    heading_offsets[k] = st.heading_offset;
  };
  // The states read before; the others, by clip.
  std::vector<std::pair<int, std::size_t>> missing;  // (clip, entry)
  {
    const std::lock_guard lock(state_mutex);
    for (std::size_t k = 0; k < count; ++k) {
      const auto hit = states.find(samples[k]);
      if (hit == states.end()) {
        missing.emplace_back(clip_of[static_cast<std::size_t>(samples[k])], k);
        continue;
      }
      put(k, hit->second.state);
    }
  }
  if (missing.empty()) return;
  std::sort(missing.begin(), missing.end());
  // The clips, read on the pool's threads (a 4.5 MB BVH takes ~45 ms to parse).
  const std::vector<std::size_t> group =
      clip_groups(missing, [](const std::pair<int, std::size_t>& m) { return m.first; });
  std::vector<std::vector<std::pair<int, KeptState>>> read(group.size() - 1);
  parallel_for(static_cast<int>(read.size()), [&](int g) {
    const int c = missing[group[static_cast<std::size_t>(g)]].first;
    // Each clip is held only while its samples' states are taken.
    const std::shared_ptr<const Clip> clip = source->clip(c);
    if (!clip->skeleton.same_hierarchy(skeleton)) {
      throw ParameterError(clip->path +
                           ": its joint hierarchy differs from the map's first clip's; clips "
                           "blended together must share one");
    }
    if (clip->motion.num_frames != clip_frames[static_cast<std::size_t>(c)]) {
      throw ParameterError(clip->path + ": it has " + std::to_string(clip->motion.num_frames) +
                           " frames, the map's clip " + std::to_string(c) + " " +
                           std::to_string(clip_frames[static_cast<std::size_t>(c)]));
    }
    std::array<FootContacts, 2> clip_contacts;
    if (feet) clip_contacts = feet_contacts(*clip);
    for (std::size_t b = group[static_cast<std::size_t>(g)];
         b < group[static_cast<std::size_t>(g) + 1]; ++b) {
      const std::size_t k = missing[b].second;
      const int f = frame_of[static_cast<std::size_t>(samples[k])];
      KeptState kept;
      kept.state = clip_sample_state(*clip, f, motion_root, options.up, moving, ancestors);
      put(k, kept.state);
      if (feet) {
        kept.contact = static_cast<std::uint8_t>((clip_contacts[0].in_contact(f) ? 1 : 0) |
                                                 (clip_contacts[1].in_contact(f) ? 2 : 0));
      }
      read[static_cast<std::size_t>(g)].emplace_back(samples[k], std::move(kept));
    }
  });
  std::size_t count_read = 0;
  for (const auto& r : read) count_read += r.size();
  const std::lock_guard lock(state_mutex);
  if (states.size() + count_read > static_cast<std::size_t>(options.kept_states)) {
    // Afresh, but for the samples asked for: a prefetch's, found kept, are blended next, and
    // dropped, each frame's blend would read their clips again, frame by frame.
    const std::unordered_set<int> asked(samples.begin(), samples.end());
    std::erase_if(states, [&](const auto& kept) { return !asked.contains(kept.first); });
  }
  for (auto& r : read)
    for (auto& [i, st] : r) states.emplace(i, std::move(st));
}

void MapBlender::Impl::build_systems(const Eigen::MatrixXd& coords,
                                     const features::FeatureSet& samples,
                                     std::span<const double> frame_times, bool lazy,
                                     const Control& control) {
  std::vector<Eigen::Vector2d> points(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) points[i] = Eigen::Vector2d(coords(i, 0), coords(i, 1));
  index.emplace(frame_times, samples, std::move(points), options.reach);

  if (options.mode == BlendMode::Local) {
    local.emplace(*index, options.neighbors, kSeparationFraction * index->median_step(),
                  control.stage("kriging set-up", 0.0, 1.0), lazy);
  } else if (options.mode == BlendMode::Kriging) {
    const int np = index->num_points();
    if (np > kMaxKrigingSamples) {
      throw ParameterError("blend: kriging over " + std::to_string(np) +
                           " distinct map points exceeds the limit of " +
                           std::to_string(kMaxKrigingSamples) +
                           " (a dense (N+1)² system); use the local mode or a frame stride");
    }
    kriging.emplace(index->points(), control.stage("kriging set-up", 0.0, 1.0));
  } else {  // idw and gp need no systems
    control.check();
  }
}

PointValidity MapBlender::Impl::validate(const Eigen::Vector2d& p) const {
  // The nearest sample and its distance (and the check that p is finite) as on every map.
  PointValidity v = index->validate(p);
  if (!options.gplvm) return v;
  const MapGp& gp = *options.gplvm;
  v.point = p;
  v.clamped = false;
  v.variance = gp.variance(p);
  if (v.variance <= gp.threshold()) return v;
  // Outside: to the edge of the GP's region on the segment towards the nearest sample.
  v.clamped = true;
  const Eigen::Vector2d q = index->sample_point(v.nearest_sample);
  const double vq = gp.variance(q);
  if (vq > gp.threshold()) {
    v.point = q;
    v.variance = vq;
    return v;
  }
  v.point = q + gp.edge_fraction(q, p) * (p - q);
  v.variance = gp.variance(v.point);
  return v;
}

MapWeights MapBlender::Impl::gp_weights(const PointValidity& v) const {
  const Eigen::VectorXd w = options.gplvm->frame_weights(v.point);
  // The smallest magnitude kept: the smallest ones summing to at most the tolerance go.
  std::vector<double> magnitude(static_cast<std::size_t>(w.size()));
  for (Eigen::Index i = 0; i < w.size(); ++i) magnitude[std::size_t(i)] = std::abs(w[i]);
  std::sort(magnitude.begin(), magnitude.end());
  double total = 0.0;
  for (const double m : magnitude) total += m;
  double dropped = 0.0;
  std::size_t first = 0;
  while (first + 1 < magnitude.size() && dropped + magnitude[first] <= kGpWeightTolerance * total)
    dropped += magnitude[first++];
  const double cut = magnitude[first];
  MapWeights out;
  out.validity = v;
  double kept = 0.0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    if (std::abs(w[i]) < cut) continue;
    out.samples.push_back(static_cast<int>(i));
    out.weights.push_back(w[i]);
    kept += w[i];
  }
  for (double& x : out.weights) x /= kept;
  return out;
}

void MapBlender::Impl::point_weights(PointValidity& v,
                                     std::vector<std::pair<int, double>>& out) const {
  out.clear();
  const int np = index->num_points();
  const bool is_local = options.mode == BlendMode::Local;
  const int count = std::min(is_local ? kLocalPartitionSize : options.neighbors, np);
  std::vector<std::uint32_t> idx(static_cast<std::size_t>(count + 1));
  std::vector<double> dist(static_cast<std::size_t>(count + 1)),
      phi(static_cast<std::size_t>(count));
  const int found = index->nearest(v.point, count + 1, idx.data(), dist.data());
  // The partition radius: the next point's distance (a point leaving the set has weight 0);
  // with no next point, twice the farthest.
  const double R =
      found > count ? dist[count] : 2.0 * dist[found - 1] + std::numeric_limits<double>::min();
  franke_little_weights(dist.data(), count, R, phi.data());
  double variance = std::numeric_limits<double>::quiet_NaN();  // idw has none
  if (!is_local) {
    for (int i = 0; i < count; ++i) {
      if (phi[i] != 0.0) out.emplace_back(static_cast<int>(idx[i]), phi[i]);
    }
  } else {
    variance = 0.0;
    std::vector<double> rhs(static_cast<std::size_t>(local->max_hood() + 1)), sol(rhs.size());
    for (int i = 0; i < count; ++i) {
      if (phi[i] == 0.0) continue;
      const double var =
          local->predict(*index, static_cast<int>(idx[i]), v.point, phi[i], out, rhs, sol);
      variance += phi[i] * var;
    }
  }
  if (!options.gplvm) v.variance = variance;  // a GP-LVM map's is the GP's
}

void MapBlender::Impl::kriging_block(std::span<MapWeights> out) const {
  const std::size_t m = out.size();
  std::vector<Eigen::Vector2d> queries(m);
  for (std::size_t c = 0; c < m; ++c) queries[c] = out[c].validity.point;
  std::vector<double> variance(m);
  const Eigen::MatrixXd x = kriging->solve(queries, variance);
  std::vector<double> dense(static_cast<std::size_t>(n));
  for (std::size_t c = 0; c < m; ++c) {
    MapWeights& w = out[c];
    if (!options.gplvm) w.validity.variance = variance[c];  // a GP-LVM map's is the GP's
    std::fill(dense.begin(), dense.end(), 0.0);
    index->to_sample_weights(x.col(static_cast<Eigen::Index>(c)).data(), dense.data());
    w.samples.resize(static_cast<std::size_t>(n));
    w.weights = dense;
    for (int s = 0; s < n; ++s) w.samples[s] = s;
  }
}

MapBlender::MapBlender(std::span<const Clip> clips, const features::FeatureSet& samples,
                       const Eigen::MatrixXd& coords, const BlendOptions& options,
                       const Control& control)
    : m(std::make_unique<Impl>()) {
  check_inputs(clips, samples, coords, options);
  const int n = samples.num_samples();
  const Skeleton& skeleton = clips.front().skeleton;
  Impl& s = *m;
  s.options = options;
  s.skeleton = skeleton;
  s.frame_time = clips.front().motion.frame_time;
  s.joints = skeleton.num_joints();
  s.n = n;
  s.build_samples(clips, samples);
  s.clip_of = samples.clip_of;
  std::vector<double> frame_times;
  for (const Clip& clip : clips) frame_times.push_back(clip.motion.frame_time);
  s.build_systems(coords, samples, frame_times, /*lazy=*/false, control);
}

MapBlender::MapBlender(std::shared_ptr<const ClipSource> source, const ClipsSummary& summary,
                       const features::FeatureSet& samples, const Eigen::MatrixXd& coords,
                       const BlendOptions& options, const Control& control)
    : m(std::make_unique<Impl>()) {
  const int n = samples.num_samples();
  if (n < 1) throw ParameterError("map: the feature set has no samples");
  options.validate(n);
  if (options.mode == BlendMode::Kriging) {
    throw ParameterError(
        "blend: kriging blends every sample of the map; give the clips (not a clip source)");
  }
  if (!source) throw ParameterError("map: no clip source given");
  const int num_clips = static_cast<int>(summary.frames.size());
  if (num_clips < 1 || summary.frame_times.size() != summary.frames.size()) {
    throw ParameterError("map: the clips' summary has " + std::to_string(summary.frames.size()) +
                         " frame counts and " + std::to_string(summary.frame_times.size()) +
                         " frame times (need as many, at least one)");
  }
  check_rows(
      samples, coords, summary.frames, [](int c) { return "clip " + std::to_string(c); },
      "the map has " + std::to_string(num_clips) + " clip(s)");
  Impl& s = *m;
  s.options = options;
  s.n = n;
  const std::shared_ptr<const Clip> first = source->clip(0);
  check_clip(*first);
  if (first->motion.num_frames != summary.frames[0]) {
    throw ParameterError(first->path + ": it has " + std::to_string(first->motion.num_frames) +
                         " frames, the clips' summary " + std::to_string(summary.frames[0]));
  }
  s.skeleton = first->skeleton;
  s.feet = try_find_feet(s.skeleton, options.up);
  s.gait = s.feet.has_value();
  s.frame_time = first->motion.frame_time;
  s.joints = s.skeleton.num_joints();
  const int J = s.joints;
  check_blend_joints(summary.motion_root, summary.moving, J, "map: the clips' summary",
                     first->path);
  s.motion_root = summary.motion_root;
  s.moving = summary.moving;
  s.ancestors = synth::root_ancestors(s.skeleton, s.motion_root);
  const std::shared_ptr<const Clip> clip0 =
      samples.clip_of[0] == 0 ? first : source->clip(samples.clip_of[0]);
  if (!clip0->skeleton.same_hierarchy(s.skeleton)) {
    throw ParameterError(clip0->path + ": its joint hierarchy differs from " + first->path +
                         "'s; clips blended together must share one");
  }
  s.fixed_translations.resize(static_cast<std::size_t>(J));
  for (int j = 0; j < J; ++j)
    s.fixed_translations[j] = clip0->motion.translation(samples.frame_of[0], j);
  s.source = std::move(source);
  s.clip_of = samples.clip_of;
  s.frame_of = samples.frame_of;
  s.clip_frames = summary.frames;
  s.build_systems(coords, samples, summary.frame_times, /*lazy=*/true, control);
}

MapBlender::~MapBlender() = default;
MapBlender::MapBlender(MapBlender&&) noexcept = default;
MapBlender& MapBlender::operator=(MapBlender&&) noexcept = default;

MapWeights MapBlender::Impl::weights(const PointValidity& v) const {
  if (options.mode == BlendMode::Gp) return gp_weights(v);
  std::vector<std::pair<int, double>> pw;
  PointValidity at = v;
  point_weights(at, pw);
  return index->to_sample_weights(pw, at);
}

MapWeights MapBlender::locate(const Eigen::Vector2d& p) const {
  if (m->options.mode == BlendMode::Kriging)
    return std::move(locate(std::span<const Eigen::Vector2d>(&p, 1)).front());
  return m->weights(m->validate(p));
}

std::vector<MapWeights> MapBlender::locate(std::span<const Eigen::Vector2d> pts) const {
  std::vector<MapWeights> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) out[i].validity = m->validate(pts[i]);
  if (m->options.mode != BlendMode::Kriging) {
    parallel_for(static_cast<int>(pts.size()), [&](int i) {
      MapWeights& w = out[static_cast<std::size_t>(i)];
      w = m->weights(w.validity);
    });
    return out;
  }
  const auto blocks = static_cast<int>((pts.size() + kKrigingBlock - 1) / kKrigingBlock);
  parallel_for(blocks, [&](int block) {
    const auto b = static_cast<std::size_t>(block) * kKrigingBlock;
    const std::size_t e = std::min(pts.size(), b + kKrigingBlock);
    m->kriging_block(std::span<MapWeights>(out).subspan(b, e - b));
  });
  return out;
}

int MapBlender::follow_neighbours(double frame_time) const {
  check_frame_time("follow_neighbours", frame_time);
  if (m->options.mode != BlendMode::Local) return 0;
  return static_cast<int>(
      std::min<long long>(follow_half_window(frame_time), std::numeric_limits<int>::max()));
}

int MapBlender::path_neighbours(double frame_time) const {
  check_frame_time("path_neighbours", frame_time);
  if (m->options.mode != BlendMode::Local) return 0;
  return static_cast<int>(std::min<long long>(
      follow_half_window(frame_time) + (m->gait ? detail::pace_window(frame_time) : 0),
      std::numeric_limits<int>::max()));
}

std::vector<Eigen::Vector2d> MapBlender::path_points(const MapPath& path, double frame_time,
                                                     double speed, long long max_frames) const {
  const MapPath timed = timed_path(path, speed);
  std::vector<Eigen::Vector2d> points = resample_path(timed, frame_time, 0.0, max_frames);
  if (m->options.mode == BlendMode::Local) {
    detail::follow_strokes(*m->index, timed, frame_time, points);
  }
  return points;
}

std::vector<MapWeights> MapBlender::locate_path(std::span<const Eigen::Vector2d> points,
                                                double frame_time, std::size_t first,
                                                std::size_t end, PathFits* fits) const {
  if (!(first <= end && end <= points.size())) {
    throw ParameterError("locate_path: frames [" + std::to_string(first) + ", " +
                         std::to_string(end) + ") of a path of " + std::to_string(points.size()));
  }
  check_frame_time("locate_path", frame_time);
  if (m->options.mode != BlendMode::Local || points.size() < 2)
    return locate(points.subspan(first, end - first));
  if (fits == nullptr) return m->locate_path(points, first, end, frame_time, nullptr);
  std::shared_ptr<detail::PathFitsData> held = m->fits_for(fits->m, points, frame_time);
  std::vector<MapWeights> out = m->locate_path(points, first, end, frame_time, held.get());
  fits->m = std::move(held);
  return out;
}

std::shared_ptr<detail::PathFitsData> MapBlender::Impl::fits_for(
    const std::shared_ptr<const detail::PathFitsData>& held,
    std::span<const Eigen::Vector2d> points, double dt) const {
  const bool ours = held && held->blender == id && std::memcmp(&held->dt, &dt, sizeof dt) == 0;
  if (ours && same_points(held->points, points)) {
    // Copied unless the caller holds the only reference (then no one else sees the change).
    if (held.use_count() == 1) return std::const_pointer_cast<detail::PathFitsData>(held);
    return std::make_shared<detail::PathFitsData>(*held);
  }
  auto out = std::make_shared<detail::PathFitsData>();
  const std::size_t F = points.size();
  out->blender = id;
  out->dt = dt;
  out->points.assign(points.begin(), points.end());
  out->known.assign(F, 0);
  out->validity.resize(F);
  out->sources.resize(F);
  if (!ours) return out;
  // Frame k's fit reads the points [k − h, k + h] within the path (follow_clips): kept where they
  // are the same points, up to the same last frame, in both paths.
  const auto h = static_cast<std::size_t>(follow_half_window(dt));
  const std::size_t F0 = held->points.size(), common = std::min(F, F0);
  std::vector<std::size_t> changed(common + 1, 0);  // changed points among the first i
  for (std::size_t i = 0; i < common; ++i) {
    changed[i + 1] =
        changed[i] +
        (std::memcmp(&held->points[i], &points[i], sizeof(Eigen::Vector2d)) != 0 ? 1 : 0);
  }
  for (std::size_t k = 0; k < common; ++k) {
    if (!held->known[k]) continue;
    const std::size_t lo = k > h ? k - h : 0, hi = std::min(F - 1, k + h);
    if (hi != std::min(F0 - 1, k + h) || changed[hi + 1] != changed[lo]) continue;
    out->known[k] = 1;
    out->validity[k] = held->validity[k];
    out->sources[k] = held->sources[k];
  }
  return out;
}

PointValidity MapBlender::Impl::path_frame(std::span<const Eigen::Vector2d> points, std::size_t k,
                                           double dt, detail::PhaseFrame& frame) const {
  const MapWeights kriged = weights(validate(points[k]));
  const Follow follow = follow_clips(points, k, dt);
  // The clip times followed at their share, the kriging's samples at the rest.
  auto& sources = frame.sources;
  for (const FollowFit& fit : follow.fits)
    sources.push_back({fit.run, fit.seconds, follow.share * fit.share});
  if (follow.share < 1.0) {
    for (std::size_t e = 0; e < kriged.samples.size(); ++e) {
      const int s = kriged.samples[e];
      sources.push_back({index->run_of(s), index->seconds_in_run(s),
                         (1.0 - follow.share) * kriged.weights[e], s});
    }
  }
  return kriged.validity;
}

std::vector<MapWeights> MapBlender::Impl::locate_path(std::span<const Eigen::Vector2d> points,
                                                      std::size_t first, std::size_t end, double dt,
                                                      detail::PathFitsData* fits) const {
  // The frames the registration and the pace read around [first, end) too.
  const auto window = static_cast<std::size_t>(gait ? detail::pace_window(dt) : 0);
  const std::size_t a = first > window ? first - window : 0;
  const std::size_t b = std::min(points.size(), end + window);
  std::vector<PointValidity> validity(b - a);
  std::vector<detail::PhaseFrame> sources(b - a);
  parallel_for(static_cast<int>(b - a), [&](int i) {
    const auto f = static_cast<std::size_t>(i);
    if (fits && fits->known[a + f]) {
      validity[f] = fits->validity[a + f];
      sources[f].sources = fits->sources[a + f];
      return;
    }
    validity[f] = path_frame(points, a + f, dt, sources[f]);
  });
  if (fits) {
    for (std::size_t f = 0; f < b - a; ++f) {
      if (fits->known[a + f]) continue;
      fits->known[a + f] = 1;
      fits->validity[a + f] = validity[f];
      fits->sources[a + f] = sources[f].sources;
    }
  }
  if (gait) {
    std::vector<int> runs;
    for (const detail::PhaseFrame& f : sources)
      for (const detail::PhaseSource& src : f.sources) runs.push_back(src.run);
    read_phases(std::move(runs));
    // The frames either side the pace reads too, where the path has them.
    const std::size_t more = detail::kPaceFrames;
    detail::register_phases(sources, first - a - std::min(first - a, more),
                            end - a + std::min(b - end, more), dt,
                            [this](int run) -> const detail::GaitPhase& { return phase_of(run); });
  }
  // Each frame's sources, at their clip times, as weights over the samples.
  std::vector<MapWeights> out(end - first);
  for (std::size_t k = first; k < end; ++k) {
    std::vector<std::pair<int, double>> added;
    for (const detail::PhaseSource& src : sources[k - a].sources) {
      if (src.sample >= 0) {
        added.emplace_back(src.sample, src.weight);
        continue;
      }
      int samples[2] = {0, 0};
      double weights[2] = {1.0, 0.0};
      const int count = index->later_in_clip(src.run, src.seconds, samples, weights);
      for (int e = 0; e < count; ++e) added.emplace_back(samples[e], src.weight * weights[e]);
    }
    out[k - first] = detail::weights_by_sample(std::move(added), validity[k - a]);
    if (gait) {
      out[k - first].pace = detail::pace(sources, k - a, dt);
      out[k - first].lead_pace = detail::lead_pace(sources, k - a);
    }
  }
  return out;
}

const detail::GaitPhase& MapBlender::Impl::phase_of(int run) const {
  static const detail::GaitPhase none;
  if (!feet) return none;
  {
    const std::lock_guard lock(phase_mutex);
    if (const auto hit = phases.find(run); hit != phases.end()) return hit->second;
  }
  if (source) {
    read_phases({run});
    const std::lock_guard lock(phase_mutex);
    return phases.at(run);  // elements never move
  }
  detail::GaitPhase phase = detail::gait_phase(
      clip_contacts[static_cast<std::size_t>(clip_of[static_cast<std::size_t>(run)])],
      index->frame_time(run), index->frame_of(run), index->run_seconds(run));
  const std::lock_guard lock(phase_mutex);
  return phases.try_emplace(run, std::move(phase)).first->second;
}

void MapBlender::Impl::read_phases(std::vector<int> runs) const {
  if (!feet || !source) return;
  {
    const std::lock_guard lock(phase_mutex);
    std::erase_if(runs, [&](int run) { return phases.contains(run); });
  }
  std::sort(runs.begin(), runs.end(), [&](int a, int b) {
    return std::pair(clip_of[static_cast<std::size_t>(a)], a) <
           std::pair(clip_of[static_cast<std::size_t>(b)], b);
  });
  runs.erase(std::unique(runs.begin(), runs.end()), runs.end());
  if (runs.empty()) return;
  const std::vector<std::size_t> group =
      clip_groups(runs, [&](int run) { return clip_of[static_cast<std::size_t>(run)]; });
  std::vector<detail::GaitPhase> read(runs.size());
  parallel_for(static_cast<int>(group.size()) - 1, [&](int g) {
    const std::size_t first = group[static_cast<std::size_t>(g)];
    const std::shared_ptr<const Clip> clip =
        source->clip(clip_of[static_cast<std::size_t>(runs[first])]);
    const std::array<FootContacts, 2> clip_feet = feet_contacts(*clip);
    for (std::size_t r = first; r < group[static_cast<std::size_t>(g) + 1]; ++r) {
      read[r] = detail::gait_phase(clip_feet, index->frame_time(runs[r]), index->frame_of(runs[r]),
                                   index->run_seconds(runs[r]));
    }
  });
  const std::lock_guard lock(phase_mutex);
  for (std::size_t r = 0; r < runs.size(); ++r) phases.try_emplace(runs[r], std::move(read[r]));
}

MapWeights MapBlender::later_in_clip(const MapWeights& weights, double seconds) const {
  if (!std::isfinite(seconds))
    throw ParameterError("later_in_clip: " + format_number(seconds) + " s is not finite");
  if (weights.samples.size() != weights.weights.size()) {
    throw ParameterError("later_in_clip: " + std::to_string(weights.samples.size()) +
                         " sample indices for " + std::to_string(weights.weights.size()) +
                         " weights");
  }
  std::vector<std::pair<int, double>> moved;
  moved.reserve(2 * weights.samples.size());
  int to[2];
  double share[2];
  for (std::size_t e = 0; e < weights.samples.size(); ++e) {
    const int s = weights.samples[e];
    if (s < 0 || s >= m->n) {
      throw ParameterError("later_in_clip: sample " + std::to_string(s) + " of a map of " +
                           std::to_string(m->n));
    }
    const int count = m->index->later_in_clip(s, seconds, to, share);
    for (int c = 0; c < count; ++c) moved.emplace_back(to[c], share[c] * weights.weights[e]);
  }
  MapWeights out = detail::weights_by_sample(std::move(moved), weights.validity);
  out.pace = weights.pace;
  return out;
}

Follow MapBlender::Impl::follow_clips(std::span<const Eigen::Vector2d> points, std::size_t k,
                                      double dt) const {
  Follow out;
  const double step = index->median_step();
  if (!(step > 0.0)) return out;
  const double far = kFollowFar * step;
  std::vector<detail::MapIndex::TrajectoryHit> hits;
  index->trajectory_near(points[k], kFollowSearch * step, kTrajectoryMaxSeconds, hits);
  if (hits.empty()) return out;
  // The window: frames k + j, j ∈ [j0, j1], weighted 1 − |j|/(h + 1).
  const auto K = static_cast<long long>(k), last = static_cast<long long>(points.size()) - 1;
  const long long h = follow_half_window(dt);
  const long long j0 = -std::min(h, K), j1 = std::min(h, last - K);
  // Every stride-th frame of the window (about kFollowWindowPoints a side) is compared.
  const long long stride = std::max(1LL, h / static_cast<long long>(kFollowWindowPoints));
  const auto at = [&](long long j) { return points[static_cast<std::size_t>(K + j)]; };
  // A clip time followed: the run (its first sample) and the seconds into it at frame k, the
  // rate the clip plays at, and the window's weighted mean squared distance to the path.
  struct Timeline {
    int run = 0;
    double seconds = 0.0, rate = 1.0, cost = 0.0;
  };
  Eigen::Vector2d v;
  const auto cost_of = [&](Timeline& c, Eigen::Matrix2d* normal, Eigen::Vector2d* gradient) {
    double sum = 0.0, weights = 0.0;
    if (normal != nullptr) {
      normal->setZero();
      gradient->setZero();
    }
    for (long long j = -((-j0) / stride) * stride; j <= j1; j += stride) {
      const double wj = 1.0 - static_cast<double>(std::abs(j)) / static_cast<double>(h + 1);
      const double tj = static_cast<double>(j) * dt;
      const Eigen::Vector2d e = at(j) - index->trajectory_at(c.run, c.seconds + c.rate * tj, v);
      sum += wj * e.squaredNorm();
      weights += wj;
      if (normal != nullptr) {
        // d(trajectory)/d(seconds) = v, d/d(rate) = v·tj.
        const Eigen::Vector2d d(v.squaredNorm(), v.squaredNorm() * tj);
        (*normal)(0, 0) += wj * d(0);
        (*normal)(0, 1) += wj * d(1);
        (*normal)(1, 1) += wj * d(1) * tj;
        (*gradient)(0) += wj * v.dot(e);
        (*gradient)(1) += wj * v.dot(e) * tj;
      }
    }
    c.cost = sum / weights;
  };
  std::vector<Timeline> found;
  for (const auto& hit : hits) {
    if (found.size() >= static_cast<std::size_t>(kFollowTimelines)) break;
    Timeline c;
    std::tie(c.run, c.seconds) = index->clip_time(hit);
    const auto same = [&](const Timeline& t) {
      return std::any_of(found.begin(), found.end(), [&](const Timeline& f) {
        return f.run == t.run && std::abs(f.seconds - t.seconds) < kFollowSameSeconds;
      });
    };
    if (same(c)) continue;
    // The rate from the window's chord, then Gauss–Newton on (seconds, rate), keeping the best.
    if (j1 > j0) {
      const Eigen::Vector2d chord = at(j1) - at(j0);
      const Eigen::Vector2d clip =
          index->trajectory_at(c.run, c.seconds + static_cast<double>(j1) * dt, v) -
          index->trajectory_at(c.run, c.seconds + static_cast<double>(j0) * dt, v);
      if (clip.squaredNorm() > 0.0)
        c.rate = std::clamp(chord.dot(clip) / clip.squaredNorm(), kFollowMinRate, kFollowMaxRate);
    }
    Timeline best = c;
    Eigen::Matrix2d normal;
    Eigen::Vector2d gradient;
    cost_of(c, &normal, &gradient);
    // A start this far off (the path crosses the clip, or runs against it) is not followed.
    if (c.cost > 4.0 * far * far) continue;
    for (int it = 0; it < kFollowIterations; ++it) {
      if (it > 0) cost_of(c, &normal, &gradient);
      if (it == 0 || c.cost < best.cost) best = c;
      normal(1, 0) = normal(0, 1);
      normal.diagonal().array() += 1e-9 * (normal.diagonal().array().abs().maxCoeff() + 1e-30);
      const Eigen::Vector2d delta = normal.ldlt().solve(gradient);
      if (!delta.allFinite()) break;
      c.seconds += std::clamp(delta(0), -kTrajectoryMaxSeconds, kTrajectoryMaxSeconds);
      c.rate =
          std::clamp(c.rate + std::clamp(delta(1), -0.25, 0.25), kFollowMinRate, kFollowMaxRate);
    }
    cost_of(c, nullptr, nullptr);
    if (c.cost < best.cost) best = c;
    if (!same(best)) found.push_back(best);
  }
  // Each timeline's cost, raised as its point at frame k leaves the search radius (where it is
  // found no more) to that of one kFollowFar off the path, so that every share below is
  // continuous along the path.
  const double radius = kFollowSearch * step, near = kFollowNear * step;
  std::vector<double> reach(found.size()), cost(found.size());
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < found.size(); ++c) {
    const double d = (points[k] - index->trajectory_at(found[c].run, found[c].seconds, v)).norm();
    reach[c] = detail::falloff(2.0 * d / radius - 1.0);
    cost[c] = found[c].cost + (1.0 - reach[c]) * far * far;
    least = std::min(least, cost[c]);
  }
  out.share = detail::falloff((std::sqrt(least) - near) / (far - near));
  if (out.share == 0.0) return out;
  // The timelines whose costs are within a tie of the least share the clips' part.
  const double tie = kFollowTie * least + kFollowTieSteps * kFollowTieSteps * step * step;
  std::vector<double> alpha(found.size());
  double total = 0.0;
  for (std::size_t c = 0; c < found.size(); ++c) {
    alpha[c] = reach[c] * detail::falloff((cost[c] - least) / tie);
    total += alpha[c];
  }
  for (std::size_t c = 0; c < found.size(); ++c) {
    if (alpha[c] != 0.0) out.fits.push_back({found[c].run, found[c].seconds, alpha[c] / total});
  }
  return out;
}

std::optional<std::array<double, 2>> MapBlender::contact_share(const MapWeights& w) const {
  if (!m->feet || w.samples.size() != w.weights.size()) return std::nullopt;
  std::array<double, 2> share{0.0, 0.0};
  double total = 0.0;
  // Read on demand: the contacts of the states the blend of these weights read.
  std::unique_lock<std::mutex> lock;
  if (m->source) lock = std::unique_lock<std::mutex>(m->state_mutex);
  for (std::size_t e = 0; e < w.samples.size(); ++e) {
    const int s = w.samples[e];
    if (s < 0 || s >= m->n) return std::nullopt;
    const double weight = w.weights[e];
    total += weight;
    std::uint8_t c = 0;
    if (m->source) {
      const auto hit = m->states.find(s);
      if (hit == m->states.end()) return std::nullopt;  // not read (blend these weights first)
      c = hit->second.contact;
    } else {
      c = m->contacts[static_cast<std::size_t>(s)];
    }
    if (c & 1) share[0] += weight;
    if (c & 2) share[1] += weight;
  }
  if (!(total != 0.0)) return std::nullopt;
  for (double& v : share) v = std::clamp(v / total, 0.0, 1.0);
  return share;
}

BlendedFrame MapBlender::blend(const MapWeights& w) const {
  const Impl& s = *m;
  if (w.samples.size() != w.weights.size() || w.samples.empty()) {
    throw ParameterError("blend: " + std::to_string(w.samples.size()) + " sample indices for " +
                         std::to_string(w.weights.size()) +
                         " weights (need equal, non-zero counts)");
  }
  // The weights' checks before any clip is read (blend_states() makes them again).
  double total = 0.0;
  for (std::size_t k = 0; k < w.samples.size(); ++k) {
    if (w.samples[k] < 0 || w.samples[k] >= s.n) {
      throw ParameterError("blend: sample index " + std::to_string(w.samples[k]) +
                           " is out of range [0, " + std::to_string(s.n) + ")");
    }
    if (!std::isfinite(w.weights[k]))
      throw ParameterError("blend: weight " + std::to_string(k) + " is not finite");
    total += w.weights[k];
  }
  if (!(std::abs(total) > 1e-12))
    throw ParameterError("blend: the weights sum to " + format_number(total) + ", not about 1");
  if (!(w.pace >= 0.0 && std::isfinite(w.pace)))
    throw ParameterError("blend: pace " + format_number(w.pace) + " is not a finite number ≥ 0");

  const auto J = static_cast<std::size_t>(s.joints);
  const std::size_t count = w.samples.size();
  const std::size_t mv = s.moving.size();
  // Per entry k of the weights: its sample's state — the blender's tables, or (with a source)
  // read from the clips now.
  std::vector<Eigen::Quaterniond> read_rotations;
  std::vector<Eigen::Vector3d> read_translations, read_velocity;
  std::vector<double> read_height, read_yaw, read_sway;
  if (s.source)
    s.read_samples(w.samples, read_rotations, read_translations, read_height, read_velocity,
                   read_yaw, read_sway);
  std::vector<SampleStateView> states(count);
  for (std::size_t k = 0; k < count; ++k) {
    SampleStateView& v = states[k];
    if (s.source) {
      v = {read_rotations.data() + k * J,
           read_translations.data() + k * mv,
           read_height[k],
           read_velocity[k],
           read_yaw[k],
           read_sway[k]};
    } else {
      const auto i = static_cast<std::size_t>(w.samples[k]);
      v = {s.rotations.data() + i * J,
           s.moving_translations.data() + i * mv,
           s.height[i],
           s.velocity[i],
           s.yaw_rate[i],
           s.heading_offset[i]};
    }
  }
  BlendedFrame out = blend_states(states, w.weights, s.fixed_translations, s.moving, s.motion_root,
                                  s.options.up, s.ancestors);
  out.velocity *= w.pace;
  out.yaw_rate *= w.pace;
  return out;
}

Motion MapBlender::pose_at(const Eigen::Vector2d& p) const {
  return pose(locate(p));
}

Motion MapBlender::pose(const MapWeights& weights) const {
  const BlendedFrame b = blend(weights);
  Motion pose;
  pose.frame_time = m->frame_time;
  pose.resize(1, m->joints);
  pose.rotations = b.rotations;
  pose.translations = b.translations;
  return pose;
}

Motion MapBlender::pose(const MapWeights& weights, const RootPlacement& placement) const {
  Motion out = pose(weights);
  place_root(out, m->motion_root, placement, m->options.up);
  return out;
}

void place_root(Motion& pose, int root, const RootPlacement& placement, Axis up) {
  if (!std::isfinite(placement.heading) || !placement.floor.allFinite())
    throw ParameterError("place_root: the root placement is not finite");
  if (pose.num_frames < 1 || root < 0 || root >= pose.num_joints) {
    throw ParameterError("place_root: joint " + std::to_string(root) + " of a pose of " +
                         std::to_string(pose.num_frames) + " frames and " +
                         std::to_string(pose.num_joints) + " joints");
  }
  const int u = static_cast<int>(up);
  // The pose faces heading 0 (its root's tilt has no heading), so turning it by the placement's
  // heading gives exactly that heading.
  Eigen::Quaterniond& q = pose.rotation(0, root);
  q = (axis_rotation(up, placement.heading) * q).normalized();
  Eigen::Vector3d& t = pose.translation(0, root);
  const double height = t[u];
  t = placement.floor;
  t[u] = height;
}

RootPlacement root_placement(const Motion& motion, int frame, int root, Axis up,
                             std::span<const int> ancestors) {
  if (frame < 0 || frame >= motion.num_frames || root < 0 || root >= motion.num_joints) {
    throw ParameterError("root_placement: frame " + std::to_string(frame) + " or joint " +
                         std::to_string(root) + " is out of range (" +
                         std::to_string(motion.num_frames) + " frames, " +
                         std::to_string(motion.num_joints) + " joints)");
  }
  const RootTransform t = root_transform(motion, frame, root, ancestors);
  RootPlacement p;
  p.heading = features::heading_angle(t.rotation.normalized(), up);
  p.floor = t.translation;
  p.floor[static_cast<int>(up)] = 0.0;
  return p;
}

const Skeleton& MapBlender::skeleton() const {
  return m->skeleton;
}
const BlendOptions& MapBlender::options() const {
  return m->options;
}
int MapBlender::num_samples() const {
  return m->n;
}
int MapBlender::num_points() const {
  return m->index->num_points();
}
double MapBlender::frame_time() const {
  return m->frame_time;
}
int MapBlender::motion_root() const {
  return m->motion_root;
}
std::span<const int> MapBlender::root_ancestors() const {
  return m->ancestors;
}
double MapBlender::median_step() const {
  return m->index->median_step();
}
bool MapBlender::inside(const Eigen::Vector2d& p) const {
  return !m->validate(p).clamped;
}
PointValidity MapBlender::validity(const Eigen::Vector2d& p) const {
  return m->validate(p);
}

double MapBlender::reach_distance() const {
  return m->index->reach_distance();
}
double MapBlender::median_speed() const {
  return m->index->median_speed();
}
void MapBlender::prefetch(std::span<const MapWeights> weights) const {
  if (!m->source) return;
  std::vector<int> samples;
  for (const MapWeights& w : weights) {
    for (const int i : w.samples) {
      if (i < 0 || i >= m->n) {
        throw ParameterError("prefetch: sample index " + std::to_string(i) +
                             " is out of range [0, " + std::to_string(m->n) + ")");
      }
      samples.push_back(i);
    }
  }
  std::sort(samples.begin(), samples.end());
  samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
  std::vector<Eigen::Quaterniond> rotations;
  std::vector<Eigen::Vector3d> translations, velocities;
  std::vector<double> heights, yaw_rates, sways;
  m->read_samples(samples, rotations, translations, heights, velocities, yaw_rates, sways);
}

bool MapBlender::reads_on_demand() const {
  return m->source != nullptr;
}

int MapBlender::num_local_systems() const {
  return m->local ? m->local->num_built() : 0;
}
Eigen::Vector2d MapBlender::sample_point(int i) const {
  if (i < 0 || i >= m->n) {
    throw ParameterError("sample " + std::to_string(i) + " is out of range [0, " +
                         std::to_string(m->n) + ")");
  }
  return m->index->sample_point(i);
}

int MapBlender::sample_frame(int i) const {
  sample_point(i);  // checks i
  return m->index->frame_of(i);
}

int MapBlender::next_sample(int i) const {
  sample_point(i);  // checks i
  return m->index->next_in_run(i);
}

double MapBlender::gait_phase(int i, double* cadence) const {
  sample_point(i);  // checks i
  const detail::GaitPhase& phase = m->phase_of(m->index->run_of(i));
  if (!phase.known()) return std::numeric_limits<double>::quiet_NaN();
  const double at = phase.at(m->index->seconds_in_run(i));
  if (cadence != nullptr) {
    const double cycle = std::floor(at);
    *cadence = 1.0 / (phase.time_at(cycle + 1.0) - phase.time_at(cycle));
  }
  return at;
}

}  // namespace motionmap::synth
