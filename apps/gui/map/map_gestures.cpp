#include "map/map_gestures.h"

#include <cmath>
#include <stdexcept>

#include <QFileInfo>
#include <QLineF>

#include "map/clip_loader.h"
#include "map/map_controller.h"
#include "map/map_view.h"
#include "motionmap/mapfile/saved_map.h"
#include "playback/playback.h"
#include "scene/skeleton_view.h"

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
  connect(mapView, &MapView::dragFinished, this, [this] {
    m_dragFailed = false;
    m_inDrag = false;
  });
  // Any other pose shown (a frame, a new map's frame) ends the dragged pose; onDrag sets the flag
  // again after its own setPose.
  connect(skeletonView, &SkeletonView::poseChanged, this, [this] { m_showsDrag = false; });
}

void MapGestures::setSavedMap(std::shared_ptr<const mapfile::SavedMap> map, int neighbors,
                              ClipLoader* loader) {
  m_saved = std::move(map);
  m_neighbors = neighbors;
  m_waitingDrag.reset();
  if (loader != m_loader) {
    if (m_loader) disconnect(m_loader, nullptr, this, nullptr);
    m_loader = loader;
    if (m_loader) {
      connect(m_loader, &ClipLoader::loaded, this, &MapGestures::onClipLoaded);
      connect(m_loader, &ClipLoader::failed, this, [this](int, const QString& message) {
        if (!m_waitingDrag) return;
        m_waitingDrag.reset();
        m_mapView->setHoverText({});
        emit failed(message);
      });
    }
  }
}

void MapGestures::onClipLoaded() {
  if (!m_waitingDrag || !m_loader || m_loader->pending() > 0) return;
  const Eigen::Vector2d point = *m_waitingDrag;
  m_waitingDrag.reset();
  onDrag(point);
}

int MapGestures::sampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const {
  if (m_mapView->hidesSamples()) return shownSampleNear(point, pixel);
  if (m_saved) {
    const mapfile::Neighbor hit = m_saved->index().nearest(point);
    if (hit.sample < 0) return -1;
    const auto& xy = m_saved->file().coordinates;
    const QPointF at = m_mapView->toWidget(Eigen::Vector2d(xy(hit.sample, 0), xy(hit.sample, 1)));
    return QLineF(at, pixel).length() <= kNearPixels ? hit.sample : -1;
  }
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || !point.allFinite()) return -1;
  // The blender knows the nearest sample (library search); the app only judges the pixel distance.
  const int sample = map->blender->locate(point).validity.nearest_sample;
  const QPointF at = m_mapView->toWidget(map->blender->sample_point(sample));
  return QLineF(at, pixel).length() <= kNearPixels ? sample : -1;
}

int MapGestures::shownSampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const {
  if (!point.allFinite()) return -1;
  const Eigen::MatrixXd* xy = nullptr;
  std::shared_ptr<const MapResult> map;
  if (m_saved) {
    xy = &m_saved->file().coordinates;
  } else {
    map = m_maps->current();
    if (!map) return -1;
    xy = &map->map.embedding.coordinates;
  }
  const auto near = [&](int sample) {
    const QPointF at = m_mapView->toWidget(Eigen::Vector2d((*xy)(sample, 0), (*xy)(sample, 1)));
    return QLineF(at, pixel).length() <= kNearPixels;
  };
  if (!m_saved) {
    // A computed map's samples, scanned: the nearest shown one.
    int best = -1;
    double bestDistance = INFINITY;
    for (Eigen::Index i = 0; i < xy->rows(); ++i) {
      if (!m_mapView->sampleShown(int(i))) continue;
      const double d = (xy->row(i).head<2>().transpose() - point).norm();
      if (d < bestDistance) best = int(i), bestDistance = d;
    }
    return best >= 0 && near(best) ? best : -1;
  }
  // A saved map's k-d tree, asked for more neighbours until a shown one or the pixel range ends.
  for (int k = 64;; k *= 16) {
    const std::vector<mapfile::Neighbor> hits = m_saved->index().nearest(point, k);
    for (const mapfile::Neighbor& hit : hits) {
      if (!m_mapView->sampleShown(hit.sample)) continue;
      return near(hit.sample) ? hit.sample : -1;
    }
    if (int(hits.size()) < k || hits.empty() || !near(hits.back().sample)) return -1;
  }
}

void MapGestures::onHover(const Eigen::Vector2d& point, const QPointF& pixel) {
  const int sample = sampleNear(point, pixel);
  if (sample < 0) return m_mapView->setHoverText({});
  if (m_saved) {
    const mapfile::MapFile& file = m_saved->file();
    const int clip = file.clip_of[std::size_t(sample)];
    const QString name =
        QFileInfo(QString::fromStdString(file.clips[std::size_t(clip)].path)).fileName();
    return m_mapView->setHoverText(tr("clip %1 of %2 (%3), frame %4")
                                       .arg(clip + 1)
                                       .arg(m_saved->num_clips())
                                       .arg(name)
                                       .arg(file.frame_of[std::size_t(sample)]));
  }
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
  if (m_saved) {
    const mapfile::MapFile& file = m_saved->file();
    emit frameClicked(file.clip_of[std::size_t(sample)], file.frame_of[std::size_t(sample)]);
    return;
  }
  const features::FeatureSet& set = *m_maps->current()->map.features;
  emit frameClicked(set.clip_of[std::size_t(sample)], set.frame_of[std::size_t(sample)]);
}

void MapGestures::onDrag(const Eigen::Vector2d& point) {
  if (m_saved) {
    if (m_playback->isPlaying() || !point.allFinite() || m_dragFailed) return;
    try {
      if (m_loader) {
        // The clips of the samples blended: from the cache, or loading (then blended on arrival).
        bool ready = true;
        for (const int c : m_saved->clips_near(point, m_neighbors)) {
          if (const auto why = m_loader->failure(c)) throw std::runtime_error(why->toStdString());
          ready = m_loader->request(c) && ready;
        }
        if (!ready) {
          m_waitingDrag = point;
          m_mapView->setPointer(point);
          m_mapView->setHoverText(tr("loading clips…"));
          return;
        }
      }
      m_waitingDrag.reset();
      const Axis up = m_saved->file().options.features.up;
      mapfile::SavedPose pose = m_saved->pose_at(point, m_neighbors, up);
      // pose_at's root (the map's motion root, as a computed map's blender has it) faces
      // heading 0 at the origin: placed like a computed map's blends.
      const int root = pose.root;
      if (!m_inDrag || !m_placement) {
        m_inDrag = true;
        const Motion& shown = m_skeletonView->currentPose();
        m_placement = shown.num_frames > 0 && shown.num_joints == pose.pose.num_joints
                          ? synth::root_placement(shown, 0, root, up, pose.ancestors)
                          : synth::RootPlacement{};
      }
      synth::place_root(pose.pose, root, *m_placement, up);
      m_skeletonView->setPose(pose.pose, 0);
      m_showsDrag = true;
      m_mapView->setPointer(point);
      m_mapView->setHoverText(
          pose.outside ? tr("blend of %1 samples (outside the data)").arg(pose.around.size())
                       : tr("blend of %1 samples").arg(pose.around.size()));
    } catch (const std::exception& e) {
      m_dragFailed = true;  // the same error at every move: said once per drag
      emit failed(QString::fromStdString(e.what()));
    }
    return;
  }
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || m_playback->isPlaying() || !point.allFinite()) return;
  try {
    const synth::MapWeights weights = map->blender->locate(point);
    if (!m_inDrag || !m_placement) {
      // The drag's placement: the pose shown now (a frame, or the last dragged pose, which stands
      // where its own drag began), else the nearest sample's frame.
      m_inDrag = true;
      const synth::MapBlender& blender = *map->blender;
      const Motion& shown = m_skeletonView->currentPose();
      if (shown.num_frames > 0 && shown.num_joints == blender.skeleton().num_joints()) {
        m_placement = synth::root_placement(shown, 0, blender.motion_root(), blender.options().up,
                                            blender.root_ancestors());
      } else {
        const features::FeatureSet& set = *map->map.features;
        const auto row = std::size_t(weights.validity.nearest_sample);
        m_placement = synth::root_placement(
            (*m_maps->clips())[std::size_t(set.clip_of[row])].motion, set.frame_of[row],
            blender.motion_root(), blender.options().up, blender.root_ancestors());
      }
    }
    m_skeletonView->setPose(map->blender->pose(weights, *m_placement), 0);
    m_showsDrag = true;
    const synth::PointValidity& validity = weights.validity;
    m_mapView->setPointer(validity.point);
    m_mapView->setHoverText(validity.clamped ? tr("blend (outside the data: moved to its edge)")
                                             : tr("blend"));
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
  }
}

}  // namespace motionmap::studio
