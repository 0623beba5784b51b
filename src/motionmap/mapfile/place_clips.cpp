// Placing new clips on a saved map without refitting it, and maps of placed clips.
#include <algorithm>
#include <set>
#include <string_view>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/mapfile/map_file.h"

namespace motionmap::mapfile {

// ---- place_clips ----------------------------------------------------------------------------

namespace {

// `name` as a regular expression that matches exactly it.
std::string regex_literal(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (std::string_view("\\^$.|?*+()[]{}").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

Placement place_clips(std::span<const Clip> clips, const MapFile& map, const PlaceOptions& options,
                      const Control& control, const embed::SampleSearch* search) {
  if (clips.empty()) throw ParameterError("place_clips: no clip given");
  const std::string onto = map.path.empty() ? std::string("the map") : map.path;
  const std::string first_clip = base_name(map.clips.front().path);
  features::FeatureOptions f = map.options.features;
  f.first_frame = options.first_frame;
  f.end_frame = options.end_frame;
  f.stride = options.stride;
  f.keep_first = options.keep_first;

  if (f.joints == features::JointSelection::All) {
    // The map's skeleton: its clips share one hierarchy, recorded from the first.
    Clip reference;
    reference.path = map.clips.front().path;
    for (std::size_t j = 0; j < map.skeleton.names.size(); ++j) {
      Joint joint;
      joint.name = map.skeleton.names[j];
      joint.parent = map.skeleton.parents[j];
      // End Site counts are part of the hierarchy (the point cloud holds their points); their
      // offsets are the new clip's own business.
      joint.end_sites.assign(std::size_t(map.skeleton.end_sites[j]), Eigen::Vector3d::Zero());
      reference.skeleton.joints.push_back(std::move(joint));
    }
    for (const Clip& clip : clips) {
      const std::string difference = features::hierarchy_difference(reference, clip);
      if (!difference.empty()) {
        throw ParameterError(clip.path + ": cannot be placed on " + onto +
                             ": its joint hierarchy differs from the map's (" + difference +
                             "); a clip placed on a map must have the skeleton of the map's "
                             "clips (joint names, parents and End Sites)");
      }
    }
  } else {
    // A --joints common map: each new clip must have every joint the map compares by; its other
    // joints are left out (added to the exclude pattern) so that the features are the map's.
    std::set<std::string> shared(map.shared_joints.begin(), map.shared_joints.end());
    std::set<std::string> extra;
    for (const Clip& clip : clips) {
      std::vector<std::string> missing;
      for (const std::string& name : map.shared_joints) {
        if (clip.skeleton.find(name) < 0) missing.push_back(name);
      }
      if (!missing.empty()) {
        throw ParameterError(
            clip.path + ": cannot be placed on " + onto + ": it lacks " +
            std::to_string(missing.size()) + " of the " + std::to_string(shared.size()) +
            " joints the map compares by (--joints common): " + name_list(missing, 8));
      }
      for (const Joint& j : clip.skeleton.joints) {
        if (!shared.count(j.name)) extra.insert(j.name);
      }
    }
    std::string pattern;
    for (const std::string& name : extra)
      pattern += (pattern.empty() ? "" : "|") + regex_literal(name);
    if (!f.exclude.empty()) {
      f.exclude = pattern.empty() ? f.exclude : "(?:" + f.exclude + ")|" + pattern;
    } else {
      f.exclude = pattern;
    }
  }

  Placement out;
  out.features = features::build_features(clips, f, control.stage("features", 0.0, 0.2),
                                          features::Distances::Later);
  const features::FeatureSet& set = out.features;
  if (map.options.features.joints == features::JointSelection::Common) {
    // Its own "joints common" notes describe the exclusion above, not the map: replace them.
    std::erase_if(out.features.notes,
                  [](const std::string& n) { return n.rfind("joints common:", 0) == 0; });
    out.features.notes.push_back("joints common: placed by the " +
                                 std::to_string(map.shared_joints.size()) +
                                 " joints the map compares by");
  }

  // The features must be the map's, column for column.
  std::vector<std::string> used;
  for (const int j : set.joints) used.push_back(clips.front().skeleton.joints[std::size_t(j)].name);
  const std::string who = clips.front().path + ": cannot be placed on " + onto + ": ";
  if (used != map.joints) {
    throw ParameterError(who + "its features use the joints " + name_list(used, 6) +
                         " where the map's use " + name_list(map.joints, 6) +
                         (used.size() == map.joints.size() ? " (another order)" : ""));
  }
  if (set.X.cols() != map.x_columns || set.distance_input.cols() != map.point_columns) {
    throw ParameterError(who + "its features have " + std::to_string(set.X.cols()) +
                         " columns and its points " + std::to_string(set.distance_input.cols()) +
                         ", where the map's have " + std::to_string(map.x_columns) + " and " +
                         std::to_string(map.point_columns) + " (End Sites or roots differ)");
  }
  const embed::PlaceInput input{&set.X, &set.distance_input};
  out.coordinates = embed::place(map.model, input, control.stage("placing", 0.2, 1.0), search);
  control.finish();
  return out;
}

std::vector<PlacedClip> placed_clips(std::span<const Clip> clips, const Placement& placement) {
  const features::FeatureSet& set = placement.features;
  if (clips.size() != set.segment_starts.size() ||
      placement.coordinates.rows() != set.num_samples()) {
    throw ParameterError("placed_clips: the placement is not of these " +
                         std::to_string(clips.size()) + " clips");
  }
  std::vector<PlacedClip> out(clips.size());
  for (std::size_t c = 0; c < clips.size(); ++c) {
    PlacedClip& p = out[c];
    p.record.path = clips[c].path;
    p.record.sha256 = recorded_sha256(clips[c]);
    p.record.frames = clips[c].motion.num_frames;
    p.record.frame_time = clips[c].motion.frame_time;
    const int first = set.segment_starts[c];
    const int end = c + 1 < clips.size() ? set.segment_starts[c + 1] : set.num_samples();
    p.frames.assign(set.frame_of.begin() + first, set.frame_of.begin() + end);
    p.coordinates = placement.coordinates.middleRows(first, end - first);
  }
  return out;
}

MapFile placed_map_file(const MapFile& fitted, std::span<const PlacedClip> placed,
                        const std::string& fitted_name) {
  if (placed.empty()) throw ParameterError("placed_map_file: no clip placed");
  if (fitted.model.coordinates.rows() == 0) {
    throw ParameterError("placed_map_file: the map " + fitted_name +
                         " was read without its model (ReadOptions::model)");
  }
  MapFile file = fitted;  // parameters, skeleton, joints and model stay the fitted map's
  file.path.clear();
  file.blend.reset();  // of the fitted map's clips, not of these
  file.clips.clear();
  file.clip_of.clear();
  file.frame_of.clear();
  const int dims = static_cast<int>(fitted.coordinates.cols());
  Eigen::Index rows = 0;
  for (const PlacedClip& p : placed) {
    if (p.frames.empty() || p.coordinates.rows() != Eigen::Index(p.frames.size()) ||
        p.coordinates.cols() != dims) {
      throw ParameterError(
          "placed_map_file: " + p.record.path + " has " + std::to_string(p.frames.size()) +
          " frames and " + std::to_string(p.coordinates.rows()) + " by " +
          std::to_string(p.coordinates.cols()) + " coordinates; expected " +
          "at least one frame and one row of " + std::to_string(dims) + " per frame");
    }
    rows += p.coordinates.rows();
  }
  file.coordinates.resize(rows, dims);
  for (const PlacedClip& p : placed) {
    ClipRecord record = p.record;
    record.first_sample = file.num_samples();
    record.samples = static_cast<int>(p.frames.size());
    file.coordinates.middleRows(record.first_sample, record.samples) = p.coordinates;
    file.clip_of.insert(file.clip_of.end(), p.frames.size(), static_cast<int>(file.clips.size()));
    file.frame_of.insert(file.frame_of.end(), p.frames.begin(), p.frames.end());
    file.clips.push_back(std::move(record));
  }
  const std::size_t fitted_clips = fitted.clips.size();
  file.notes.push_back("every frame placed on the " +
                       std::string(embed::method_name(fitted.model.method)) + " map " +
                       fitted_name + " without refitting it (fitted on " +
                       std::to_string(fitted.model.coordinates.rows()) + " frames of " +
                       (fitted_clips == 1 ? base_name(fitted.clips.front().path)
                                          : std::to_string(fitted_clips) + " clips") +
                       ")");
  return file;
}

embed::Embedding embedding_for_csv(const MapFile& map, const Eigen::MatrixXd& coordinates) {
  embed::Embedding e;
  e.method = map.model.method;
  e.coordinates = coordinates;
  e.k_used = map.k_used;
  e.heat_used = map.heat_used;
  e.from_points = !map.dense;
  if (map.landmarks_used > 0) {
    e.landmarks.emplace();
    e.landmarks->frames.assign(std::size_t(map.landmarks_used), 0);
  }
  e.neighbor_search = map.neighbor_search;
  e.graph_components = map.graph_components;
  e.connecting_edges = map.connecting_edges;
  return e;
}

}  // namespace motionmap::mapfile
