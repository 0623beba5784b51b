#include "map/joint_drag.h"

#include <algorithm>

#include "map/map_controller.h"
#include "map/map_view.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "playback/playback.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

JointDrag::JointDrag(const MapController* maps, MapView* mapView, SkeletonView* skeletonView,
                     const Playback* playback, QObject* parent)
    : QObject(parent),
      m_maps(maps),
      m_mapView(mapView),
      m_skeletonView(skeletonView),
      m_playback(playback) {
  connect(skeletonView, &SkeletonView::jointDragStarted, this, &JointDrag::onStarted);
  connect(skeletonView, &SkeletonView::jointDragged, this, &JointDrag::onDragged);
  connect(skeletonView, &SkeletonView::jointDragFinished, this,
          [this] { m_skeletonView->setDragTarget(std::nullopt); });
  connect(maps, &MapController::finished, this, &JointDrag::updateAvailability);
  connect(skeletonView, &SkeletonView::skeletonChanged, this, &JointDrag::updateAvailability);
}

JointDrag::~JointDrag() = default;

void JointDrag::setAvailable(bool available) {
  m_available = available;
  updateAvailability();
}

void JointDrag::updateAvailability() {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  const bool on = m_available && map && map->blender &&
                  map->blender->skeleton().same_hierarchy(m_skeletonView->skeleton());
  m_skeletonView->setJointDragEnabled(on);
}

void JointDrag::onStarted(int joint, const Eigen::Vector3d&) {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  const Motion& shown = m_skeletonView->currentPose();
  if (!m_available || !map || !map->blender || m_playback->isPlaying() || shown.num_frames < 1 ||
      shown.num_joints != map->blender->skeleton().num_joints()) {
    m_skeletonView->cancelJointDrag();
    return;
  }
  try {
    if (m_map != map || !m_reacher) {
      // Each sample's joints, once per map (milliseconds at 10 000 frames).
      m_reacher.reset();
      m_map.reset();
      m_reacher = std::make_unique<synth::Reacher>(*map->blender);
      m_map = map;
    }
    const synth::MapBlender& blender = *map->blender;
    m_goal = synth::ReachGoal{};
    m_goal.joint = joint;
    m_goal.placement = synth::root_placement(shown, 0, blender.motion_root(), blender.options().up);
    // Pins stay where they are now (world positions of the pose shown, placed like the goal).
    const WorldPose& world = m_skeletonView->worldPose();
    for (const int pin : m_skeletonView->pinnedJoints()) {
      if (pin == joint || std::size_t(pin) >= world.positions.size()) continue;
      m_goal.pins.push_back({pin, world.positions[std::size_t(pin)], 1.0});
    }
    m_goal.start = m_mapView->pointer();
  } catch (const std::exception& e) {
    m_skeletonView->cancelJointDrag();
    emit failed(QString::fromStdString(e.what()));
  }
}

void JointDrag::onDragged(int joint, const Eigen::Vector3d& target) {
  if (!m_reacher || !m_map || joint != m_goal.joint || m_playback->isPlaying()) return;
  try {
    m_goal.target = target;
    synth::ReachResult r = m_reacher->reach(m_goal);
    m_goal.start = r.point;
    m_skeletonView->setPose(r.pose, 0);
    m_mapView->setPointer(r.point);
    const QString name =
        QString::fromStdString(m_map->blender->skeleton().joints[std::size_t(joint)].name);
    const QString summary = tr("%1 %2 from the mouse (%3 % of the height)")
                                .arg(name)
                                .arg(r.error, 0, 'g', 3)
                                .arg(100.0 * r.error_fraction, 0, 'f', 1);
    m_mapView->setHoverText(tr("pose reaching with %1").arg(name));
    m_last = std::move(r);
    emit reached(summary);
  } catch (const std::exception& e) {
    m_skeletonView->cancelJointDrag();
    emit failed(QString::fromStdString(e.what()));
  }
}

}  // namespace motionmap::studio
