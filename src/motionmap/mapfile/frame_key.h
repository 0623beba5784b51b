#pragma once
// Key poses from frames of clips: what in-betweening's FILE:FRAME keys (`motionmap inbetween
// --keys walk.bvh:9`) and Python's (clip, frame) keys (motionmap.inbetween) become. A frame that
// is a sample of the map sits on its sample's point (synth::sample_key); any other — a frame the
// map's stride or frame range left out, or a clip not in the map — is placed on the map as
// place_clips() (`map --onto`) places frames, this one frame alone (a leading bind pose kept),
// and keeps its own pose.
//
//   mapfile::KeyMap on{&blender, &samples, clip_files, &clips[0], [&]() -> const MapFile& {
//     return map; }};
//   mapfile::FrameKey k = mapfile::frame_key(on, walk, 9);   // k.key, k.placed
//
// Here and not in synth/: placing needs the map file's model (mapfile comes after synth).
#include <functional>
#include <string>
#include <vector>

#include "motionmap/mapfile/map_file.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/inbetween.h"

namespace motionmap::mapfile {

/// What frame_key() needs of a map.
struct KeyMap {
  const synth::MapBlender* blender = nullptr;
  const features::FeatureSet* samples = nullptr;  ///< the blender's samples
  /// Per clip of the map: the file it was read from (a key's clip is matched to them as files,
  /// std::filesystem::equivalent).
  std::vector<std::string> clip_files;
  /// A clip of the map: its skeleton is the one keys must have; its name is in the messages.
  const Clip* reference = nullptr;
  /// The map with its placement model; called only when a key must be placed (it may read or make
  /// the map file then).
  std::function<const MapFile&()> map_file;
  /// place_clips()'s search, when the caller keeps one for the map (called only when a key must
  /// be placed); empty: made for each key placed.
  std::function<const embed::SampleSearch*()> search;
};

struct FrameKey {
  synth::Key key;       ///< its point and pose (label and time left as they are by default)
  bool placed = false;  ///< not a sample of the map: placed on it as place_clips() places it
};

/// The clip of a map (`clip_files`, its clips' paths) that a key's `name` names when no file is
/// there: the one whose path ends with name's components (`walk.bvh` names takes/walk.bvh,
/// `takes/walk.bvh` names /data/takes/walk.bvh). Returns its path.
/// @throws ParameterError "no such clip file 'NAME', and no clip of the map is named so (its N
///   clips: a.bvh, b.bvh, …)" ("its clip: a.bvh" for one) — or, where one to three clips' file
///   names hold NAME's (case aside), "…; did you mean x_NAME or y_NAME?" — or "'NAME' names N
///   clips of the map (A, B, …): give more of its path".
std::string map_clip_named(const std::vector<std::string>& clip_files, const std::string& name);

/// The key pose of frame `frame` (from 0) of `clip` on the map (see above).
/// @throws ParameterError "frame F is out of range: PATH has N frames, 0 to N−1", "PATH is a clip
///   of another skeleton than the map's (…); a key is a frame of a clip of the map's skeleton",
///   or for a KeyMap without its blender, samples or reference; what place_clips() throws.
FrameKey frame_key(const KeyMap& map, const Clip& clip, int frame);

}  // namespace motionmap::mapfile
