#pragma once
// The undoable steps of a Studio session, for one QUndoStack (Edit → Undo / Redo): a take added
// (a sketch), a take's motion edited (a control point dragged), a take renamed or deleted, and a
// change of the map's method or parameters. Each command keeps both states, so undoing and
// redoing is instant: an edit keeps the take's previous path and motion, a parameter change the
// previous method and parameters (their map comes back from the map cache).
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include <QUndoCommand>

#include "common/parameters.h"
#include "takes/takes.h"

namespace motionmap::studio {

class TakesController;

/// What the Motion menu sets: the method and both parameter sets.
struct MapState {
  embed::Method method = embed::Method::Isomap;
  MapParameters parameters;
  SynthParameters synth;
};

/// Whether `a` and `b` synthesize alike (the blend as the map cache tells blenders apart, the
/// motion options, the timing), so that an unchanged dialog leaves no undo step.
bool sameSynthParameters(const SynthParameters& a, const SynthParameters& b);

/// A sketch's take added at `row` (made current by redo).
class AddTakeCommand : public QUndoCommand {
 public:
  AddTakeCommand(TakeList* takes, Take take, int row);
  void redo() override;
  void undo() override;

 private:
  TakeList* m_takes;
  Take m_take;
  int m_row;
  int m_previousCurrent = -1;
};

/// The take at `row` removed (and put back where it was by undo).
class DeleteTakeCommand : public QUndoCommand {
 public:
  DeleteTakeCommand(TakeList* takes, int row);
  void redo() override;
  void undo() override;

 private:
  TakeList* m_takes;
  Take m_take;
  int m_row;
  bool m_wasCurrent = false;
};

class RenameTakeCommand : public QUndoCommand {
 public:
  RenameTakeCommand(TakeList* takes, int id, QString from, QString to);
  void redo() override;
  void undo() override;

 private:
  void set(const QString& name);
  TakeList* m_takes;
  int m_id;
  QString m_from, m_to;
};

/// A take's path and motion replaced by a re-synthesized one (an in-between take's: with its
/// keys and their frames); undo puts the previous ones back.
class EditTakeCommand : public QUndoCommand {
 public:
  EditTakeCommand(TakeList* takes, int id, synth::MapPath path,
                  std::shared_ptr<const synth::SynthResult> result,
                  std::optional<std::pair<TakeKeys, std::vector<int>>> keys = std::nullopt);
  void redo() override;
  void undo() override;

 private:
  TakeList* m_takes;
  int m_id;
  synth::MapPath m_path, m_previousPath;
  std::shared_ptr<const synth::SynthResult> m_result, m_previousResult;
  TakeKeys m_keys, m_previousKeys;
  std::vector<int> m_controls, m_previousControls;
  bool m_previousExported = false;
};

/// A method or parameter change that has already been made: the first redo (QUndoStack::push)
/// does nothing, later ones and undo call `apply` with the state after or before.
class MapStateCommand : public QUndoCommand {
 public:
  MapStateCommand(std::function<void(const MapState&)> apply, MapState before, MapState after,
                  const QString& text);
  void redo() override;
  void undo() override;

 private:
  std::function<void(const MapState&)> m_apply;
  MapState m_before, m_after;
  bool m_done = true;  ///< already applied when pushed
};

/// Method and parameter changes as undo steps. A change is recorded when it is asked for and
/// pushed (a MapStateCommand on the takes' history) once its map is shown, so a map that fails or
/// is cancelled leaves no step; changes asked while one is pending join it, and a change that ends
/// where it began leaves none. Undo and redo call `apply` with the state before or after (changes
/// made while applying are not recorded).
class MapChangeRecorder {
 public:
  /// `takes` (its history) must outlive this; `state` reads the state now.
  MapChangeRecorder(TakesController* takes, std::function<MapState()> state,
                    std::function<void(const MapState&)> apply);
  /// A change from `before`, called `text` in the Edit menu, is being made.
  void record(const MapState& before, const QString& text);
  /// Its map is shown: the change becomes an undo step.
  void commit();
  /// Its map failed or was cancelled, or the history was dropped: no step.
  void drop() { m_pending.reset(); }

 private:
  struct Pending {
    MapState before;
    QString text;
  };
  TakesController* m_takes;
  std::function<MapState()> m_state;
  std::function<void(const MapState&)> m_apply;
  std::optional<Pending> m_pending;
};

}  // namespace motionmap::studio
