#pragma once
// Key poses in Studio: Ctrl-click on the map places a key — the frame under the mouse when a
// frame's point is within MapGestures::kNearPixels, else the map point itself — numbered in the
// order placed. Two keys make an in-between take (synth::inbetween on the worker: the route
// through the map's valid region drawn, the motion played when it arrives); further Ctrl-clicks
// add keys to the current in-between take, a Ctrl-click on one of its keys removes it, dragging a
// key moves it (onto the frame it is dropped near, else to the map point), and retime() sets the
// keys' times. Every change is one undo step (an edit of the take), made when its motion arrives.
// On a computed map and on a saved one alike: the map is the source's blendMap() (a saved map's
// blender, built on a worker; a click before it is ready says so and is not kept).
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <QObject>
#include <QPointF>
#include <QString>

#include "common/parameters.h"
#include "motionmap/synth/inbetween.h"
#include "takes/takes.h"

namespace motionmap::studio {

class MapSource;
class MapView;
class SynthesisController;
class TakesController;
struct MapResult;

class KeysController : public QObject {
  Q_OBJECT
 public:
  /// Keys on the map `source` gives now (its blendMap()), drawn on `mapView`, made into takes of
  /// `takes` through `synthesis`; `parameters` gives the synthesis parameters now. All must
  /// outlive this.
  KeysController(std::function<MapSource*()> source, MapView* mapView, TakesController* takes,
                 SynthesisController* synthesis, std::function<SynthParameters()> parameters,
                 QObject* parent = nullptr);

  /// A Ctrl-click at map point `point` (widget pixel `pixel`): removes the current in-between
  /// take's key drawn there, else adds a key there (see the top). False when nothing changed
  /// (no map to blend on, or a refusal reported by failed(): a saved map's blender still being
  /// built, or a clip it cannot load).
  bool click(const Eigen::Vector2d& point, const QPointF& pixel);
  /// Moves key `index` of the current in-between take to `point` (pixel `pixel`).
  bool moveKey(int index, const Eigen::Vector2d& point, const QPointF& pixel);
  /// Sets the current in-between take's keys' times (seconds from the first key, one per key,
  /// increasing); empty: back to the samples' own speed. False (failed() says why) otherwise.
  bool retime(const std::vector<double>& times);
  /// The current take, when it is an in-between take of the map shown.
  const Take* keyedTake() const;
  /// Keys placed before the first in-between (fewer than two, or two being in-betweened).
  const std::vector<synth::Key>& pendingKeys() const { return m_pending; }
  /// Forgets the pending keys (another clip or map).
  void clearPending();

 signals:
  void failed(const QString& message);
  /// An in-betweening started (the window shows its progress).
  void started();

 private:
  /// The key a click at `point` / `pixel` makes on `map`. @throws a saved map's clip errors.
  synth::Key keyAt(const MapResult& map, const Eigen::Vector2d& point, const QPointF& pixel) const;
  /// The map to place keys on; nullptr (failed() saying why, when there is something to say)
  /// when there is none yet.
  std::shared_ptr<const MapResult> keyMap();
  bool start(TakeKeys keys, int take);
  void showPending();

  std::function<MapSource*()> m_source;
  MapView* m_mapView;
  TakesController* m_takes;
  SynthesisController* m_synthesis;
  std::function<SynthParameters()> m_parameters;
  std::vector<synth::Key> m_pending;
};

}  // namespace motionmap::studio
