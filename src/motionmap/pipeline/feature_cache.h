#pragma once
// Feature sets shared between the maps of one list of clips: each set is built once per feature
// key (the FeatureOptions) and handed out as a shared, immutable FeatureSet, whichever of the six
// methods asks. D is built on the first request that needs it (MDS, Isomap, LE, LLE, metrics),
// never for PCA and SVD alone.
//
//   motionmap::pipeline::FeatureCache cache;                // one per list of clips
//   auto pca = map_clips(clips, pca_options, control, &cache);     // X only
//   auto iso = map_clips(clips, isomap_options, control, &cache);  // the same X, D added once
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>

#include "motionmap/core/control.h"
#include "motionmap/features/features.h"

namespace motionmap::pipeline {

/// A string that is equal for two FeatureOptions exactly when they select the same samples and
/// build the same X and D.
std::string feature_key(const features::FeatureOptions& options);

class FeatureCache {
 public:
  /// The features of `clips` for `options`, with D when `need_distances`. Built (or D added)
  /// through `control` when the cache has no such set yet; a set once handed out never changes.
  /// Thread-safe: concurrent callers wait for each other. Every call must pass the same clips:
  /// clear() the cache when they change.
  /// @throws as features::build_features(); Cancelled (the cache is then left as it was).
  std::shared_ptr<const features::FeatureSet> get(std::span<const Clip> clips,
                                                  const features::FeatureOptions& options,
                                                  bool need_distances, const Control& control = {});

  /// Forgets every set (sets already handed out stay valid).
  void clear();
  /// Sets held.
  int size() const;

 private:
  mutable std::mutex m_mutex;
  std::map<std::string, std::shared_ptr<const features::FeatureSet>> m_sets;
};

}  // namespace motionmap::pipeline
