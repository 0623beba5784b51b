#pragma once
// What the Motion menu lets the user choose, as plain values: the map parameters (Motion →
// Parameters…) and how drags blend and sketches become motions (Motion → Synthesis…), with their
// place in QSettings so that the parameters of the last good map are the next session's.
//
//   MapParameters map = readMapParameters(QSettings());       // defaults where a value is bad
//   SynthParameters synth = readSynthParameters(QSettings());
//   pipeline::ClipMapOptions options = map.options(embed::Method::Isomap);
//   writeParameters(settings, map, synth);
#include <optional>
#include <string>

#include <QString>

#include "motionmap/embed/embed.h"
#include "motionmap/features/features.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/synthesize.h"

class QSettings;

namespace motionmap::studio {

/// The map parameters the Motion → Parameters dialog edits (the rest are the library's defaults).
struct MapParameters {
  int k = 20;                  ///< neighbours (Isomap, LE, LLE)
  std::optional<double> heat;  ///< LE heat-kernel width; nothing = the library's automatic one
  features::FeatureKind features = features::FeatureKind::Quaternions;
  features::DistanceKind distance = features::DistanceKind::PointCloud;
  std::string exclude;  ///< regular expression of joints left out

  /// The library options for `method` (no callbacks).
  pipeline::ClipMapOptions options(embed::Method method) const;
  bool operator==(const MapParameters&) const = default;
};

/// How a drag blends and a sketch becomes a motion (Motion → Synthesis…): the library's options
/// and defaults, as `motionmap pose` / `synth` take them. The blend part goes into each map's
/// blender (changing it recomputes the map, or takes it from the cache); the motion part applies
/// to the next sketch, freeRoots to the next in-between.
struct SynthParameters {
  synth::BlendOptions blend;   ///< mode, K, reach (the up axis is the map's)
  synth::SynthOptions motion;  ///< speed (of a sketch not timed as drawn), output fps, smoothing
  /// A sketch keeps the timing of the gesture; false: it is followed at motion.speed (0: the
  /// clip's own median map speed).
  bool timedAsDrawn = true;
  /// An in-between's root stands where it stood in its clip at the first key only; at every later
  /// key it stands where the clips carry it (synth::InbetweenOptions::free_roots).
  bool freeRoots = false;
};

/// The map parameters saved in `settings` (keys "map/…"). A value from an older version or
/// edited by hand that the library would reject is dropped (its default stays) rather than
/// breaking every map of the session.
MapParameters readMapParameters(const QSettings& settings);
/// The synthesis parameters saved in `settings` (keys "synth/…"), with the same fall-back to the
/// defaults for bad values; motion options the library rejects as a whole are all left at theirs.
SynthParameters readSynthParameters(const QSettings& settings);
/// Saves both for readMapParameters and readSynthParameters.
void writeParameters(QSettings& settings, const MapParameters& map, const SynthParameters& synth);

/// The menu label of `method`: "PCA", "SVD", "MDS", "Isomap", "LE", "LLE".
QString methodLabel(embed::Method method);

}  // namespace motionmap::studio
