#pragma once
// The map the user chose in the Motion menu, without widgets: its method, the map parameters and
// the synthesis parameters. A choice asks the MapController for that map (at once from its cache,
// else computed on its worker), becomes an undo step once its map is shown (MapChangeRecorder),
// and is saved in QSettings when its map was made without error, so the next session starts from
// it. When a computation fails or is cancelled, the choice goes back to the map shown before.
// On a map that cannot be recomputed (a saved map) only the synthesis parameters change.
#include <QObject>

#include "common/parameters.h"
#include "takes/undo_commands.h"

namespace motionmap::studio {

class MapController;
class TakesController;

class MapChoice : public QObject {
  Q_OBJECT
 public:
  /// Starts from the last session's choice (QSettings). `maps` and `takes` (the undo history)
  /// must outlive this.
  MapChoice(MapController* maps, TakesController* takes, QObject* parent = nullptr);

  embed::Method method() const { return m_method; }
  const MapParameters& parameters() const { return m_parameters; }
  const SynthParameters& synthParameters() const { return m_synth; }
  MapState state() const { return {m_method, m_parameters, m_synth}; }

  /// Whether the map shown can be recomputed (false: setMethod is refused).
  void setRecomputable(bool recomputable) { m_recomputable = recomputable; }
  /// Asks for the map of `method` with the current parameters: cachedMapReady at once when it is
  /// cached, else the MapController computes it.
  void setMethod(embed::Method method);
  /// The map parameters changed: the current method's map with them.
  void setParameters(const MapParameters& parameters);
  /// Checks `parameters` with the library (K against the samples of the map shown): false, with
  /// failed(message), for a value it rejects. A new blend asks for the map again.
  bool setSynthParameters(const SynthParameters& parameters);
  /// Goes back to `state` (undo, redo): its map from the cache when it was shown before.
  void applyState(const MapState& state);
  /// Forgets a change whose map is still computing (other clips, a new history).
  void dropPending() { m_changes.drop(); }

 signals:
  /// The method to check in the Motion menu.
  void methodChanged(motionmap::embed::Method method);
  /// The map asked for came from the cache: it is the controller's current map now.
  void cachedMapReady(motionmap::embed::Method method);
  /// setMethod (or new parameters) on a map that cannot be recomputed: `method` was asked for.
  void refused(motionmap::embed::Method method);
  /// The synthesis parameters changed (a saved map's drags blend their K).
  void synthChanged();
  /// The library's message for a value it rejects.
  void failed(const QString& message);

 private:
  /// Both parameter sets to QSettings (the next session's).
  void save() const;
  /// After a failed or cancelled map: the choice of the map shown again (if any).
  void restoreShown();

  MapController* m_maps;
  embed::Method m_method = embed::Method::Isomap;
  MapParameters m_parameters;
  SynthParameters m_synth;
  bool m_recomputable = true;
  MapChangeRecorder m_changes;
};

}  // namespace motionmap::studio
