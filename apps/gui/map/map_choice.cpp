#include "map/map_choice.h"

#include <limits>

#include <QSettings>

#include "map/map_controller.h"

namespace motionmap::studio {

namespace {
void saveMethod(embed::Method method) {
  QSettings().setValue("method", QString::fromUtf8(embed::method_name(method).data()));
}
}  // namespace

MapChoice::MapChoice(MapController* maps, TakesController* takes, QObject* parent)
    : QObject(parent),
      m_maps(maps),
      m_changes(
          takes, [this] { return state(); }, [this](const MapState& s) { applyState(s); }) {
  QSettings settings;
  if (const auto m =
          embed::parse_method(settings.value("method", "isomap").toString().toStdString()))
    m_method = *m;
  m_parameters = readMapParameters(settings);
  m_synth = readSynthParameters(settings);
  connect(maps, &MapController::finished, this, [this] {
    m_changes.commit();
    save();  // the parameters of a map computed without error are the next session's
  });
  connect(maps, &MapController::failed, this, &MapChoice::restoreShown);
  connect(maps, &MapController::cancelled, this, &MapChoice::restoreShown);
}

void MapChoice::setMethod(embed::Method method) {
  if (!m_recomputable) return emit refused(method);
  const MapState before = state();
  m_method = method;
  emit methodChanged(method);
  if (method != before.method) m_changes.record(before, tr("method %1").arg(methodLabel(method)));
  saveMethod(method);
  if (m_maps->request(method, m_parameters, m_synth.blend)) {  // cached
    m_changes.commit();
    save();
    emit cachedMapReady(method);
  }
}

void MapChoice::setParameters(const MapParameters& parameters) {
  const MapState before = state();
  m_parameters = parameters;
  if (m_recomputable && !(parameters == before.parameters))
    m_changes.record(before, tr("map parameters"));
  setMethod(m_method);
}

bool MapChoice::setSynthParameters(const SynthParameters& parameters) {
  try {
    parameters.motion.validate();
    // K is checked against the samples of the map shown; a new clip's map checks it again.
    const std::shared_ptr<const MapResult> map = m_maps->current();
    parameters.blend.validate(map ? map->map.features->num_samples()
                                  : std::numeric_limits<int>::max());
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
  if (!sameSynthParameters(parameters, m_synth))
    m_changes.record(state(), tr("synthesis parameters"));
  // A new blend needs a new map (a saved map's drags blend with the new K as they are).
  const bool newBlend =
      m_recomputable && MapController::cacheKey(m_method, m_parameters, parameters.blend) !=
                            MapController::cacheKey(m_method, m_parameters, m_synth.blend);
  m_synth = parameters;
  emit synthChanged();
  if (newBlend) {
    setMethod(m_method);                // a blender with the new options: computed, or cached
  } else if (!m_maps->isComputing()) {  // else it joins the change whose map is being computed
    m_changes.commit();
    save();
  }
  return true;
}

void MapChoice::applyState(const MapState& state) {
  m_changes.drop();  // an undo or redo replaces a change whose map was still computing
  m_parameters = state.parameters;
  m_synth = state.synth;
  emit synthChanged();
  if (!m_recomputable) return save();
  setMethod(state.method);  // its map from the cache when it was shown before
}

void MapChoice::restoreShown() {
  m_changes.drop();
  // The map before a failed or cancelled computation is current again (MapController): its
  // method and parameters come back with it, so what is shown is what the menus say.
  const std::optional<MapRequest> shown = m_maps->shownRequest();
  if (!shown) return;
  m_method = shown->method;
  emit methodChanged(m_method);
  saveMethod(m_method);
  m_parameters = shown->parameters;
  m_synth.blend = shown->blend;
}

void MapChoice::save() const {
  QSettings settings;
  writeParameters(settings, m_parameters, m_synth);
}

}  // namespace motionmap::studio
