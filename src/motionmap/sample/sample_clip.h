#pragma once
// The built-in sample: procedural clips of a plausible humanoid, so the demo and the tests run
// anywhere (the repository cannot ship third-party motion capture).
//
//   motionmap::Clip swing = motionmap::sample::make_sample_clip(motionmap::sample::SampleKind::Swing);
//   motionmap::io::write_bvh(motionmap::io::from_motion(swing.skeleton, swing.motion), "swing.bvh");
#include <string_view>
#include <optional>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::sample {

enum class SampleKind { Swing, Walk };

/// "swing" / "walk".
std::string_view sample_kind_name(SampleKind kind);
std::optional<SampleKind> parse_sample_kind(std::string_view name);

/// A CMU-like 31-joint skeleton (the joint names and hierarchy of CMU's BVH conversions, Y up,
/// lengths in centimetres), root channels Xposition Yposition Zposition Zrotation Yrotation
/// Xrotation, every other joint Zrotation Yrotation Xrotation.
Skeleton cmu_like_skeleton();

struct SampleOptions {
  double fps = 120.0;
  double seconds = 0.0;  ///< 0: the kind's natural length (a swing ≈ 4 s, a walk ≈ 4 s)
};

/// A deterministic procedural clip: a golf-like swing (address, backswing, downswing, follow-
/// through, smooth in time) or a walk cycle moving along +Z. @throws ParameterError for fps ≤ 0 or
/// seconds < 0.
Clip make_sample_clip(SampleKind kind, const SampleOptions& options = {});

}  // namespace motionmap::sample
