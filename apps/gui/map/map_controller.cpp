#include "map/map_controller.h"

#include <QElapsedTimer>
#include <QMetaObject>

#include "motionmap/core/control.h"
#include "motionmap/core/error.h"

namespace motionmap::studio {

// A gplvm map's GP is its rule of where it is valid, and its blends are the GP's predictive mean
// while the chosen mode is the default (local).
void gplvm_blend(synth::BlendOptions& blend, std::shared_ptr<const MapGp> gp) {
  if (!gp) return;
  if (blend.mode == synth::BlendOptions().mode) blend.mode = synth::BlendMode::Gp;
  blend.gplvm = std::move(gp);
}

namespace {

/// [clip][frame]: the map row shown for each frame. Frames left out of the map (a bind pose)
/// show the row of the nearest earlier frame of their clip (or its first row).
std::vector<std::vector<int>> rowsOfFrames(const std::vector<Clip>& clips,
                                           const features::FeatureSet& set) {
  std::vector<std::vector<int>> out(clips.size());
  for (std::size_t c = 0; c < clips.size(); ++c) {
    const int first = set.segment_starts[c];
    const int end =
        c + 1 < set.segment_starts.size() ? set.segment_starts[c + 1] : set.num_samples();
    std::vector<int>& rows = out[c];
    rows.assign(std::size_t(std::max(0, clips[c].motion.num_frames)), first);
    int row = first;
    for (int f = 0; f < int(rows.size()); ++f) {
      while (row + 1 < end && set.frame_of[std::size_t(row + 1)] <= f) ++row;
      rows[std::size_t(f)] = row;
    }
  }
  return out;
}

}  // namespace

MapController::MapController(QObject* parent) : QObject(parent) {}

MapController::~MapController() {
  m_job.stop();
}

void MapController::setClips(std::shared_ptr<const std::vector<Clip>> clips) {
  // The worker may still read the old clips: it is stopped before they are let go.
  stop();
  m_clips = std::move(clips);
  m_maps.clear();  // maps (and blenders) belong to one set of clips
  m_currentKey.clear();
  m_shownKey.clear();
  m_shownRequest.reset();
  m_featureCache = std::make_shared<pipeline::FeatureCache>();
}

std::string MapController::cacheKey(embed::Method method, const MapParameters& parameters,
                                    const synth::BlendOptions& blend) {
  // Appends only: g++ 12 warns (-Wrestrict, a false positive) on "literal" + std::string&&.
  std::string key(embed::method_name(method));
  key.append("|k=").append(std::to_string(parameters.k));
  key.append("|heat=").append(
      parameters.heat ? QString::number(*parameters.heat, 'g', 17).toStdString() : "auto");
  key.append("|").append(features::feature_kind_name(parameters.features));
  key.append("|").append(features::distance_kind_name(parameters.distance));
  key.append("|exclude=").append(parameters.exclude);
  // The blender is part of a cached map.
  key.append("|blend=").append(synth::blend_mode_name(blend.mode));
  key.append(",").append(std::to_string(blend.neighbors));
  key.append(",").append(QString::number(blend.reach, 'g', 17).toStdString());
  return key;
}

std::shared_ptr<const MapResult> MapController::current() const {
  if (isComputing()) return nullptr;
  const auto it = m_maps.find(m_currentKey);
  return it == m_maps.end() ? nullptr : it->second;
}

std::optional<MapRequest> MapController::shownRequest() const {
  if (!current()) return std::nullopt;
  return m_shownRequest;
}

bool MapController::stop() {
  if (!m_job.stop()) return false;  // results still queued from it are ignored from now on
  m_currentKey = m_shownKey;        // the map before the computation is current again
  emit stopped();
  return true;
}

void MapController::cancel() {
  if (!stop()) return;
  emit cancelled();
}

bool MapController::request(embed::Method method, const MapParameters& parameters,
                            const synth::BlendOptions& blendOptions) {
  if (!m_clips) return false;
  stop();
  m_currentKey = cacheKey(method, parameters, blendOptions);
  m_asked = MapRequest{method, parameters, blendOptions};
  if (m_maps.count(m_currentKey)) {
    m_shownKey = m_currentKey;
    m_shownRequest = m_asked;
    return true;
  }
  emit started(method);
  std::shared_ptr<const std::vector<Clip>> clips = m_clips;
  std::shared_ptr<pipeline::FeatureCache> cache = m_featureCache;
  const pipeline::ClipMapOptions base = parameters.options(method);
  synth::BlendOptions blend = blendOptions;
  blend.up = base.features.up;
  m_job.start(
      [this, clips, cache, base, blend, key = m_currentKey](const BackgroundJob::Ticket& ticket) {
        runJob<MapResult>(
            this, m_job, ticket,
            [this](double fraction, const QString& stage) { emit progress(fraction, stage); },
            [&](const Control& control) {
              auto result = std::make_shared<MapResult>();
              pipeline::ClipMapOptions options = base;
              int frames = 0;
              for (const Clip& c : *clips) frames += c.motion.num_frames;
              options.metrics = frames <= kMaxMetricsFrames;
              QElapsedTimer clock;
              clock.start();
              // Kriging's set-up (O(N³)) can outlast the map; the other modes' take moments.
              const double mapShare = blend.mode == synth::BlendMode::Kriging ? 0.5 : 0.95;
              result->map =
                  pipeline::map_clips(*clips, options, control.part(0.0, mapShare), cache.get());
              control.check();
              synth::BlendOptions mapBlend = blend;
              gplvm_blend(mapBlend, pipeline::map_gplvm(result->map));
              result->parameters = pipeline::describe_parameters(result->map.embedding, options);
              // The blender's set-up stays off the GUI thread too, and polls the same Control
              // (kriging factors an (N+1)² system: tens of seconds at 10 000 points).
              result->blender = std::make_unique<synth::MapBlender>(
                  *clips, *result->map.features, result->map.embedding.coordinates, mapBlend,
                  control.part(mapShare, 1.0));
              result->seconds = double(clock.nsecsElapsed()) * 1e-9;
              result->options = options;
              result->rowOfFrame = rowsOfFrames(*clips, *result->map.features);
              return result;
            },
            [this, key](const JobOutcome<MapResult>& outcome) { onResult(key, outcome); });
      });
  return false;
}

void MapController::onResult(const std::string& key, const JobOutcome<MapResult>& outcome) {
  if (outcome.cancelled || !outcome.error.isEmpty()) {
    m_currentKey = m_shownKey;  // the map before is current again
    emit stopped();
    if (outcome.cancelled) return emit cancelled();
    return emit failed(outcome.error);
  }
  emit stopped();
  const std::shared_ptr<MapResult> result = outcome.value;
  m_maps[key] = result;
  m_shownKey = key;
  m_shownRequest = m_asked;
  emit finished(std::move(result));
}

}  // namespace motionmap::studio
