#pragma once
// Compare two clips (View → Compare with clip…): a second clip of the map played in sync with
// the one playing — the same time from its start (its own frame rate), held on its last frame
// when it is shorter — its character beside the one playing, in a 3-D view of its own (the
// Compare dock), or overlaid in the main 3-D view, translucent in the comparison colour: each
// at its own place, or moved onto the playing character's root so their poses coincide. Its
// trajectory is drawn over the map in the comparison colour with a ring at its frame
// (MapView::setComparison). Another map of the same clips keeps the comparison; a map without
// that clip ends it.
#include <functional>
#include <memory>
#include <vector>

#include <QDockWidget>

#include "motionmap/skeleton/skeleton.h"

class QComboBox;
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
  /// Where the compared character is drawn.
  enum class Placement {
    SideBySide,  ///< in the dock's own 3-D view
    Overlaid,    ///< in the main 3-D view, where its clip places it
    Together,    ///< in the main 3-D view, its root's floor point on the playing one's
  };

  /// `main` is the window's 3-D view (the one playing); `clipOf(c)` gives clip `c` of the map
  /// shown (loading it when needed; throws what loading throws). All must outlive this.
  ComparePanel(MapView* view, SkeletonView* main, Playback* playback,
               std::function<const MapSource*()> source,
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
  /// Side by side (default), overlaid, or overlaid together (the dock's choice).
  void setPlacement(Placement placement);
  Placement placement() const { return m_placement; }
  QComboBox* placementChoice() const { return m_placementChoice; }
  /// The shift applied to the compared character's world pose (overlaid together: its root's
  /// floor point onto the playing one's; else none).
  Eigen::Vector3d overlayShift() const { return m_shift; }

 signals:
  void failed(const QString& message);

 private:
  /// Frame `frame` of the motion playing is shown: the compared clip follows.
  void follow(int frame);
  /// The compared clip's trajectory on the map shown (and its frame → row table).
  void drawTrajectory();
  /// The compared character in the main view (overlaid) or none there (side by side).
  void drawOverlay();

  MapView* m_view;
  Playback* m_playback;
  std::function<const MapSource*()> m_source;
  std::function<std::shared_ptr<const Clip>(int)> m_clipOf;
  SkeletonView* m_main;
  SkeletonView* m_view3d;
  QComboBox* m_placementChoice;
  Placement m_placement = Placement::SideBySide;
  Eigen::Vector3d m_shift = Eigen::Vector3d::Zero();
  std::vector<bool> m_detached;  ///< the compared clip's joints drawn without a bone
  int m_root = 0;                ///< its motion root
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
