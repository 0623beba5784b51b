#pragma once
// The mouse on the map: hovering names the frame under the pointer, a click near the trajectory
// asks to play that frame, and a drag shows the pose the map's blender makes at the mouse (with
// where the library took it: inside the data, or moved to its edge). Sketches are the window's
// (they start a synthesis).
//
// A dragged pose stands where the pose shown when the drag began stood: the blender's pose faces
// heading 0 at the origin (synth::MapBlender::pose, mapfile::SavedMap::pose_at), so it is turned
// to that pose's heading and moved to its floor position (synth::RootPlacement), and the body
// never spins or jumps while dragging, on a computed or a saved map. On release the dragged pose
// stays, with the pointer at the map point it was blended at (the point under the mouse, or where
// the library moved it); the next frame shown (play, a step, the slider, a click, a new map) puts
// the pose and the pointer back on that frame.
#include <memory>
#include <optional>

#include <Eigen/Core>
#include <QObject>
#include <QPointF>
#include <QString>

#include "motionmap/synth/blender.h"

namespace motionmap::studio {}  // namespace motionmap::studio
namespace motionmap::mapfile {
class SavedMap;
}
namespace motionmap::studio {

class ClipLoader;
class MapController;
class MapView;
class Playback;
class SkeletonView;

class MapGestures : public QObject {
  Q_OBJECT
 public:
  /// How close (pixels) to a sample's map point a hover or a click must be.
  static constexpr double kNearPixels = 12.0;

  /// Handles `mapView`'s gestures on the map `maps` shows, posing `skeletonView`; drags are
  /// ignored while `playback` plays. All must outlive this.
  MapGestures(const MapController* maps, MapView* mapView, SkeletonView* skeletonView,
              const Playback* playback, QObject* parent = nullptr);

  /// The map row nearest `pixel` (at map point `point`) within kNearPixels, or −1. On a saved
  /// map: a k-d tree lookup (mapfile::PointIndex), O(log N).
  /// Samples a colouring by label hides (MapView::sampleShown) are never found.
  int sampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const;

  /// A saved map shown instead of the controller's (nullptr: back to the controller's). Drags then
  /// blend its `neighbors` nearest samples (mapfile::SavedMap::pose_at) once their clips are
  /// loaded: clips not in the map's cache are asked of `loader` (on its worker thread) and the
  /// drag's last point is blended when they arrive, so no mouse event waits for a file.
  void setSavedMap(std::shared_ptr<const mapfile::SavedMap> map, int neighbors, ClipLoader* loader);
  /// A saved map's drags blend `neighbors` samples from now on.
  void setNeighbors(int neighbors) { m_neighbors = neighbors; }

  /// Whether the 3-D view shows a dragged pose (from the first move of a drag until another frame
  /// is shown).
  bool showsDraggedPose() const { return m_showsDrag; }
  /// Where the dragged poses stand (the pose shown when the drag began); nothing before a drag.
  const std::optional<synth::RootPlacement>& dragPlacement() const { return m_placement; }

 signals:
  /// A click near the trajectory: frame `frame` of clip `clip`.
  void frameClicked(int clip, int frame);
  /// The library's error for a drag.
  void failed(const QString& message);

 private:
  /// sampleNear while some samples are hidden: the nearest shown one within kNearPixels.
  int shownSampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const;
  void onHover(const Eigen::Vector2d& point, const QPointF& pixel);
  void onClick(const Eigen::Vector2d& point, const QPointF& pixel);
  void onDrag(const Eigen::Vector2d& point);

  const MapController* m_maps;
  MapView* m_mapView;
  SkeletonView* m_skeletonView;
  const Playback* m_playback;
  void onClipLoaded();
  std::shared_ptr<const mapfile::SavedMap> m_saved;
  int m_neighbors = 12;
  ClipLoader* m_loader = nullptr;
  std::optional<Eigen::Vector2d> m_waitingDrag;  ///< a drag point whose clips are loading
  bool m_dragFailed = false;  ///< a saved map's blend failed: this drag is ignored (one message)
  bool m_inDrag = false;      ///< a drag is under way (its placement is taken)
  bool m_showsDrag = false;   ///< the 3-D view shows a dragged pose
  std::optional<synth::RootPlacement> m_placement;  ///< of the pose shown when the drag began
};

}  // namespace motionmap::studio
