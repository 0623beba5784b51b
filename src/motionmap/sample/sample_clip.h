#pragma once
// The built-in sample: procedural clips of a plausible humanoid, so the demo and the tests run
// anywhere (the repository cannot ship third-party motion capture).
//
//   motionmap::Clip swing =
//   motionmap::sample::make_sample_clip(motionmap::sample::SampleKind::Swing);
//   motionmap::io::write_bvh(motionmap::io::from_motion(swing.skeleton, swing.motion),
//   "swing.bvh");
#include <optional>
#include <string_view>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::sample {

enum class SampleKind { Swing, Walk };

/// "swing" / "walk".
std::string_view sample_kind_name(SampleKind kind);
/// The kind called `name` ("swing" or "walk", ASCII case ignored), or nothing.
std::optional<SampleKind> parse_sample_kind(std::string_view name);

/// A CMU-like 31-joint skeleton (the joint names, hierarchy, channel layouts and End Sites of CMU's
/// BVH conversions, e.g. 64_08.bvh) with the proportions of an average adult (≈ 1.72 m): Y up,
/// facing +Z, the subject's left on +X, lengths in centimetres, a T-pose at rest with the hips
/// 95 cm above the floor (y = 0). Root channels Xposition Yposition Zposition Zrotation Yrotation
/// Xrotation, every other joint Zrotation Yrotation Xrotation.
Skeleton cmu_like_skeleton();

/// Length limits of make_sample_clip().
inline constexpr double kMaxSampleFps = 1000.0;
inline constexpr double kMaxSampleSeconds = 600.0;
inline constexpr long kMaxSampleFrames = 144000;  ///< ten minutes at 240 fps

struct SampleOptions {
  double fps = 120.0;    ///< frames per second, in (0, kMaxSampleFps]
  double seconds = 0.0;  ///< clip length in [0, kMaxSampleSeconds]; 0: the kind's natural 4 s
};

/// A deterministic procedural clip of cmu_like_skeleton() with round(seconds × fps) frames
/// (Clip::path is "sample:swing" or "sample:walk"; no warnings).
///
/// Swing: a right-handed golf swing towards +X (the golfer faces +Z), feet planted, both hands on
/// one (implicit) club. Its choreography always fills the clip; at the natural 4 s: address until
/// 0.55 s, backswing to the top at 1.80 s, a pause until 1.95 s, downswing to impact at 2.30 s,
/// follow-through to a high finish at 3.02 s, then a hold. Another length scales these times.
/// Tiny smooth pseudo-noise keeps every frame distinct.
///
/// Walk: a steady walk along +Z at 1.3 m/s with a 1 s gait cycle (heel strike of the left foot at
/// 0.5 s, 1.5 s, …), feet planted while in stance; a longer clip walks further.
///
/// @throws ParameterError naming `fps`, `seconds` or the frame count when fps is not in
///         (0, kMaxSampleFps], seconds is not in [0, kMaxSampleSeconds] (NaN and infinities
///         included), or round(seconds × fps) is 0 or more than kMaxSampleFrames.
Clip make_sample_clip(SampleKind kind, const SampleOptions& options = {});

}  // namespace motionmap::sample
