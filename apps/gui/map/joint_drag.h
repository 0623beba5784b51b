#pragma once
// Posing by dragging a joint in the 3-D view: each move of the mouse asks the map for the valid
// point whose blended pose brings that joint closest to where the mouse puts it (synth::Reacher,
// with the pinned joints held where they were when the drag began), shows that pose and moves the
// map's pointer there. So every pose reached is a blend of real frames, and the map shows which.
//
// The pose stands where the pose shown when the drag began stood (its root's heading and floor
// position, synth::RootPlacement), as a drag on the map does; each step starts from the previous
// one's map point, so the body moves smoothly. On a computed map and on a saved one alike: the map
// is the source's blendMap() (a saved map's blender, built on a worker; a drag before it is ready
// says so). The reacher is made once per map at the first drag (MapSource::reacher); a saved
// map's is built on a worker, as it reads every clip once (a clip at a time, as `motionmap reach
// --map` does): a drag before it is ready says so.
#include <functional>
#include <memory>
#include <optional>

#include <Eigen/Core>
#include <QObject>
#include <QString>

#include "motionmap/synth/blender.h"
#include "motionmap/synth/reach.h"

namespace motionmap::studio {

class MapSource;
class MapView;
class Playback;
class SkeletonView;
struct MapResult;

class JointDrag : public QObject {
  Q_OBJECT
 public:
  /// Poses `skeletonView` from the map `source` gives now (its blendMap()), with the pointer on
  /// `mapView`; nothing while `playback` plays. All must outlive this.
  JointDrag(std::function<MapSource*()> source, MapView* mapView, SkeletonView* skeletonView,
            const Playback* playback, QObject* parent = nullptr);
  ~JointDrag() override;

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

  std::function<MapSource*()> m_source;
  MapView* m_mapView;
  SkeletonView* m_skeletonView;
  const Playback* m_playback;
  /// The map the reacher was made for (kept alive with it) and the reacher.
  std::shared_ptr<const MapResult> m_map;
  std::shared_ptr<const synth::Reacher> m_reacher;
  synth::ReachGoal m_goal;  ///< the drag's placement, pins and start point
  std::optional<synth::ReachResult> m_last;
};

}  // namespace motionmap::studio
