#include "motionmap/pipeline/feature_cache.h"

namespace motionmap::pipeline {

std::string feature_key(const features::FeatureOptions& o) {
  // The exclude pattern last and length-prefixed: it may hold any character.
  return std::string(features::feature_kind_name(o.features)) + "|" +
         std::string(features::distance_kind_name(o.distance)) + "|" +
         std::string(axis_name(o.up)) + "|" + std::to_string(o.first_frame) + "|" +
         std::to_string(o.end_frame) + "|" + std::to_string(o.stride) + "|" +
         (o.keep_first ? "1" : "0") + "|" + std::string(features::joint_selection_name(o.joints)) +
         "|" + std::to_string(o.exclude.size()) + ":" + o.exclude;
}

std::shared_ptr<const features::FeatureSet> FeatureCache::get(
    std::span<const Clip> clips, const features::FeatureOptions& options, bool need_distances,
    const Control& control) {
  std::lock_guard<std::mutex> lock(m_mutex);
  const std::string key = feature_key(options);
  auto it = m_sets.find(key);
  if (it != m_sets.end() && (!need_distances || it->second->has_distances())) return it->second;

  std::shared_ptr<features::FeatureSet> set;
  if (it == m_sets.end()) {
    const features::Distances when =
        need_distances ? features::Distances::Now : features::Distances::Later;
    set = std::make_shared<features::FeatureSet>(
        features::build_features(clips, options, control, when));
  } else {
    // A copy, so the set already handed out (perhaps being read) never changes.
    set = std::make_shared<features::FeatureSet>(*it->second);
    features::add_distances(*set, control);
  }
  m_sets[key] = set;
  return set;
}

void FeatureCache::clear() {
  std::lock_guard<std::mutex> lock(m_mutex);
  m_sets.clear();
}

int FeatureCache::size() const {
  std::lock_guard<std::mutex> lock(m_mutex);
  return static_cast<int>(m_sets.size());
}

}  // namespace motionmap::pipeline
