#pragma once
// Posing by dragging a joint in the 3-D view: each move of the mouse asks the map for the valid
// point whose blended pose brings that joint closest to where the mouse puts it (synth::Reacher,
// with the pinned joints held where they were when the drag began), shows that pose and moves the
// map's pointer there. So every pose reached is a blend of real frames, and the map shows which.
//
// The pose stands where the pose shown when the drag began stood (its root's heading and floor
// position, synth::RootPlacement), as a drag on the map does; each step starts from the previous
// one's map point, so the body moves smoothly. A computed map only: a saved map's clips are read
// on demand, and scoring every sample's pose would read them all (`motionmap reach --map` does).
#include <memory>
#include <optional>

#include <Eigen/Core>
#include <QObject>
#include <QString>

#include "motionmap/synth/blender.h"
#include "motionmap/synth/reach.h"

namespace motionmap::studio {

class MapController;
class MapView;
class Playback;
class SkeletonView;
struct MapResult;

class JointDrag : public QObject {
  Q_OBJECT
 public:
  /// Poses `skeletonView` from the map `maps` shows, with the pointer on `mapView`; nothing
  /// while `playback` plays. All must outlive this.
  JointDrag(const MapController* maps, MapView* mapView, SkeletonView* skeletonView,
            const Playback* playback, QObject* parent = nullptr);
  ~JointDrag() override;

  /// Whether the map shown can be posed from (a computed map; not a saved one). Enables the 3-D
  /// view's joint dragging accordingly.
  void setAvailable(bool available);
  /// The last step's answer (nothing before a drag).
  const std::optional<synth::ReachResult>& last() const { return m_last; }

 signals:
  /// What the last step reached ("LeftHand 0.8 cm from the mouse (0.5 % of the height)").
  void reached(const QString& summary);
  void failed(const QString& message);

 private:
  void onStarted(int joint, const Eigen::Vector3d& at);
  void onDragged(int joint, const Eigen::Vector3d& target);
  void updateAvailability();

  const MapController* m_maps;
  MapView* m_mapView;
  SkeletonView* m_skeletonView;
  const Playback* m_playback;
  bool m_available = false;
  /// The map the reacher was made for (kept alive with it) and the reacher.
  std::shared_ptr<const MapResult> m_map;
  std::unique_ptr<synth::Reacher> m_reacher;
  synth::ReachGoal m_goal;  ///< the drag's placement, pins and start point
  std::optional<synth::ReachResult> m_last;
};

}  // namespace motionmap::studio
