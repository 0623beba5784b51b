#pragma once
// pca and svd maps of libraries whose clips and features X need not fit in memory: the clips are
// read from their files a few at a time (one per thread, merged in clip order, so the map does
// not depend on the thread count), twice. Pass 1 builds each clip's rows of X and accumulates the
// row count, the column means and the #features by #features scatter matrix
// (embed::ProjectionStream); the axes come from that small matrix; pass 2 reads the clips again
// and places each clip's rows on the axes. Memory: O(#features² + a clip per thread + the
// #frames by dims coordinates and the per-frame bookkeeping). The map is map_clips()'s of the
// same clips to rounding (Procrustes disparity ~1e-27, same signs:
// tests/pipeline/stream_map_test.cpp), with the same notes and warnings.
//
//   auto paths = motionmap::io::expand_clip_inputs(inputs);
//   motionmap::pipeline::ClipMapOptions opt;
//   opt.embed.method = motionmap::embed::Method::Pca;
//   auto streamed = motionmap::pipeline::stream_map(paths, {}, opt, control);
//   // streamed.map as map_clips() returns it (X with no rows; streamed.map.model places new
//   // frames); streamed.clips: the clips mapped, without their poses (paths, frame counts)
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/io/clip_inputs.h"
#include "motionmap/pipeline/clip_map.h"

namespace motionmap::pipeline {

/// Loading a library whole and building its features takes about this many bytes of memory per
/// byte of its files (BVH text; measured in docs/performance.md, "Streaming pca and svd").
constexpr double kLoadBytesPerFileByte = 5.0;

/// The memory loading the clips at `paths` whole and building their features would take,
/// estimated from the files' sizes (kLoadBytesPerFileByte; a file that cannot be read counts 0:
/// loading reports it).
double estimate_load_bytes(std::span<const std::string> paths);

/// Why `options` cannot be streamed (stream_map() would refuse them), or an empty string when
/// they can: the method must be pca or svd, the joints JointSelection::All, and no metrics.
std::string why_not_streamed(const ClipMapOptions& options);

/// Whether a map of the clips at `paths` should be streamed although not asked to: the options
/// can be (why_not_streamed()) and loading the clips whole would need more than `available`
/// bytes (estimate_load_bytes(); never when `available` is unknown).
bool streams_by_default(const ClipMapOptions& options, std::span<const std::string> paths,
                        std::optional<std::int64_t> available);

/// A streamed map and the clips it maps.
struct StreamedMap {
  /// As map_clips() returns it: features with clip_of, frame_of, segment_starts, joints and
  /// notes, X and the points with their column counts but no rows; `model` set.
  ClipMap map;
  /// The clips mapped (those that loaded), in order, without their poses: path, skeleton, frame
  /// count and frame time, the warnings of loading them and, with load.load.sha256, their SHA-256
  /// (from pass 1).
  std::vector<Clip> clips;
  /// load.keep_going only: why each clip skipped in pass 1 failed to load.
  std::vector<std::string> failures;
};

/// The map of the clips at `paths`, read a few at a time in two passes (see the top of this file).
/// `control` hears the stages "pass 1: features and XᵀX", "eigen" and "pass 2: features and
/// projection", with progress in clips, and is polled for cancellation between clips.
/// @throws ParameterError for options that cannot be streamed (why_not_streamed()) or are
///   invalid, for clips of different hierarchies (naming the first that differs), and as
///   embed::ProjectionStream; what io::load_clip() throws (the first clip that fails without
///   load.keep_going; in pass 2 always); io::no_clip_loaded() when every clip fails;
///   Error naming the file when a clip gives other frames in pass 2 than in pass 1, or with
///   load.load.sha256 another SHA-256 (it changed in between); Cancelled.
StreamedMap stream_map(std::span<const std::string> paths, const io::LoadClipsOptions& load,
                       const ClipMapOptions& options, const Control& control = {});

}  // namespace motionmap::pipeline
