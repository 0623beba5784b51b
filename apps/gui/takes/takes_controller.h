#pragma once
// The takes and the undo history of a window, without widgets: sketches synthesized by the
// window's SynthesisController become takes, a dragged control point re-synthesizes its take on
// the same worker (progress and cancel as for a sketch) and the result replaces the take's motion,
// and every change — a take added, edited, renamed or deleted, the method or a parameter set
// changed — is one step of a QUndoStack. An edit being synthesized is shown on the map (pending)
// until its motion arrives; if it is cancelled, fails or a newer synthesis replaces it, the take
// stays as it was.
#include <functional>
#include <optional>
#include <vector>

#include <QObject>
#include <QUndoStack>

#include "map/map_view.h"
#include "takes/synthesis_controller.h"
#include "takes/takes.h"
#include "takes/undo_commands.h"

namespace motionmap::studio {

class TakesController : public QObject {
  Q_OBJECT
 public:
  /// Takes the results of `synthesis` (which must outlive this).
  explicit TakesController(SynthesisController* synthesis, QObject* parent = nullptr);

  TakeList& list() { return m_list; }
  const TakeList& list() const { return m_list; }
  QUndoStack& undoStack() { return m_stack; }
  /// An undo or redo of a map change is being applied (its own changes are not recorded).
  bool applying() const { return m_applying; }

  /// The synthesis' result (resultTake() −1: a new take, made current; else the edit of that
  /// take). Called by the window when the synthesis finished.
  void takeResult(const std::string& mapKey);
  /// Starts re-synthesizing the current take with its control point `control` moved to `to`
  /// (deformPath), on its own map with `parameters`: only the part of the motion the move
  /// changes (SynthesisController::startEdit, synth::edit_path) when the take was made with
  /// these motion options, else all of it. Its result is one undo step. False (nothing started)
  /// without a current take, for a control index out of range, or when the synthesis could not
  /// start.
  bool editControlPoint(int control, const Eigen::Vector2d& to, const SynthParameters& parameters);
  /// Starts in-betweening `keys` on `map` with `parameters`: a new take (`take` −1) or the new
  /// keys of the in-between take with id `take` (shown pending, as the straight lines between
  /// the keys, until its motion arrives). False when nothing could start.
  bool inbetween(std::shared_ptr<const MapResult> map, TakeKeys keys,
                 const SynthParameters& parameters, int take = -1);
  /// A new sketch is being synthesized (it stopped an edit's synthesis, if one ran).
  void sketchStarted();
  /// The take an edit is being synthesized for (−1: none).
  int pendingTake() const { return m_pending ? m_pending->first : -1; }
  /// The frames [first, end) the last edit that arrived re-made (a sketch's moved control point:
  /// synth::edit_path); nothing when it re-synthesized the whole take (other motion options, an
  /// in-between take).
  const std::optional<std::pair<int, int>>& lastEditWindow() const { return m_lastEditWindow; }

  /// Renames (an undoable step); false for an empty or unchanged name.
  bool rename(int row, const QString& name);
  /// Deletes (an undoable step); false for a row out of range.
  bool remove(int row);
  /// Records a method or parameter change already made; undo and redo call `apply` with the
  /// state before or after. Nothing is recorded while a recorded change is being applied.
  void recordMapChange(const MapState& before, const MapState& after, const QString& text,
                       const std::function<void(const MapState&)>& apply);
  /// Undo and redo: an edit being synthesized is cancelled first (its result would land on a
  /// take in another state).
  void undo();
  void redo();
  /// Forgets every take and the history (another clip).
  void clear();

  /// The takes sketched on `map` (nullptr: none) as the map view draws them: the current one with
  /// its control points, an edit being synthesized as its new path.
  std::vector<MapView::TakePath> pathsOn(const MapResult* map) const;
  /// The map point of frame `frame` of the current take's motion, when it was sketched on `map`
  /// (a take's map points belong to the map it was sketched on); nothing otherwise.
  std::optional<Eigen::Vector2d> pointOn(const MapResult* map, int frame) const;

 signals:
  /// Anything drawn changed (takes, the current one, a pending edit).
  void changed();

 private:
  void dropPending();

  SynthesisController* m_synthesis;
  TakeList m_list;
  QUndoStack m_stack;
  std::optional<std::pair<int, synth::MapPath>> m_pending;  ///< take id, its path being made
  bool m_applying = false;  ///< a recorded map change is being applied (not recorded again)
  std::optional<std::pair<int, int>> m_lastEditWindow;
};

}  // namespace motionmap::studio
