#pragma once
// What the window shows a map of, in two kinds behind one interface:
//  - ComputedMapSource: clips opened here and mapped by the MapController (a method and
//    parameters chosen in the Motion menu, sketches, added clips);
//  - SavedMapSource: a map file opened as it was made (File → Open map): its points drawn as a
//    density image, its clips loaded on demand on a worker (ClipLoader), the clip playing drawn
//    over it.
// The window asks the source shown for the clip playing, the map point of its frames, its part of
// the status line and which changes it refuses, so it never asks which kind it has.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <QObject>
#include <QString>
#include <QStringList>

#include "motionmap/embed/embed.h"
#include "motionmap/skeleton/skeleton.h"

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
    Sketch,     ///< a motion synthesized along a sketched path
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
  QStringList clipPaths() const override;
  Eigen::MatrixXd clipPoints(int clip) const override;
  Samples samples() const override;

 private:
  MapController* m_maps;
  MapView* m_mapView;
  SkeletonView* m_skeletonView;
  int m_clipIndex = 0;
  embed::Method m_computing = embed::Method::Isomap;  ///< the method of the map being computed
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
  /// is shown before show().
  SavedMapSource(const QString& path, MapView* mapView, SkeletonView* skeletonView,
                 QObject* parent = nullptr);
  ~SavedMapSource() override;

  /// Draws the map's points as a density image (the first clip follows with selectClip).
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
  QString refusal(Change change) const override;
  QStringList clipPaths() const override;
  Eigen::MatrixXd clipPoints(int clip) const override;
  Samples samples() const override;
  QString clipFile(int clip) const override;
  std::vector<Near> nearestSamples(const Eigen::Vector2d& point, int k) const override;

 private:
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
};

}  // namespace motionmap::studio
