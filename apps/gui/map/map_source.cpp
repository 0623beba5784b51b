#include "map/map_source.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <QElapsedTimer>
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

std::shared_ptr<const synth::Reacher> MapSource::reacher(std::shared_ptr<const MapResult> map,
                                                         QString& why) {
  why.clear();
  if (!map || !map->blender) return nullptr;
  // Each sample's joints (milliseconds at 10 000 frames); the caller keeps `map` with it.
  return std::make_shared<const synth::Reacher>(*map->blender);
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

std::shared_ptr<const Clip> ComputedMapSource::mapClip(int clip) const {
  if (clip < 0 || clip >= clipCount()) return nullptr;
  // Shares the clips' ownership: the set outlives a setClips() while this is held.
  return std::shared_ptr<const Clip>(m_maps->clips(), &(*m_maps->clips())[std::size_t(clip)]);
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
  m_mapView->setShadingReach(map->blender ? map->blender->reach_distance() : 0.0, {},
                             map->blender ? map->blender->options().gplvm : nullptr);
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

Axis ComputedMapSource::upAxis() const {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  return map ? map->options.features.up : Axis::Y;
}

// ---- SavedMapBlends ----

SavedMapBlends::SavedMapBlends(std::shared_ptr<const mapfile::SavedMap> map)
    : m_map(std::move(map)),
      m_samples(std::make_shared<const features::FeatureSet>(m_map->samples())) {}

std::string SavedMapBlends::key(synth::BlendOptions& blend) const {
  blend.up = m_map->file().options.features.up;
  gplvm_blend(blend, m_map->gplvm());
  return std::string(synth::blend_mode_name(blend.mode)) + "," + std::to_string(blend.neighbors) +
         "," + QString::number(blend.reach, 'g', 17).toStdString();
}

std::shared_ptr<const MapResult> SavedMapBlends::find(synth::BlendOptions blend) const {
  const std::string k = key(blend);
  const std::lock_guard lock(m_mutex);
  const auto it = m_built.find(k);
  return it == m_built.end() ? nullptr : it->second;
}

std::shared_ptr<const MapResult> SavedMapBlends::get(synth::BlendOptions blend,
                                                     const Control& control) {
  const std::string k = key(blend);
  if (auto built = find(blend)) return built;
  // One build at a time: another caller's build of the same blender is waited for, not repeated.
  std::unique_lock building(m_building, std::defer_lock);
  while (!building.try_lock_for(std::chrono::milliseconds(20))) control.check();
  if (auto built = find(blend)) return built;
  QElapsedTimer clock;
  clock.start();
  const mapfile::MapFile& file = m_map->file();
  auto result = std::make_shared<MapResult>();
  result->map.features = m_samples;
  result->map.embedding.method = file.options.embed.method;
  result->map.embedding.coordinates = file.coordinates;
  result->map.dense = file.dense;
  result->options = file.options;
  result->parameters = file.parameters;
  if (blend.mode == synth::BlendMode::Kriging) {
    // Kriging blends every sample: every clip is loaded (the blender keeps what it needs).
    const std::vector<Clip> clips = m_map->load_all_clips(control.part(0.0, 0.5));
    result->blender = std::make_unique<synth::MapBlender>(clips, *m_samples, file.coordinates,
                                                          blend, control.part(0.5, 1.0));
  } else {
    result->blender =
        std::make_unique<synth::MapBlender>(mapfile::make_blender(m_map, blend, control));
  }
  result->seconds = double(clock.nsecsElapsed()) * 1e-9;
  const std::lock_guard lock(m_mutex);
  m_built[k] = result;
  return result;
}

std::shared_ptr<const synth::Reacher> SavedMapBlends::findReacher(const MapResult* map) const {
  const std::lock_guard lock(m_mutex);
  const auto it = m_reachers.find(map);
  return it == m_reachers.end() ? nullptr : it->second;
}

std::shared_ptr<const synth::Reacher> SavedMapBlends::reacher(
    const std::shared_ptr<const MapResult>& map, const Control& control) {
  if (auto built = findReacher(map.get())) return built;
  std::unique_lock building(m_building, std::defer_lock);
  while (!building.try_lock_for(std::chrono::milliseconds(20))) control.check();
  if (auto built = findReacher(map.get())) return built;
  auto made = std::make_shared<const synth::Reacher>(*map->blender, control);
  const std::lock_guard lock(m_mutex);
  m_reachers[map.get()] = made;  // its blender is m_built's, kept as long as this
  return made;
}

// ---- SavedMapSource ----

SavedMapSource::SavedMapSource(const QString& path, MapView* mapView, SkeletonView* skeletonView,
                               QObject* parent, std::function<synth::BlendOptions()> blend)
    : MapSource(parent),
      m_path(path),
      m_map(std::make_shared<const mapfile::SavedMap>(
          mapfile::read_map_file(path.toStdString(), {.model = false}), kCachedClips)),
      m_mapView(mapView),
      m_skeletonView(skeletonView),
      m_loader(new ClipLoader(this)),
      m_blend(std::move(blend)),
      m_blends(std::make_shared<SavedMapBlends>(m_map)) {
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
  m_reach.stop();
  m_prepare.stop();
  m_loader->setMap(nullptr);
}

void SavedMapSource::show() {
  render::MapPlotOptions options;
  options.line_width = 1.0;  // the density shows between the strokes
  m_mapView->setDensityMap(
      std::shared_ptr<const Eigen::MatrixXd>(m_map, &m_map->file().coordinates),
      Eigen::MatrixXd(0, 2), options);
  // The blender's reach over the same samples (SavedMap::reach_distance is the blender's rule,
  // synth::reach_radius), decided exactly by the map's own k-d tree.
  // A gplvm map's rule is its GP's (SavedMap::gplvm, which its blender gets).
  m_mapView->setShadingReach(m_map->reach_distance(blendOptions().reach),
                             std::shared_ptr<const synth::PointIndex>(m_map, &m_map->index()),
                             m_map->gplvm());
  prepareBlend();  // ready by the first sketch, key or joint drag
}

std::shared_ptr<const Clip> SavedMapSource::mapClip(int clip) const {
  if (clip < 0 || clip >= clipCount()) return nullptr;
  return m_map->clip(clip);
}

std::shared_ptr<const MapResult> SavedMapSource::blendMap() const {
  return m_blends->find(blendOptions());
}

MapSupply SavedMapSource::blendSupply() const {
  MapSupply supply;
  supply.ready = blendMap();
  if (!supply.ready) {
    supply.make = [blends = m_blends, blend = blendOptions()](const Control& control) {
      return blends->get(blend, control);
    };
  }
  return supply;
}

QString SavedMapSource::prepareBlend() {
  const synth::BlendOptions blend = blendOptions();
  if (m_blends->find(blend)) return {};
  const QString why =
      !m_prepareError.isEmpty()
          ? m_prepareError
          : tr("The saved map's blender is being prepared (it reads what blending needs of its "
               "clips); try again in a moment");
  if (m_prepare.running()) return why;
  m_prepareError.clear();
  m_preparedPercent = -1;
  m_prepare.start([this, blends = m_blends, blend](const BackgroundJob::Ticket& ticket) {
    runJob<const MapResult>(
        this, m_prepare, ticket,
        [this](double fraction, const QString&) {
          // Now and then, not at every report.
          const int percent = int(100.0 * fraction);
          if (percent < m_preparedPercent + 10) return;
          m_preparedPercent = percent;
          emit busy(tr("Preparing the saved map for sketching: %1 %").arg(percent));
        },
        [&](const Control& control) { return blends->get(blend, control); },
        [this](const JobOutcome<const MapResult>& outcome) {
          // A failure is told when the blender is asked for (a sketch, a key, a joint drag).
          m_prepareError = outcome.error;
          if (m_preparedPercent >= 0 && outcome.error.isEmpty())
            emit busy(statusParts().join(QStringLiteral(" · ")));
        });
  });
  return why;
}

std::shared_ptr<const synth::Reacher> SavedMapSource::reacher(std::shared_ptr<const MapResult> map,
                                                              QString& why) {
  why.clear();
  if (!map || !map->blender) return nullptr;
  if (auto ready = m_blends->findReacher(map.get())) return ready;
  why = !m_reachError.isEmpty()
            ? m_reachError
            : tr("Preparing to pose from the saved map (each sample's pose is read once, a clip "
                 "at a time); drag the joint again in a moment");
  if (m_reach.running()) return nullptr;
  m_reachError.clear();
  m_reachPercent = -1;
  m_reach.start([this, blends = m_blends, map](const BackgroundJob::Ticket& ticket) {
    runJob<const synth::Reacher>(
        this, m_reach, ticket,
        [this](double fraction, const QString&) {
          const int percent = int(100.0 * fraction);
          if (percent < m_reachPercent + 10) return;
          m_reachPercent = percent;
          emit busy(tr("Preparing to pose from the saved map: %1 %").arg(percent));
        },
        [&](const Control& control) { return blends->reacher(map, control); },
        [this](const JobOutcome<const synth::Reacher>& outcome) {
          m_reachError = outcome.error;
          if (outcome.error.isEmpty())
            emit busy(tr("Ready to pose from the saved map: drag a joint in the 3-D view"));
        });
  });
  return nullptr;
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

Axis SavedMapSource::upAxis() const {
  return m_map->file().options.features.up;
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
  }
  return {};
}

}  // namespace motionmap::studio
