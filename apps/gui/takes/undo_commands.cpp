#include "takes/undo_commands.h"

#include <utility>

#include <QCoreApplication>

#include "map/map_controller.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {

namespace {
QString tr(const char* text) {
  return QCoreApplication::translate("UndoCommands", text);
}
}  // namespace

bool sameSynthParameters(const SynthParameters& a, const SynthParameters& b) {
  const MapParameters map;
  return MapController::cacheKey(embed::Method::Pca, map, a.blend) ==
             MapController::cacheKey(embed::Method::Pca, map, b.blend) &&
         a.motion.speed == b.motion.speed && a.motion.fps == b.motion.fps &&
         a.motion.smooth == b.motion.smooth && a.timedAsDrawn == b.timedAsDrawn &&
         a.freeRoots == b.freeRoots;
}

AddTakeCommand::AddTakeCommand(TakeList* takes, Take take, int row)
    : m_takes(takes), m_take(std::move(take)), m_row(row) {
  setText(tr("sketch %1").arg(m_take.name));
}

void AddTakeCommand::redo() {
  m_previousCurrent = m_takes->current();
  m_takes->insert(m_row, m_take);
  m_takes->setCurrent(m_row);
}

void AddTakeCommand::undo() {
  // The take may have been renamed or edited since: what comes back on redo is what it was then.
  m_take = m_takes->remove(m_row);
  m_takes->setCurrent(m_previousCurrent < m_takes->count() ? m_previousCurrent : -1);
}

DeleteTakeCommand::DeleteTakeCommand(TakeList* takes, int row)
    : m_takes(takes), m_take(takes->at(row)), m_row(row) {
  setText(tr("delete %1").arg(m_take.name));
}

void DeleteTakeCommand::redo() {
  m_wasCurrent = m_takes->current() == m_row;
  m_take = m_takes->remove(m_row);
}

void DeleteTakeCommand::undo() {
  m_takes->insert(m_row, m_take);
  if (m_wasCurrent) m_takes->setCurrent(m_row);
}

RenameTakeCommand::RenameTakeCommand(TakeList* takes, int id, QString from, QString to)
    : m_takes(takes), m_id(id), m_from(std::move(from)), m_to(std::move(to)) {
  setText(tr("rename %1 to %2").arg(m_from, m_to));
}

void RenameTakeCommand::set(const QString& name) {
  const int row = m_takes->rowOf(m_id);
  if (row >= 0) m_takes->rename(row, name);
}

void RenameTakeCommand::redo() {
  set(m_to);
}

void RenameTakeCommand::undo() {
  set(m_from);
}

EditTakeCommand::EditTakeCommand(TakeList* takes, int id, synth::MapPath path,
                                 std::shared_ptr<const synth::SynthResult> result,
                                 std::optional<std::pair<TakeKeys, std::vector<int>>> keys)
    : m_takes(takes), m_id(id), m_path(std::move(path)), m_result(std::move(result)) {
  const int row = takes->rowOf(id);
  if (row >= 0) {
    const Take& take = takes->at(row);
    m_previousPath = take.path;
    m_previousResult = take.result;
    m_previousExported = take.exported;
    m_previousKeys = take.keys;
    m_previousControls = take.controls;
    setText(tr("edit %1").arg(take.name));
  }
  // A sketch's edit keeps its control points (deformPath moves them with the path).
  m_keys = keys ? std::move(keys->first) : m_previousKeys;
  m_controls = keys ? std::move(keys->second) : m_previousControls;
}

void EditTakeCommand::redo() {
  const int row = m_takes->rowOf(m_id);
  if (row < 0) return;
  m_takes->setKeys(row, m_keys, m_controls);
  m_takes->setMotion(row, m_path, m_result, false);
}

void EditTakeCommand::undo() {
  const int row = m_takes->rowOf(m_id);
  if (row < 0) return;
  m_takes->setKeys(row, m_previousKeys, m_previousControls);
  m_takes->setMotion(row, m_previousPath, m_previousResult, m_previousExported);
}

MapStateCommand::MapStateCommand(std::function<void(const MapState&)> apply, MapState before,
                                 MapState after, const QString& text)
    : m_apply(std::move(apply)), m_before(std::move(before)), m_after(std::move(after)) {
  setText(text);
}

void MapStateCommand::redo() {
  if (m_done) {
    m_done = false;
    return;
  }
  m_apply(m_after);
}

void MapStateCommand::undo() {
  m_apply(m_before);
}

MapChangeRecorder::MapChangeRecorder(TakesController* takes, std::function<MapState()> state,
                                     std::function<void(const MapState&)> apply)
    : m_takes(takes), m_state(std::move(state)), m_apply(std::move(apply)) {}

void MapChangeRecorder::record(const MapState& before, const QString& text) {
  if (m_takes->applying()) return;  // an undo or redo: already in the history
  if (m_pending) {
    m_pending->text = text;  // from the map still shown, to the latest asked for
  } else {
    m_pending = Pending{before, text};
  }
}

void MapChangeRecorder::commit() {
  if (!m_pending) return;
  const Pending change = *std::exchange(m_pending, std::nullopt);
  const MapState now = m_state();
  if (change.before.method == now.method && change.before.parameters == now.parameters &&
      sameSynthParameters(change.before.synth, now.synth))
    return;
  m_takes->recordMapChange(change.before, now, change.text, m_apply);
}

}  // namespace motionmap::studio
