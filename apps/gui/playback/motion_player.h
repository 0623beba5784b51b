#pragma once
// Which motion plays — the clip shown by the map's source, or the current take — and the frame
// of it shown: the playback clock told its length and rate, the 3-D view posed, the map's pointer
// on the frame's point (a take's point on the map it was sketched on). The window asks it for the
// motion playing and wires its signals to the menus and the status line.
#include <functional>

#include <QObject>
#include <QStringList>

#include "map/map_controller.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::studio {

class MapSource;
class MapView;
class Playback;
class SkeletonView;
class TakesController;

class MotionPlayer : public QObject {
  Q_OBJECT
 public:
  /// `source` gives the map source shown and `map` the computed map shown (nullptr: none); the
  /// others must outlive this.
  MotionPlayer(Playback* playback, SkeletonView* skeletonView, MapView* mapView,
               TakesController* takes, std::function<MapSource*()> source,
               std::function<const MapResult*()> map, QObject* parent = nullptr);

  /// The current take's motion (nothing before the first sketch, or with no take selected).
  const synth::SynthResult* synthesized() const;
  /// A take plays (else the clip), whether or not it still has a motion.
  bool playsTake() const { return m_playsTake; }
  /// The motion playing: the current take's when a take plays, else the clip's (nullptr: none).
  const Motion* playingMotion() const;
  /// Clip `index` of the source plays from `frame` (no take current). False when the source did
  /// not make it the clip playing (out of range, failed, or still loading).
  bool playClip(int index, int frame);
  /// The current take plays from its first frame; without a current take, the clip again (when
  /// a take was playing).
  void playCurrentTake();
  /// Shows frame `frame` of the motion playing (the clock's frameChanged).
  void showFrame(int frame);
  /// Playback stops and the clip is what plays (the takes are about to go).
  void stop();
  /// The take's part of the status line: its frames, how many lie outside the data and the
  /// synthesis' notes (empty while the clip plays).
  QStringList statusParts() const;

 signals:
  /// Frame `frame` is shown.
  void frameShown(int frame);
  /// Another motion (or none) plays: `shown` whether there is one.
  void motionShown(bool shown);
  /// The current take changed: `exportable` whether there is one to export.
  void takeShown(bool exportable);
  /// What plays changed: the status line is out of date.
  void statusChanged();

 private:
  /// Tells the clock the length and rate of the motion playing, and the 3-D view its bones.
  void updateMotion();

  Playback* m_playback;
  SkeletonView* m_skeletonView;
  MapView* m_mapView;
  TakesController* m_takes;
  std::function<MapSource*()> m_source;
  std::function<const MapResult*()> m_map;
  bool m_playsTake = false;
};

}  // namespace motionmap::studio
