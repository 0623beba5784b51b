#pragma once
// Compare two clips (View → Compare with clip…): a second clip of the map played in sync with
// the one playing — the same time from its start (its own frame rate), held on its last frame
// when it is shorter — its character in a 3-D view of its own (the Compare dock, beside the
// main one), its trajectory drawn over the map in the comparison colour with a ring at its
// frame (MapView::setComparison). Another map of the same clips keeps the comparison; a map
// without that clip ends it.
#include <functional>
#include <memory>
#include <vector>

#include <QDockWidget>

#include "motionmap/skeleton/skeleton.h"

class QLabel;
class QPushButton;

namespace motionmap::studio {

class MapSource;
class MapView;
class Playback;
class SkeletonView;

class ComparePanel : public QDockWidget {
  Q_OBJECT
 public:
  /// `clipOf(c)` gives clip `c` of the map shown (loading it when needed; throws what loading
  /// throws). All must outlive this.
  ComparePanel(MapView* view, Playback* playback, std::function<const MapSource*()> source,
               std::function<std::shared_ptr<const Clip>(int)> clipOf, QWidget* parent = nullptr);

  /// Plays clip `clip` of the map beside the clip playing. False (failed() says why) for a clip
  /// out of range or one that cannot be loaded; the comparison before stays.
  bool compareWith(int clip);
  /// Ends the comparison (the dock hides, the map's comparison goes).
  void stop();
  /// The clip compared (−1: none) and its frame shown.
  int comparedClip() const { return m_clip; }
  int comparedFrame() const { return m_frame; }
  /// The frame of the compared clip shown with frame `frame` of the motion playing.
  int syncedFrame(int frame) const;
  SkeletonView* view3d() const { return m_view3d; }
  QLabel* caption() const { return m_caption; }

 signals:
  void failed(const QString& message);

 private:
  /// Frame `frame` of the motion playing is shown: the compared clip follows.
  void follow(int frame);
  /// The compared clip's trajectory on the map shown (and its frame → row table).
  void drawTrajectory();

  MapView* m_view;
  Playback* m_playback;
  std::function<const MapSource*()> m_source;
  std::function<std::shared_ptr<const Clip>(int)> m_clipOf;
  SkeletonView* m_view3d;
  QLabel* m_caption;
  QPushButton* m_stop;
  std::shared_ptr<const Clip> m_compared;
  int m_clip = -1;
  int m_frame = 0;
  QString m_name;
  Eigen::MatrixXd m_trajectory;   ///< the compared clip's map points (its samples, in order)
  std::vector<int> m_rowOfFrame;  ///< per frame of the compared clip: its row in m_trajectory
};

}  // namespace motionmap::studio
