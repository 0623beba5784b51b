#include "motionmap/mapfile/frame_key.h"

#include <algorithm>
#include <filesystem>
#include <span>

#include "motionmap/core/error.h"
#include "motionmap/core/text_cursor.h"
#include "motionmap/features/joint_match.h"

namespace motionmap::mapfile {

namespace {

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec) && !ec;
}

// Whether `path` ends with the components of `name`.
bool ends_with_name(const std::filesystem::path& path, const std::filesystem::path& name) {
  std::vector<std::filesystem::path> p(path.begin(), path.end()), n(name.begin(), name.end());
  std::erase_if(p, [](const auto& c) { return c.empty() || c == "."; });
  std::erase_if(n, [](const auto& c) { return c.empty() || c == "."; });
  return !n.empty() && n.size() <= p.size() && std::equal(n.rbegin(), n.rend(), p.rbegin());
}

}  // namespace

std::string map_clip_named(const std::vector<std::string>& clip_files, const std::string& name) {
  std::vector<std::filesystem::path> paths;
  paths.reserve(clip_files.size());
  for (const std::string& clip : clip_files)
    paths.push_back(std::filesystem::path(clip).lexically_normal());
  // The clips (each path once) whose path ends with the components of `n`.
  const auto named_by = [&](const std::filesystem::path& n) {
    std::vector<std::string> out;
    for (std::size_t c = 0; c < paths.size(); ++c) {
      if (ends_with_name(paths[c], n) &&
          std::find(out.begin(), out.end(), clip_files[c]) == out.end())
        out.push_back(clip_files[c]);
    }
    return out;
  };
  const std::filesystem::path wanted = std::filesystem::path(name).lexically_normal();
  const std::vector<std::string> found = named_by(wanted);
  if (found.size() == 1) return found.front();
  if (found.empty()) {
    // Up to three clips whose file name holds the name given (walk_angry_001.bvh for
    // dataset-1_walk_angry_001.bvh), each by its file name where that names it alone.
    const std::string part = ascii_lower(wanted.filename().string());
    std::vector<std::string> like;
    for (std::size_t c = 0; c < paths.size() && !part.empty() && like.size() <= 3; ++c) {
      const std::string file = paths[c].filename().string();
      if (ascii_lower(file).find(part) == std::string::npos) continue;
      const std::string named = named_by(file).size() == 1 ? file : clip_files[c];
      if (std::find(like.begin(), like.end(), named) == like.end()) like.push_back(named);
    }
    if (!like.empty() && like.size() <= 3) {
      std::string guess;
      for (std::size_t c = 0; c < like.size(); ++c)
        guess += (c == 0 ? "" : c + 1 == like.size() ? " or " : ", ") + like[c];
      throw ParameterError("no such clip file '" + name +
                           "', and no clip of the map is named so; did you mean " + guess + "?");
    }
    std::string some;
    for (std::size_t c = 0; c < std::min<std::size_t>(clip_files.size(), 3); ++c)
      some += (c ? ", " : "") + std::filesystem::path(clip_files[c]).filename().string();
    if (clip_files.size() > 3) some += ", …";
    throw ParameterError("no such clip file '" + name + "', and no clip of the map is named so (" +
                         (clip_files.size() == 1
                              ? std::string("its clip: ")
                              : "its " + std::to_string(clip_files.size()) + " clips: ") +
                         some + ")");
  }
  throw ParameterError("'" + name + "' names " + std::to_string(found.size()) +
                       " clips of the map (" + found[0] + ", " + found[1] +
                       (found.size() > 2 ? ", …" : "") + "): give more of its path");
}

FrameKey frame_key(const KeyMap& map, const Clip& clip, int frame) {
  if (!map.blender || !map.samples || !map.reference) {
    throw ParameterError("frame_key: the map's blender, samples and reference clip are needed");
  }
  if (const std::string why = features::hierarchy_difference(*map.reference, clip); !why.empty()) {
    throw ParameterError(clip.path + " is a clip of another skeleton than the map's (" + why +
                         "); a key is a frame of a clip of the map's skeleton");
  }
  const int frames = clip.motion.num_frames;
  if (frame < 0 || frame >= frames) {
    throw ParameterError("frame " + std::to_string(frame) + " is out of range: " + clip.path +
                         " has " + std::to_string(frames) + " frames, 0 to " +
                         std::to_string(frames - 1));
  }
  int sample = -1;
  for (std::size_t c = 0; c < map.clip_files.size() && sample < 0; ++c) {
    if (same_file(map.clip_files[c], clip.path))
      sample = synth::find_sample(*map.samples, static_cast<int>(c), frame);
  }
  FrameKey out;
  if (sample >= 0) {
    out.key = synth::sample_key(*map.blender, sample, clip.motion, frame);
    return out;
  }
  if (!map.map_file) {
    throw ParameterError("frame_key: " + clip.path + " frame " + std::to_string(frame) +
                         " is not a sample of the map, and no map file was given to place it");
  }
  // Placed as `map --onto` places frames: this one frame, a leading bind pose included.
  PlaceOptions place;
  place.first_frame = frame;
  place.end_frame = frame + 1;
  place.keep_first = true;
  const Placement placed = place_clips(std::span<const Clip>(&clip, 1), map.map_file(), place,
                                       Control(), map.search ? map.search() : nullptr);
  out.placed = true;
  out.key.point = Eigen::Vector2d(placed.coordinates(0, 0), placed.coordinates(0, 1));
  out.key.pose.frame_time = clip.motion.frame_time;
  out.key.pose.resize(1, clip.motion.num_joints);
  for (int j = 0; j < clip.motion.num_joints; ++j) {
    out.key.pose.rotation(0, j) = clip.motion.rotation(frame, j);
    out.key.pose.translation(0, j) = clip.motion.translation(frame, j);
  }
  return out;
}

}  // namespace motionmap::mapfile
