#pragma once
// What the window shows a map of, in two kinds behind one interface:
//  - ComputedMapSource: clips opened here and mapped by the MapController (a method and
//    parameters chosen in the Motion menu, sketches, added clips);
//  - SavedMapSource: a map file opened as it was made (File → Open map): its points drawn as a
//    density image, its clips loaded on demand on a worker (ClipLoader), the clip playing drawn
//    over it.
// The window asks the source shown for the clip playing, the map point of its frames, its part of
// the status line, which changes it refuses and the map sketches, keys and joint drags blend on
// (blendMap(): a saved map's blender is built once per blend options on a worker, SavedMapBlends),
// so it never asks which kind it has.
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <QObject>
#include <QString>
#include <QStringList>

#include "common/background_job.h"
#include "map/map_controller.h"
#include "motionmap/embed/embed.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/reach.h"

namespace motionmap::mapfile {
class SavedMap;
}

namespace motionmap::studio {

class ClipLoader;
class MapController;
class MapView;
class SkeletonView;

class MapSource : public QObject {
  Q_OBJECT
 public:
  /// What a user may ask of a map that a source can refuse.
  enum class Change {
    Recompute,  ///< another method or parameters
    AddClip,    ///< a clip joining the map
  };

  using QObject::QObject;

  virtual int clipCount() const = 0;
  /// The clip playing (nullptr: none yet).
  virtual const Clip* clip() const = 0;
  virtual int currentClip() const = 0;
  /// A clip asked for by selectClip is being loaded.
  virtual bool isLoadingClip() const { return false; }
  /// Makes clip `index` the one playing, with its skeleton in the 3-D view. True when it is now;
  /// false when `index` is out of range, when it cannot be loaded (failed() says why; the clip
  /// before stays) or while it loads (clipReady(index, frame) follows).
  virtual bool selectClip(int index, int frame) = 0;
  /// The map point of frame `frame` of the clip playing (nothing: the frame is not on the map).
  virtual std::optional<Eigen::Vector2d> framePoint(int frame) const = 0;
  /// The map's and the clip's part of the status line (empty: nothing to say yet).
  virtual QStringList statusParts() const = 0;
  /// The method of the map shown (nothing: no map shown).
  virtual std::optional<embed::Method> shownMethod() const = 0;
  /// The up axis of the clips as the map shown was made with them (Y without a map).
  virtual Axis upAxis() const = 0;
  /// Why `change` cannot be made on this map (empty: it can).
  virtual QString refusal(Change /*change*/) const { return {}; }
  /// The clips' file paths, in the map's order (clip i is "clip i + 1" in hover texts).
  virtual QStringList clipPaths() const = 0;
  /// The map points of clip `clip`'s samples (#samples by 2; empty out of range or without a
  /// map).
  virtual Eigen::MatrixXd clipPoints(int clip) const = 0;
  /// The map's samples: points (#samples by ≥ 2), each one's clip and frame; null members without
  /// a map. Valid until the map shown changes.
  struct Samples {
    const Eigen::MatrixXd* points = nullptr;
    const std::vector<int>* clipOf = nullptr;
    const std::vector<int>* frameOf = nullptr;
  };
  virtual Samples samples() const = 0;
  /// A sample near map point `point`: its row and its map distance.
  struct Near {
    int sample = -1;
    double distance = 0.0;
  };
  /// The `k` samples nearest `point`, nearest first: a scan of samples() (a saved map: its k-d
  /// tree).
  virtual std::vector<Near> nearestSamples(const Eigen::Vector2d& point, int k) const;
  /// The file a clip list names clip `clip` by (a saved map's relative paths resolved as it
  /// resolves them); its path as recorded by default.
  virtual QString clipFile(int clip) const { return clipPaths().value(clip); }
  /// Clip `clip` of the map (a saved map's loaded now when it is not in its cache); nullptr out
  /// of range or without clips. @throws a saved map's clip errors (mapfile::SavedMap::clip).
  virtual std::shared_ptr<const Clip> mapClip(int clip) const = 0;

  /// The map sketches, key poses and joint drags blend on, with its synth::MapBlender: the
  /// computed map shown (nullptr while it is computed); a saved map's once its blender is built
  /// for the synthesis parameters' blend options (nullptr before: see prepareBlend()).
  virtual std::shared_ptr<const MapResult> blendMap() const = 0;
  /// blendMap() for a synthesis on a worker thread: ready, or (a saved map) built there first.
  /// Empty when there is nothing to blend on.
  virtual MapSupply blendSupply() const { return {blendMap(), {}}; }
  /// Why blendMap() is nullptr now (empty when it is not, or when there is nothing to say: a map
  /// being computed): a saved map starts building its blender on a worker (busy() shows how far)
  /// and says so, or says why the last build failed (a clip missing: the library's message,
  /// naming the file).
  virtual QString prepareBlend() { return {}; }
  /// A synth::Reacher over `map` (a blendMap()) for joint drags: made here (milliseconds for a
  /// computed map); a saved map's is built on a worker (it reads every clip once), so nullptr
  /// with `why` saying it is being prepared (or why it could not be) until it is ready.
  /// @throws what synth::Reacher throws.
  virtual std::shared_ptr<const synth::Reacher> reacher(std::shared_ptr<const MapResult> map,
                                                        QString& why);

 signals:
  /// A clip selectClip had to load has arrived: the window shows it from `frame`.
  void clipReady(int clip, int frame);
  /// A clip could not be loaded (the library's message).
  void failed(const QString& message);
  /// A line for the status bar while a clip loads.
  void busy(const QString& text);
};

/// The legend's names of clips named `names` (file names): "clip 2: …" numbered from 1 as hover
/// numbers them, each without the prefix all share (cut at a separator: `_`, `-`, `.`, space,
/// `/` or `:`), so the part that tells them apart shows, marked by "…", and without an extension
/// all share: walk_happy_01.bvh and walk_happy_02.bvh give "clip 1: …happy_01" and
/// "clip 2: …happy_02". One name: unchanged.
/// Names up to kLegendShortName characters are only numbered (they fit whole).
QStringList legendNames(const QStringList& names);
inline constexpr qsizetype kLegendShortName = 12;

/// The clips of `maps` and the map it shows.
class ComputedMapSource : public MapSource {
  Q_OBJECT
 public:
  /// `maps` and the views must outlive this.
  ComputedMapSource(MapController* maps, MapView* mapView, SkeletonView* skeletonView,
                    QObject* parent = nullptr);

  /// `clip` alone is mapped (the map asked for by the caller); it plays, its skeleton shown with
  /// the camera framing it.
  void open(Clip clip);
  /// `clips` (at least one, all of the first's skeleton) are mapped together, the first playing.
  /// The reason when they cannot (none, another skeleton: nothing changes), else empty.
  QString openAll(std::vector<Clip> clips);
  /// `clip` joins the clips (a new set: the worker may still read the old one, so it is copied,
  /// never changed in place). The reason when it cannot (no clip open, another skeleton), else
  /// empty.
  QString add(Clip clip);
  /// The first clip's file name, "+ N more" with others: for the window's title.
  QString title() const;
  /// The map before stays on screen, greyed, while the map of `method` is computed (or fails:
  /// then it is back).
  void showComputing(embed::Method method);
  /// Draws the controller's current map; false when there is none.
  bool show();
  int clipCount() const override;
  const Clip* clip() const override;
  int currentClip() const override { return m_clipIndex; }
  bool selectClip(int index, int frame) override;
  std::optional<Eigen::Vector2d> framePoint(int frame) const override;
  QStringList statusParts() const override;
  std::optional<embed::Method> shownMethod() const override;
  Axis upAxis() const override;
  QStringList clipPaths() const override;
  Eigen::MatrixXd clipPoints(int clip) const override;
  Samples samples() const override;
  std::shared_ptr<const Clip> mapClip(int clip) const override;
  std::shared_ptr<const MapResult> blendMap() const override { return m_maps->current(); }

 private:
  MapController* m_maps;
  MapView* m_mapView;
  SkeletonView* m_skeletonView;
  int m_clipIndex = 0;
  embed::Method m_computing = embed::Method::Isomap;  ///< the method of the map being computed
};

/// A saved map as MapResults to blend on, one per blend options, each built once (its blender:
/// mapfile::make_blender, reading the clips on demand; the kriging mode, which blends every
/// sample, loads every clip) and shared by the threads that ask. The MapResult holds the map's
/// samples, coordinates, options and parameters as the file recorded them (no rowOfFrame: the
/// source maps frames to rows). Thread-safe.
class SavedMapBlends {
 public:
  explicit SavedMapBlends(std::shared_ptr<const mapfile::SavedMap> map);

  /// The map blended with `blend` (its up axis made the map's): built now unless it was, polling
  /// `control` (a caller finding another's build running waits for it, polling its own).
  /// @throws what mapfile::make_blender and SavedMap::clip throw (a clip missing or changed: an
  ///   Error naming the map file and the clip file), Cancelled.
  std::shared_ptr<const MapResult> get(synth::BlendOptions blend, const Control& control = {});
  /// The same when it is built; nullptr otherwise (never waits for a build).
  std::shared_ptr<const MapResult> find(synth::BlendOptions blend) const;
  /// The reacher over `map` (one get() returned), built now unless it was (reading every clip
  /// once, a clip at a time), polling `control`. @throws as get().
  std::shared_ptr<const synth::Reacher> reacher(const std::shared_ptr<const MapResult>& map,
                                                const Control& control = {});
  /// The same when it is built; nullptr otherwise.
  std::shared_ptr<const synth::Reacher> findReacher(const MapResult* map) const;

 private:
  std::string key(synth::BlendOptions& blend) const;

  std::shared_ptr<const mapfile::SavedMap> m_map;
  std::shared_ptr<const features::FeatureSet> m_samples;
  mutable std::mutex m_mutex;  ///< guards m_built and m_reachers
  std::map<std::string, std::shared_ptr<const MapResult>> m_built;
  std::map<const MapResult*, std::shared_ptr<const synth::Reacher>> m_reachers;  ///< of m_built's
  std::timed_mutex m_building;  ///< held by the build running (a blender or a reacher)
};

/// A map file shown as it was saved.
class SavedMapSource : public MapSource {
  Q_OBJECT
 public:
  /// Clips kept loaded: a drag blends samples of many clips (a library's variants of one motion
  /// lie side by side on its map); 32 clips of 6 000 frames are about 300 MB.
  static constexpr int kCachedClips = 32;

  /// Reads `path` (mapfile::read_map_file, without the placement model) and loads its first
  /// clip, so that a map whose clips are gone says so at once: throws what they throw. Nothing
  /// is shown before show(). `blend` gives the blend options sketches are synthesized with now
  /// (the synthesis parameters'; empty: the defaults).
  SavedMapSource(const QString& path, MapView* mapView, SkeletonView* skeletonView,
                 QObject* parent = nullptr, std::function<synth::BlendOptions()> blend = {});
  ~SavedMapSource() override;

  /// Draws the map's points as a density image (the first clip follows with selectClip), and
  /// starts building its blender (prepareBlend()).
  void show();
  /// "name.h5 (N points, C clips)", for the window's title.
  QString title() const;
  /// The frame of the first sample (where the map opens).
  int firstFrame() const;
  const std::shared_ptr<const mapfile::SavedMap>& map() const { return m_map; }
  ClipLoader* loader() const { return m_loader; }

  int clipCount() const override;
  const Clip* clip() const override { return m_clip.get(); }
  int currentClip() const override { return m_clipIndex; }
  bool isLoadingClip() const override;
  bool selectClip(int index, int frame) override;
  std::optional<Eigen::Vector2d> framePoint(int frame) const override;
  QStringList statusParts() const override;
  std::optional<embed::Method> shownMethod() const override;
  Axis upAxis() const override;
  QString refusal(Change change) const override;
  QStringList clipPaths() const override;
  Eigen::MatrixXd clipPoints(int clip) const override;
  Samples samples() const override;
  QString clipFile(int clip) const override;
  std::vector<Near> nearestSamples(const Eigen::Vector2d& point, int k) const override;
  std::shared_ptr<const Clip> mapClip(int clip) const override;
  std::shared_ptr<const MapResult> blendMap() const override;
  MapSupply blendSupply() const override;
  QString prepareBlend() override;
  std::shared_ptr<const synth::Reacher> reacher(std::shared_ptr<const MapResult> map,
                                                QString& why) override;
  /// A blender or a reacher is being built on this source's workers (prepareBlend(), reacher()).
  bool isPreparing() const { return m_prepare.running() || m_reach.running(); }

 private:
  synth::BlendOptions blendOptions() const { return m_blend ? m_blend() : synth::BlendOptions{}; }

  QString m_path;
  std::shared_ptr<const mapfile::SavedMap> m_map;
  MapView* m_mapView;
  SkeletonView* m_skeletonView;
  ClipLoader* m_loader;
  std::shared_ptr<const Clip> m_clip;  ///< the clip playing
  int m_clipIndex = -1;
  std::vector<int> m_rowOfFrame;  ///< the map row of each of its frames (−1: not a sample)
  int m_wantClip = -1;            ///< a clip being loaded to be shown, from m_wantFrame
  int m_wantFrame = 0;
  std::function<synth::BlendOptions()> m_blend;
  std::shared_ptr<SavedMapBlends> m_blends;  ///< shared with the synthesis' worker
  BackgroundJob m_prepare;                   ///< a blender being built ahead of its first use
  QString m_prepareError;                    ///< why the last build failed (empty: it did not)
  int m_preparedPercent = -1;                ///< the last progress shown by busy() (−1: none)
  BackgroundJob m_reach;                     ///< a reacher being built for the first joint drag
  QString m_reachError;                      ///< why the last one failed (empty: it did not)
  int m_reachPercent = -1;
};

}  // namespace motionmap::studio
