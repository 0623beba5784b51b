#pragma once
// A seeded synthetic motion library made from real clips, for measuring maps at 10⁴–10⁶ frames
// (issue 11, "Measurements"). Every output clip is a chain of segments of the source clips, each
//  1. time-warped: a smooth, monotone warp of the source's time, resampled with quaternion slerp
//     for rotations and linear interpolation for translations;
//  2. mirrored left↔right with some probability (mirror_motion());
//  3. retargeted to the output clip's skeleton (one of the sources'; the root's translation scaled
//     by the ratio of hip heights) and turned and moved to continue where the previous segment
//     stopped, its first frames blended from the previous segment's last pose;
// and the whole clip gets small smooth noise on every rotation and on the root's position.
// Everything is drawn from a seeded generator of its own (not <random>'s distributions, whose
// results differ between standard libraries), clip i from (seed, i) alone, so the same seed gives
// byte-identical files.
//
//   auto sources = motionmap::bench::load_sources("../shared/data/cmu", &notes);
//   motionmap::bench::LibraryOptions options;
//   options.frames = 72000;                     // 12 clips of 6000 frames
//   motionmap::bench::write_library(sources, options, "/tmp/lib72k");
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::bench {

/// A small deterministic random generator (SplitMix64): the same seed gives the same numbers on
/// every platform and standard library.
class Random {
 public:
  explicit Random(std::uint64_t seed) : m_state(seed) {}
  std::uint64_t next();
  /// Uniform in [0, 1), 53 random bits.
  double uniform();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0.
  int index(int n);

 private:
  std::uint64_t m_state;
};

/// The seed of clip `index` of a library made with `seed` (independent of the library's size).
std::uint64_t clip_seed(std::uint64_t seed, std::int64_t index);

// ---- Mirroring -------------------------------------------------------------------------------
// A mirror is a reflection M across the sagittal plane through the origin (M negates the lateral
// axis). A motion is mirrored by giving joint j the transforms of its left↔right partner p(j)
// reflected: R'_j = M·R_p(j)·M, t'_j = M·t_p(j). M·R·M is the rotation by −θ about M·a for R the
// rotation by θ about a, i.e. the quaternion (w, x, y, z) keeps w and the lateral component and
// negates the other two: for CMU's skeleton (Y up, facing +Z, the subject's left on +X) the lateral
// axis is X, so (w, x, y, z) → (w, x, −y, −z) and (x, y, z) → (−x, y, z); a channel triple
// Zrotation Yrotation Xrotation (a, b, c) becomes (−a, −b, c). Forward kinematics of the mirrored
// motion on mirror_skeleton() puts joint j exactly at M times where p(j) was; on the original
// skeleton, only as exactly as the subject's left and right bones have equal lengths.

/// Left↔right partner of every joint: `Left…` ↔ `Right…`, and `L` ↔ `R` before a capital letter
/// (CMU's LHipJoint, LThumb), when a joint of that name exists; the joint itself otherwise.
/// @throws ParameterError if the pairs do not form a mirror-symmetric hierarchy (the parent of a
///         joint's partner must be the partner of its parent; partners must have as many End
///         Sites).
std::vector<int> mirror_partners(const Skeleton& skeleton);

/// The axis that separates left from right in `skeleton`'s rest pose: the coordinate axis along
/// which the rest positions of left and right partners differ most (X for CMU's skeletons).
/// @throws ParameterError if the skeleton has no left↔right pair, or `partners` does not hold one
///         entry per joint.
Axis lateral_axis(const Skeleton& skeleton, std::span<const int> partners);

/// The skeleton mirrored: joint j (name, parent, channels kept) gets p(j)'s offset and End Sites
/// reflected across the plane normal to `lateral`.
/// @throws ParameterError if `partners` does not hold one entry per joint.
Skeleton mirror_skeleton(const Skeleton& skeleton, std::span<const int> partners, Axis lateral);

/// The motion mirrored as above (#frames by #joints, as `motion`). Exact: sign flips and swaps
/// only, so mirroring twice gives back the same numbers.
/// @throws ParameterError if `partners` does not hold one entry per joint of `motion`.
Motion mirror_motion(const Motion& motion, std::span<const int> partners, Axis lateral);

// ---- Time warps ------------------------------------------------------------------------------

/// The motion at fractional frame positions `at` (each in [0, #frames − 1]): rotations slerped
/// between the two frames around, translations interpolated linearly. Frame time kept.
/// @throws ParameterError if the motion has fewer than 2 frames or a position is out of range.
Motion resample(const Motion& motion, std::span<const double> at);

/// A smooth monotone time warp: source frame positions u_0 = start, u_{i+1} = u_i + r_i·step for
/// output frames i = 0, 1, … while u ≤ end and fewer than `max_frames` are made, with the rate r
/// a smooth function of time in [1/max_rate, max_rate] (exp of a sum of three random sinusoids of
/// periods 1–4 s). `step` is the output frame time over the source's, `frame_time` the output's.
/// @throws ParameterError if max_rate < 1, step ≤ 0, end < start or max_frames < 1.
std::vector<double> time_warp(Random& random, double start, double end, int max_frames,
                              double max_rate, double step, double frame_time);

// ---- The library -----------------------------------------------------------------------------

/// A source clip ready to be cut: its leading bind pose (CMU's T-pose frame) left out, the
/// mirroring facts of its skeleton, and its hip height.
struct Source {
  Clip clip;
  std::vector<int> partners;  ///< mirror_partners(clip.skeleton); empty if !can_mirror
  Axis lateral = Axis::X;     ///< lateral_axis(), when it has pairs
  bool can_mirror = false;    ///< it has left↔right pairs
  /// rest height of the root above the lowest joint or End Site; of the first joint below the root
  /// that is above it when the root is on the floor (Bandai's joint_Root)
  double hip_height = 0.0;
};

/// Loads every .bvh file in `directory` (sorted by name) that shares the joint hierarchy of the
/// first one; clips of another hierarchy or with fewer than 3 frames left are skipped, with a line
/// in `notes` (as are a left-out bind pose and a skeleton that cannot be mirrored). Y is up.
/// @throws Error if the directory cannot be listed or holds no usable clip; ParseError for a
///         malformed file.
std::vector<Source> load_sources(const std::string& directory, std::vector<std::string>* notes);

struct LibraryOptions {
  std::int64_t frames = 20000;       ///< total frames of the library, ≥ 1
  int clip_frames = 6000;            ///< frames per file (the last one holds the rest), ≥ 2
  std::uint64_t seed = 1;            ///< same seed, same files
  double max_rate = 1.25;            ///< time-warp rates within [1/max_rate, max_rate], ≥ 1
  double mirror_probability = 0.5;   ///< chance that a segment is mirrored, in [0, 1]
  double noise_degrees = 1.0;        ///< amplitude of the rotation noise, ≥ 0
  double noise_translation = 0.005;  ///< amplitude of the root noise, × hip height, ≥ 0
  int segment_min = 60;              ///< output frames per segment, at least …
  int segment_max = 480;             ///< … and at most (a segment also ends with its source)
  int blend_frames = 12;             ///< frames blended from the previous segment, ≥ 0
  int decimals = 4;  ///< decimals of the written values (CMU writes 4); < 0: full precision
  /// @throws ParameterError naming the first option out of range.
  void validate() const;
};

/// One segment of an output clip, for the library's manifest.
struct Segment {
  int first_frame = 0;  ///< in the output clip
  int frames = 0;
  int source = 0;                               ///< index into the sources
  double source_begin = 0.0, source_end = 0.0;  ///< fractional frames of the source (bind pose out)
  bool mirrored = false;
};

struct SyntheticClip {
  Clip clip;  ///< path empty; the skeleton of one of the sources
  std::vector<Segment> segments;
};

/// Output clip `index` of `frames` frames: depends only on the sources, the options and
/// (seed, index).
/// @throws ParameterError for invalid options or frames < 2.
SyntheticClip make_clip(std::span<const Source> sources, const LibraryOptions& options,
                        std::int64_t index, int frames);

/// The clip's BVH document values rounded to `decimals` (as write_library writes them); < 0 keeps
/// them. Negative zeros become zeros.
void round_values(std::vector<double>& values, int decimals);

/// Writes ceil(frames / clip_frames) files clip_00000.bvh, … into `directory` (created if needed)
/// and then manifest.txt (the options and one line per segment). Returns the BVH paths written.
/// `progress(done, total)` is called after each file.
/// @throws ParameterError for invalid options; Error if a file cannot be written.
std::vector<std::string> write_library(
    std::span<const Source> sources, const LibraryOptions& options, const std::string& directory,
    const std::function<void(std::int64_t, std::int64_t)>& progress = {});

}  // namespace motionmap::bench
