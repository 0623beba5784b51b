#include "map/map_source.h"

#include <QFileInfo>

#include "common/parameters.h"
#include "export/map_export.h"
#include "map/clip_loader.h"
#include "map/map_controller.h"
#include "map/map_view.h"
#include "motionmap/mapfile/saved_map.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

// ---- ComputedMapSource ----

ComputedMapSource::ComputedMapSource(MapController* maps, MapView* mapView,
                                     SkeletonView* skeletonView, QObject* parent)
    : MapSource(parent), m_maps(maps), m_mapView(mapView), m_skeletonView(skeletonView) {
  connect(maps, &MapController::started, this,
          [this](embed::Method method) { m_computing = method; });
}

void ComputedMapSource::open(Clip clip) {
  auto clips = std::make_shared<std::vector<Clip>>();
  clips->push_back(std::move(clip));
  m_maps->setClips(std::move(clips));
  m_clipIndex = 0;
  m_skeletonView->setSkeleton(this->clip()->skeleton);
}

QString ComputedMapSource::add(Clip clip) {
  const auto& open = m_maps->clips();
  if (!open) return tr("Open a clip first: added clips join its map");
  if (!clip.skeleton.same_hierarchy(open->front().skeleton)) {
    return tr("%1 has another skeleton than %2 (joint names or parents differ): it cannot join "
              "the map")
        .arg(QString::fromStdString(clip.path), QString::fromStdString(open->front().path));
  }
  auto clips = std::make_shared<std::vector<Clip>>(*open);
  clips->push_back(std::move(clip));
  m_maps->setClips(std::move(clips));
  return {};
}

QString ComputedMapSource::title() const {
  if (clipCount() == 0) return {};
  const std::vector<Clip>& clips = *m_maps->clips();
  QString title = QFileInfo(QString::fromStdString(clips.front().path)).fileName();
  if (clips.size() > 1) title += tr(" + %n more", nullptr, int(clips.size()) - 1);
  return title;
}

void ComputedMapSource::showComputing(embed::Method method) {
  const QString text = tr("Computing the %1 map…").arg(methodLabel(method));
  if (m_mapView->hasMap()) {
    m_mapView->setBusyText(text);
    m_mapView->setPointer(std::nullopt);
  } else {
    m_mapView->clearMap(text);
  }
}

bool ComputedMapSource::show() {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map) return false;
  m_mapView->setMap(map->map.embedding.coordinates, map->map.features->segment_starts,
                    mapPlotOptions(*map, *m_maps->clips()));
  m_mapView->setShadingReach(map->blender ? map->blender->reach_distance() : 0.0);
  return true;
}

int ComputedMapSource::clipCount() const {
  return m_maps->clips() ? int(m_maps->clips()->size()) : 0;
}

const Clip* ComputedMapSource::clip() const {
  if (m_clipIndex < 0 || m_clipIndex >= clipCount()) return nullptr;
  return &(*m_maps->clips())[std::size_t(m_clipIndex)];
}

bool ComputedMapSource::selectClip(int index, int /*frame*/) {
  if (index < 0 || index >= clipCount()) return false;
  if (index != m_clipIndex) {
    m_clipIndex = index;
    m_skeletonView->setSkeleton(clip()->skeleton, /*keepCamera=*/true);  // its own bone lengths
  }
  return true;
}

std::optional<Eigen::Vector2d> ComputedMapSource::framePoint(int frame) const {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || m_clipIndex >= int(map->rowOfFrame.size()) || frame < 0 ||
      frame >= int(map->rowOfFrame[std::size_t(m_clipIndex)].size()))
    return std::nullopt;
  return map->blender->sample_point(map->rowOfFrame[std::size_t(m_clipIndex)][std::size_t(frame)]);
}

QStringList ComputedMapSource::statusParts() const {
  QStringList parts;
  const Clip* shown = clip();
  if (!shown) return parts;
  if (clipCount() > 1) parts << tr("clip %1 of %2").arg(m_clipIndex + 1).arg(clipCount());
  parts << tr("%1 frames").arg(shown->motion.num_frames)
        << tr("%1 fps").arg(shown->motion.fps(), 0, 'g', 4);
  if (const std::shared_ptr<const MapResult> map = m_maps->current()) {
    parts << QString::fromStdString(map->parameters) << tr("%1 s").arg(map->seconds, 0, 'f', 2);
    if (map->map.metrics) {
      parts << tr("trustworthiness %1")
                   .arg(map->map.metrics->neighborhood.trustworthiness, 0, 'f', 3);
    }
  } else if (m_maps->isComputing()) {
    parts << tr("computing %1…").arg(methodLabel(m_computing));
  }
  return parts;
}

std::optional<embed::Method> ComputedMapSource::shownMethod() const {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map) return std::nullopt;
  return map->options.embed.method;
}

// ---- SavedMapSource ----

SavedMapSource::SavedMapSource(const QString& path, MapView* mapView, SkeletonView* skeletonView,
                               QObject* parent)
    : MapSource(parent),
      m_path(path),
      m_map(std::make_shared<const mapfile::SavedMap>(
          mapfile::read_map_file(path.toStdString(), {.model = false}), kCachedClips)),
      m_mapView(mapView),
      m_skeletonView(skeletonView),
      m_loader(new ClipLoader(this)) {
  m_map->clip(0);  // its first clip: loaded now, so a map whose clips are gone says so at once
  m_loader->setMap(m_map);
  connect(m_loader, &ClipLoader::loaded, this, [this](int c) {
    if (c != m_wantClip) return;
    m_wantClip = -1;
    emit clipReady(c, m_wantFrame);
  });
  connect(m_loader, &ClipLoader::failed, this, [this](int c, const QString& message) {
    if (c != m_wantClip) return;
    m_wantClip = -1;
    emit failed(message);
  });
}

SavedMapSource::~SavedMapSource() {
  m_loader->setMap(nullptr);
}

void SavedMapSource::show() {
  render::MapPlotOptions options;
  options.line_width = 1.0;  // the density shows between the strokes
  m_mapView->setDensityMap(
      std::shared_ptr<const Eigen::MatrixXd>(m_map, &m_map->file().coordinates),
      Eigen::MatrixXd(0, 2), options);
  m_mapView->setShadingReach(0.0);
}

QString SavedMapSource::title() const {
  return tr("%1 (%2 points, %3 clips)")
      .arg(QFileInfo(m_path).fileName())
      .arg(m_map->file().num_samples())
      .arg(clipCount());
}

int SavedMapSource::firstFrame() const {
  const mapfile::MapFile& file = m_map->file();
  return file.frame_of.empty() ? 0 : file.frame_of.front();
}

int SavedMapSource::clipCount() const {
  return m_map->num_clips();
}

bool SavedMapSource::isLoadingClip() const {
  return m_loader->pending() > 0;
}

bool SavedMapSource::selectClip(int index, int frame) {
  if (index < 0 || index >= clipCount()) return false;
  if (index == m_clipIndex && m_clip) return true;
  if (const auto why = m_loader->failure(index)) {
    emit failed(*why);
    return false;
  }
  const mapfile::MapFile& file = m_map->file();
  if (!m_loader->request(index)) {  // loading on the worker: clipReady follows its arrival
    m_wantClip = index;
    m_wantFrame = frame;
    emit busy(tr("Loading clip %1 of %2 (%3)…")
                  .arg(index + 1)
                  .arg(clipCount())
                  .arg(QString::fromStdString(file.clips[std::size_t(index)].path)));
    return false;
  }
  m_wantClip = -1;
  std::shared_ptr<const Clip> loaded;
  try {
    loaded = m_map->clip(index);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));  // the clip before stays
    return false;
  }
  const bool first = !m_clip;
  m_clip = std::move(loaded);
  m_clipIndex = index;
  m_skeletonView->setSkeleton(m_clip->skeleton, /*keepCamera=*/!first);
  const mapfile::ClipRecord& record = file.clips[std::size_t(index)];
  m_rowOfFrame.assign(std::size_t(m_clip->motion.num_frames), -1);
  for (int r = record.first_sample; r < record.first_sample + record.samples; ++r)
    m_rowOfFrame[std::size_t(file.frame_of[std::size_t(r)])] = r;
  m_mapView->setTrajectory(file.coordinates.middleRows(record.first_sample, record.samples));
  return true;
}

std::optional<Eigen::Vector2d> SavedMapSource::framePoint(int frame) const {
  const int row =
      frame >= 0 && frame < int(m_rowOfFrame.size()) ? m_rowOfFrame[std::size_t(frame)] : -1;
  if (row < 0) return std::nullopt;
  const auto& xy = m_map->file().coordinates;
  return Eigen::Vector2d(xy(row, 0), xy(row, 1));
}

QStringList SavedMapSource::statusParts() const {
  const mapfile::MapFile& file = m_map->file();
  QStringList parts;
  parts << tr("map file: %1 points, %2 clips").arg(file.num_samples()).arg(clipCount())
        << QString::fromStdString(file.parameters);
  if (m_clip) {
    parts << tr("clip %1 of %2: %3")
                 .arg(m_clipIndex + 1)
                 .arg(clipCount())
                 .arg(QFileInfo(QString::fromStdString(m_clip->path)).fileName())
          << tr("%1 frames").arg(m_clip->motion.num_frames)
          << tr("%1 fps").arg(m_clip->motion.fps(), 0, 'g', 4);
  }
  return parts;
}

std::optional<embed::Method> SavedMapSource::shownMethod() const {
  return m_map->file().options.embed.method;
}

QString SavedMapSource::refusal(Change change) const {
  switch (change) {
    case Change::Recompute:
      return tr("The saved map is shown as it was made (%1); open clips to compute maps of other "
                "methods")
          .arg(QString::fromStdString(m_map->file().parameters));
    case Change::AddClip:
      return tr(
          "A saved map is open: clips cannot join it without refitting (open a clip to start a "
          "new map, or place clips on the map with `motionmap map NEW --onto`)");
    case Change::Sketch:
      return tr("Sketching on a saved map is not supported in Studio; write the path as CSV and "
                "run `motionmap synth --map %1 --path PATH.csv -o new.bvh`")
          .arg(QString::fromStdString(m_map->file().path));
  }
  return {};
}

}  // namespace motionmap::studio
