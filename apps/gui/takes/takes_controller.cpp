#include "takes/takes_controller.h"

namespace motionmap::studio {

TakesController::TakesController(SynthesisController* synthesis, QObject* parent)
    : QObject(parent), m_synthesis(synthesis) {
  connect(&m_list, &TakeList::changed, this, &TakesController::changed);
  connect(&m_list, &TakeList::renameRequested, this, &TakesController::rename);
  // An edit that does not arrive leaves its take as it was.
  connect(m_synthesis, &SynthesisController::cancelled, this, &TakesController::dropPending);
  connect(m_synthesis, &SynthesisController::failed, this, &TakesController::dropPending);
}

void TakesController::sketchStarted() {
  dropPending();  // the new sketch stopped the edit's synthesis
}

void TakesController::dropPending() {
  if (!m_pending) return;
  m_pending.reset();
  emit changed();
}

void TakesController::takeResult(const std::string& mapKey) {
  const int id = m_synthesis->resultTake();
  const bool keyed = !m_synthesis->resultKeys().keys.empty();
  if (id < 0) {
    Take take;
    take.name = m_list.nextName();
    take.id = m_list.newId();
    take.path = m_synthesis->resultPath();
    take.controls = keyed ? m_synthesis->resultKeyFrames() : controlPoints(take.path);
    take.keys = m_synthesis->resultKeys();
    take.result = m_synthesis->sharedResult();
    take.map = m_synthesis->resultMap();
    take.mapKey = mapKey;
    m_stack.push(new AddTakeCommand(&m_list, std::move(take), m_list.count()));
    return;
  }
  m_pending.reset();
  m_lastEditWindow = m_synthesis->resultWindow();
  if (m_list.rowOf(id) < 0) return emit changed();  // deleted meanwhile
  if (keyed) {
    m_stack.push(new EditTakeCommand(
        &m_list, id, m_synthesis->resultPath(), m_synthesis->sharedResult(),
        std::make_pair(m_synthesis->resultKeys(), m_synthesis->resultKeyFrames())));
    return;
  }
  m_stack.push(
      new EditTakeCommand(&m_list, id, m_synthesis->resultPath(), m_synthesis->sharedResult()));
}

bool TakesController::inbetween(std::shared_ptr<const MapResult> map, TakeKeys keys,
                                const SynthParameters& parameters, int take) {
  synth::MapPath straight;
  for (const synth::Key& key : keys.keys) straight.points.push_back(key.point);
  if (!m_synthesis->startInbetween(std::move(map), std::move(keys), parameters, take)) return false;
  if (take >= 0) m_pending.emplace(take, std::move(straight));
  emit changed();
  return true;
}

bool TakesController::editControlPoint(int control, const Eigen::Vector2d& to,
                                       const SynthParameters& parameters) {
  const Take* take = m_list.currentTake();
  if (!take || control < 0 || control >= int(take->controls.size()) || !to.allFinite())
    return false;
  synth::MapPath path = deformPath(take->path, take->controls, control, to);
  // Only the part of the motion the moved point changes is re-made (synth::edit_path).
  if (!m_synthesis->startEdit(take->map, take->result, path, parameters, take->id)) return false;
  m_pending.emplace(take->id, std::move(path));
  emit changed();
  return true;
}

bool TakesController::rename(int row, const QString& name) {
  const QString trimmed = name.trimmed();
  if (row < 0 || row >= m_list.count() || trimmed.isEmpty() || trimmed == m_list.at(row).name)
    return false;
  m_stack.push(new RenameTakeCommand(&m_list, m_list.at(row).id, m_list.at(row).name, trimmed));
  return true;
}

bool TakesController::remove(int row) {
  if (row < 0 || row >= m_list.count()) return false;
  if (m_pending && m_pending->first == m_list.at(row).id) m_synthesis->cancel();
  m_stack.push(new DeleteTakeCommand(&m_list, row));
  return true;
}

void TakesController::recordMapChange(const MapState& before, const MapState& after,
                                      const QString& text,
                                      const std::function<void(const MapState&)>& apply) {
  if (m_applying) return;
  auto guarded = [this, apply](const MapState& state) {
    m_applying = true;
    apply(state);
    m_applying = false;
  };
  m_stack.push(new MapStateCommand(guarded, before, after, text));
}

void TakesController::undo() {
  if (m_pending) m_synthesis->cancel();
  m_stack.undo();
}

void TakesController::redo() {
  if (m_pending) m_synthesis->cancel();
  m_stack.redo();
}

void TakesController::clear() {
  m_pending.reset();
  m_stack.clear();
  m_list.clear();
}

std::vector<MapView::TakePath> TakesController::pathsOn(const MapResult* map) const {
  std::vector<MapView::TakePath> paths;
  if (!map) return paths;
  for (int row = 0; row < m_list.count(); ++row) {
    const Take& take = m_list.at(row);
    if (take.map.get() != map) continue;  // a take belongs to the map it was sketched on
    MapView::TakePath drawn;
    drawn.name = take.name;
    drawn.current = row == m_list.current();
    drawn.points =
        m_pending && m_pending->first == take.id ? m_pending->second.points : take.path.points;
    drawn.keyed = !take.keys.keys.empty();
    if (drawn.current) {
      drawn.controls = take.controls;
      // An edit being made: its new keys, on the straight lines drawn meanwhile.
      if (drawn.keyed && m_pending && m_pending->first == take.id) {
        drawn.controls.clear();
        for (std::size_t k = 0; k < drawn.points.size(); ++k) drawn.controls.push_back(int(k));
      }
    }
    paths.push_back(std::move(drawn));
  }
  return paths;
}

std::optional<Eigen::Vector2d> TakesController::pointOn(const MapResult* map, int frame) const {
  const Take* take = m_list.currentTake();
  if (!map || !take || !take->result || take->map.get() != map || frame < 0 ||
      frame >= int(take->result->validity.size()))
    return std::nullopt;
  return take->result->validity[std::size_t(frame)].point;
}

}  // namespace motionmap::studio
