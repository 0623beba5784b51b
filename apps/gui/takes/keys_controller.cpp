#include "takes/keys_controller.h"

#include <QFileInfo>

#include "map/map_gestures.h"
#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "takes/synthesis_controller.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {

KeysController::KeysController(std::function<MapSource*()> source, MapView* mapView,
                               TakesController* takes, SynthesisController* synthesis,
                               std::function<SynthParameters()> parameters, QObject* parent)
    : QObject(parent),
      m_source(std::move(source)),
      m_mapView(mapView),
      m_takes(takes),
      m_synthesis(synthesis),
      m_parameters(std::move(parameters)) {
  // The first in-between of the pending keys arrived: they are its keys now.
  connect(synthesis, &SynthesisController::finished, this, [this] {
    if (!m_synthesis->resultKeys().keys.empty() && m_synthesis->resultTake() < 0) clearPending();
  });
}

const Take* KeysController::keyedTake() const {
  const Take* take = m_takes->list().currentTake();
  const MapSource* source = m_source();
  const std::shared_ptr<const MapResult> map = source ? source->blendMap() : nullptr;
  if (!take || take->keys.keys.empty() || !map || take->map != map) return nullptr;
  return take;
}

std::shared_ptr<const MapResult> KeysController::keyMap() {
  MapSource* source = m_source();
  if (!source) return nullptr;
  if (std::shared_ptr<const MapResult> map = source->blendMap(); map && map->blender) return map;
  // A saved map's blender not built yet (or failed to be): say so; a map being computed: quiet.
  if (const QString why = source->prepareBlend(); !why.isEmpty()) emit failed(why);
  return nullptr;
}

void KeysController::clearPending() {
  m_pending.clear();
  showPending();
}

void KeysController::showPending() {
  std::vector<Eigen::Vector2d> points;
  for (const synth::Key& key : m_pending) points.push_back(key.point);
  m_mapView->setPendingKeys(std::move(points));
}

synth::Key KeysController::keyAt(const MapResult& map, const Eigen::Vector2d& point,
                                 const QPointF& pixel) const {
  const synth::MapBlender& blender = *map.blender;
  const int sample = blender.locate(point).validity.nearest_sample;
  const QPointF at = m_mapView->toWidget(blender.sample_point(sample));
  if (QLineF(at, pixel).length() <= MapGestures::kNearPixels) {
    // A frame of a clip: its pose, standing where it stood.
    const features::FeatureSet& set = *map.map.features;
    const int clip = set.clip_of[std::size_t(sample)], frame = set.frame_of[std::size_t(sample)];
    const std::shared_ptr<const Clip> source = m_source()->mapClip(clip);
    if (!source) throw Error("no clip " + std::to_string(clip + 1) + " on the map");
    synth::Key key = synth::sample_key(blender, sample, source->motion, frame);
    key.label = QFileInfo(QString::fromStdString(source->path)).fileName().toStdString() + ":" +
                std::to_string(frame);
    return key;
  }
  synth::Key key;
  key.point = point;
  key.label = format_number(point.x()) + ":" + format_number(point.y());
  return key;
}

bool KeysController::start(TakeKeys keys, int take) {
  const std::shared_ptr<const MapResult> map = m_source()->blendMap();
  if (!m_takes->inbetween(map, std::move(keys), m_parameters(), take)) return false;
  emit started();
  return true;
}

bool KeysController::click(const Eigen::Vector2d& point, const QPointF& pixel) {
  if (!point.allFinite()) return false;
  const std::shared_ptr<const MapResult> map = keyMap();
  if (!map) return false;
  try {
    if (const Take* take = keyedTake()) {
      TakeKeys keys = take->keys;
      const int hit = m_mapView->controlPointAt(pixel);
      if (hit >= 0 && hit < int(keys.keys.size())) {
        if (keys.keys.size() <= 2) {
          emit failed(tr("An in-between needs two keys: delete the take instead"));
          return false;
        }
        keys.keys.erase(keys.keys.begin() + hit);
      } else {
        synth::Key key = keyAt(*map, point, pixel);
        // A new key after the last: its time one second after the last key's, when timed.
        if (keys.keys.back().time) key.time = *keys.keys.back().time + 1.0;
        keys.keys.push_back(std::move(key));
      }
      return start(std::move(keys), take->id);
    }
    m_pending.push_back(keyAt(*map, point, pixel));
    showPending();
    if (m_pending.size() < 2) return true;
    TakeKeys keys;
    keys.keys = m_pending;
    return start(std::move(keys), -1);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
}

bool KeysController::moveKey(int index, const Eigen::Vector2d& point, const QPointF& pixel) {
  const Take* take = keyedTake();
  const std::shared_ptr<const MapResult> map = take ? take->map : nullptr;
  if (!take || !map || index < 0 || index >= int(take->keys.keys.size()) || !point.allFinite())
    return false;
  try {
    TakeKeys keys = take->keys;
    synth::Key moved = keyAt(*map, point, pixel);
    moved.time = keys.keys[std::size_t(index)].time;
    keys.keys[std::size_t(index)] = std::move(moved);
    return start(std::move(keys), take->id);
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
}

bool KeysController::retime(const std::vector<double>& times) {
  const Take* take = keyedTake();
  if (!take) {
    emit failed(tr("Retiming needs an in-between take (Ctrl-click two frames on the map)"));
    return false;
  }
  TakeKeys keys = take->keys;
  if (!times.empty() && times.size() != keys.keys.size()) {
    emit failed(tr("%1 times for %2 keys: give one per key, or none")
                    .arg(times.size())
                    .arg(keys.keys.size()));
    return false;
  }
  for (std::size_t k = 0; k < keys.keys.size(); ++k)
    keys.keys[k].time = times.empty() ? std::nullopt : std::optional<double>(times[k]);
  keys.framesBetween = -1;
  return start(std::move(keys), take->id);
}

}  // namespace motionmap::studio
