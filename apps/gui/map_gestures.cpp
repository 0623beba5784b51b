#include "map_gestures.h"

#include <QLineF>

#include "map_controller.h"
#include "map_view.h"
#include "playback.h"
#include "skeleton_view.h"

namespace motionmap::studio {

MapGestures::MapGestures(const MapController* maps, MapView* mapView, SkeletonView* skeletonView,
                         const Playback* playback, QObject* parent)
    : QObject(parent),
      m_maps(maps),
      m_mapView(mapView),
      m_skeletonView(skeletonView),
      m_playback(playback) {
  connect(mapView, &MapView::hovered, this, &MapGestures::onHover);
  connect(mapView, &MapView::clicked, this, &MapGestures::onClick);
  connect(mapView, &MapView::dragged, this, &MapGestures::onDrag);
}

int MapGestures::sampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || !point.allFinite()) return -1;
  // The blender knows the nearest sample (library search); the app only judges the pixel distance.
  const int sample = map->blender->locate(point).validity.nearest_sample;
  const QPointF at = m_mapView->toWidget(map->blender->sample_point(sample));
  return QLineF(at, pixel).length() <= kNearPixels ? sample : -1;
}

void MapGestures::onHover(const Eigen::Vector2d& point, const QPointF& pixel) {
  const int sample = sampleNear(point, pixel);
  if (sample < 0) return m_mapView->setHoverText({});
  const features::FeatureSet& set = *m_maps->current()->map.features;
  const int clip = set.clip_of[std::size_t(sample)];
  const int frame = set.frame_of[std::size_t(sample)];
  m_mapView->setHoverText(m_maps->clips()->size() > 1
                              ? tr("clip %1, frame %2").arg(clip + 1).arg(frame)
                              : tr("frame %1").arg(frame));
}

void MapGestures::onClick(const Eigen::Vector2d& point, const QPointF& pixel) {
  const int sample = sampleNear(point, pixel);
  if (sample < 0) return;
  const features::FeatureSet& set = *m_maps->current()->map.features;
  emit frameClicked(set.clip_of[std::size_t(sample)], set.frame_of[std::size_t(sample)]);
}

void MapGestures::onDrag(const Eigen::Vector2d& point) {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || m_playback->isPlaying() || !point.allFinite()) return;
  try {
    const synth::MapWeights weights = map->blender->locate(point);
    m_skeletonView->setPose(map->blender->pose(weights), 0);
    const synth::PointValidity& validity = weights.validity;
    m_mapView->setPointer(validity.point);
    m_mapView->setHoverText(validity.clamped ? tr("blend (outside the data: moved to its edge)")
                                             : tr("blend"));
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
  }
}

}  // namespace motionmap::studio
