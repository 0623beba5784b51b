#include "map/joint_drag.h"

#include <algorithm>

#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "playback/playback.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

JointDrag::JointDrag(std::function<MapSource*()> source, MapView* mapView,
                     SkeletonView* skeletonView, const Playback* playback, QObject* parent)
    : QObject(parent),
      m_source(std::move(source)),
      m_mapView(mapView),
      m_skeletonView(skeletonView),
      m_playback(playback) {
  connect(skeletonView, &SkeletonView::jointDragStarted, this, &JointDrag::onStarted);
  connect(skeletonView, &SkeletonView::jointDragged, this, &JointDrag::onDragged);
  connect(skeletonView, &SkeletonView::jointDragFinished, this,
          [this] { m_skeletonView->setDragTarget(std::nullopt); });
  connect(skeletonView, &SkeletonView::skeletonChanged, this, &JointDrag::updateAvailability);
  updateAvailability();
}

JointDrag::~JointDrag() = default;

void JointDrag::updateAvailability() {
  // The map may still be on its way (computed, or a saved map's blender built): a drag then
  // says so (onStarted).
  m_skeletonView->setJointDragEnabled(m_skeletonView->skeleton().num_joints() > 0);
}

void JointDrag::onStarted(int joint, const Eigen::Vector3d&) {
  MapSource* source = m_source();
  std::shared_ptr<const MapResult> map = source ? source->blendMap() : nullptr;
  const Motion& shown = m_skeletonView->currentPose();
  if (!map || !map->blender) {
    m_skeletonView->cancelJointDrag();
    if (const QString why = source ? source->prepareBlend() : QString(); !why.isEmpty())
      emit failed(why);
    return;
  }
  if (m_playback->isPlaying() || shown.num_frames < 1 ||
      !map->blender->skeleton().same_hierarchy(m_skeletonView->skeleton()) ||
      shown.num_joints != map->blender->skeleton().num_joints()) {
    m_skeletonView->cancelJointDrag();
    return;
  }
  try {
    if (m_map != map || !m_reacher) {
      m_reacher.reset();
      m_map.reset();
      QString why;
      m_reacher = source->reacher(map, why);
      if (!m_reacher) {  // a saved map's: being built on a worker, or it could not be
        m_skeletonView->cancelJointDrag();
        if (!why.isEmpty()) emit failed(why);
        return;
      }
      m_map = map;
    }
    const synth::MapBlender& blender = *map->blender;
    m_goal = synth::ReachGoal{};
    m_goal.joint = joint;
    m_goal.placement = synth::root_placement(shown, 0, blender.motion_root(), blender.options().up,
                                             blender.root_ancestors());
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
