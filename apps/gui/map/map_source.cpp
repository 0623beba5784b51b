#include "map/map_source.h"

#include <algorithm>
#include <cmath>

#include <QFileInfo>

#include "common/parameters.h"
#include "export/map_export.h"
#include "map/clip_loader.h"
#include "map/map_controller.h"
#include "map/map_view.h"
#include "motionmap/mapfile/saved_map.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

namespace {
QStringList numbered(const QStringList& names) {
  QStringList out;
  for (qsizetype c = 0; c < names.size(); ++c)
    out << QObject::tr("clip %1: %2").arg(c + 1).arg(names[c]);
  return out;
}
}  // namespace

QStringList legendNames(const QStringList& names) {
  if (names.size() < 2) return names;
  qsizetype common = names.front().size();
  for (const QString& name : names) {
    qsizetype i = 0;
    while (i < common && i < name.size() && name[i] == names.front()[i]) ++i;
    common = i;
  }
  // Back to just after a separator, and never the whole of a name.
  auto separator = [](QChar c) {
    return c == QLatin1Char('_') || c == QLatin1Char('-') || c == QLatin1Char('.') ||
           c == QLatin1Char(' ') || c == QLatin1Char('/') || c == QLatin1Char(':');
  };
  while (common > 0 && !separator(names.front()[common - 1])) --common;
  bool allSame = true;
  for (const QString& name : names) {
    if (name.size() <= common) common = 0;
    allSame = allSame && name == names.front();
  }
  if (allSame) common = 0;  // nothing tells them apart but their numbers
  // Short names fit whole: "64_08.bvh" stays (kLegendShortName).
  qsizetype longest = 0;
  for (const QString& name : names) longest = std::max(longest, name.size());
  if (longest <= kLegendShortName) return numbered(names);
  // A file extension all share (".bvh") tells nothing either.
  qsizetype extension = 0;
  const qsizetype dot = names.front().lastIndexOf(QLatin1Char('.'));
  if (dot > common && !allSame) {
    const QString ext = names.front().mid(dot);
    extension = ext.size();
    for (const QString& name : names)
      if (!name.endsWith(ext) || name.size() - ext.size() <= common) extension = 0;
  }
  QStringList out;
  for (qsizetype c = 0; c < names.size(); ++c) {
    const QString rest = names[c].mid(common, names[c].size() - common - extension);
    out << QObject::tr("clip %1: %2")
               .arg(c + 1)
               .arg(common > 0 ? QStringLiteral("…") + rest : rest);
  }
  return out;
}

std::vector<MapSource::Near> MapSource::nearestSamples(const Eigen::Vector2d& point, int k) const {
  std::vector<Near> all;
  const Samples s = samples();
  if (!s.points || k < 1 || !point.allFinite()) return all;
  const Eigen::MatrixXd& xy = *s.points;
  all.reserve(std::size_t(xy.rows()));
  for (Eigen::Index i = 0; i < xy.rows(); ++i) {
    const double d = std::hypot(xy(i, 0) - point.x(), xy(i, 1) - point.y());
    if (std::isfinite(d)) all.push_back({int(i), d});
  }
  const std::size_t keep = std::min(all.size(), std::size_t(k));
  std::partial_sort(
      all.begin(), all.begin() + std::ptrdiff_t(keep), all.end(), [](const Near& a, const Near& b) {
        return a.distance != b.distance ? a.distance < b.distance : a.sample < b.sample;
      });
  all.resize(keep);
  return all;
}

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

QString ComputedMapSource::openAll(std::vector<Clip> clips) {
  if (clips.empty()) return tr("No clips to map");
  for (const Clip& clip : clips) {
    if (!clip.skeleton.same_hierarchy(clips.front().skeleton)) {
      return tr("%1 has another skeleton than %2 (joint names or parents differ): they cannot "
                "share a map")
          .arg(QString::fromStdString(clip.path), QString::fromStdString(clips.front().path));
    }
  }
  m_maps->setClips(std::make_shared<std::vector<Clip>>(std::move(clips)));
  m_clipIndex = 0;
  m_skeletonView->setSkeleton(clip()->skeleton);
  return {};
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

QStringList ComputedMapSource::clipPaths() const {
  QStringList paths;
  if (m_maps->clips())
    for (const Clip& clip : *m_maps->clips()) paths << QString::fromStdString(clip.path);
  return paths;
}

Eigen::MatrixXd ComputedMapSource::clipPoints(int clip) const {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || clip < 0 || clip >= clipCount()) return Eigen::MatrixXd(0, 2);
  const std::vector<int>& starts = map->map.features->segment_starts;
  const Eigen::MatrixXd& xy = map->map.embedding.coordinates;
  if (std::size_t(clip) >= starts.size()) return Eigen::MatrixXd(0, 2);
  const int begin = starts[std::size_t(clip)];
  const int end =
      std::size_t(clip) + 1 < starts.size() ? starts[std::size_t(clip) + 1] : int(xy.rows());
  return xy.block(begin, 0, end - begin, 2);
}

MapSource::Samples ComputedMapSource::samples() const {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map || !map->map.features) return {};
  return {&map->map.embedding.coordinates, &map->map.features->clip_of,
          &map->map.features->frame_of};
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
  render::MapPlotOptions options = mapPlotOptions(*map, *m_maps->clips());
  if (!options.clip_names.isEmpty()) {
    // Several clips: numbered as hover numbers them, told apart by their ends, each running light
    // → dark in its colour so its time direction shows.
    options.clip_names = legendNames(options.clip_names);
    options.clip_time_ramp = true;
    options.legend_elide_right = true;  // "clip 2: …" stays whole, the name's end is cut
  }
  m_mapView->setMap(map->map.embedding.coordinates, map->map.features->segment_starts, options);
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

QStringList SavedMapSource::clipPaths() const {
  QStringList paths;
  for (const mapfile::ClipRecord& record : m_map->file().clips)
    paths << QString::fromStdString(record.path);
  return paths;
}

Eigen::MatrixXd SavedMapSource::clipPoints(int clip) const {
  const mapfile::MapFile& file = m_map->file();
  if (clip < 0 || clip >= clipCount()) return Eigen::MatrixXd(0, 2);
  const mapfile::ClipRecord& record = file.clips[std::size_t(clip)];
  return file.coordinates.block(record.first_sample, 0, record.samples, 2);
}

MapSource::Samples SavedMapSource::samples() const {
  const mapfile::MapFile& file = m_map->file();
  return {&file.coordinates, &file.clip_of, &file.frame_of};
}

std::vector<MapSource::Near> SavedMapSource::nearestSamples(const Eigen::Vector2d& point,
                                                            int k) const {
  std::vector<Near> out;
  for (const mapfile::Neighbor& n : m_map->index().nearest(point, k))
    out.push_back({n.sample, n.distance});
  return out;
}

QString SavedMapSource::clipFile(int clip) const {
  if (clip < 0 || clip >= clipCount()) return {};
  return QString::fromStdString(m_map->resolve_path(clip));
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
