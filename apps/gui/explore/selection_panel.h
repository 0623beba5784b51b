#pragma once
// The Selection panel (a dock): the frames a box or a lasso drawn on the map holds (right drag: a
// box, Shift + right drag: a lasso, a right click: none), listed per clip with their frame ranges;
// double-click a range (or a clip) to play it, **Play all** plays every range one after another
// (loop off meanwhile, the in/out points set to each range), **Export list…** writes the clips as
// a clip list (`motionmap map @list.txt` reads it; each clip's ranges in a comment above it) and
// **Export CSV…** the frames (clip, frame, x, y). The selected points are drawn on the map in
// MapView::selectionColor() with the outline drawn; a new map clears the selection.
#include <functional>
#include <vector>

#include <QDockWidget>
#include <QTimer>

#include "explore/selection.h"

class QLabel;
class QPushButton;
class QTreeWidget;
class QTreeWidgetItem;

namespace motionmap::studio {

class MapSource;
class MapView;
class Playback;

class SelectionPanel : public QDockWidget {
  Q_OBJECT
 public:
  /// Selections are drawn on `view`, played with `playback` after `showClip(clip, frame)` made
  /// the clip current (at once, or once a saved map's clip has loaded: `source` says which clip
  /// plays). All must outlive this.
  SelectionPanel(MapView* view, Playback* playback, std::function<const MapSource*()> source,
                 std::function<void(int clip, int frame)> showClip, QWidget* parent = nullptr);

  /// Selects the frames inside `polygon` (map coordinates), or none for fewer than 3 corners.
  void select(const QPolygonF& polygon);
  void clear();
  const std::vector<SelectedFrame>& frames() const { return m_frames; }
  const std::vector<FrameRange>& ranges() const { return m_ranges; }
  /// The list's entries (one per clip, its ranges below it).
  QTreeWidget* tree() const { return m_tree; }

  /// Plays ranges()[index] (then stops, unless Play all goes on).
  void playRange(int index);
  /// Plays every range in order.
  void playAll();
  /// Stops Play all (playback pauses).
  void stopSequence();
  bool playingAll() const { return m_sequence; }
  /// The range playing (or waiting for its clip); −1: none.
  int rangePlaying() const { return m_playing; }

  /// Writes the clip list / the CSV; false with `error` set on failure.
  bool exportList(const QString& path, QString* error = nullptr) const;
  bool exportCsv(const QString& path, QString* error = nullptr) const;

 signals:
  /// A line for the status bar.
  void message(const QString& text);
  void failed(const QString& message);

 private:
  void rebuild();
  /// Starts ranges()[m_playing] once its clip is the one shown.
  void startWhenShown();
  void onPlayingChanged(bool playing);
  void chooseAndExport(bool list);

  MapView* m_view;
  Playback* m_playback;
  std::function<const MapSource*()> m_source;
  std::function<void(int, int)> m_showClip;
  std::vector<SelectedFrame> m_frames;
  std::vector<FrameRange> m_ranges;
  QTreeWidget* m_tree;
  QLabel* m_summary;
  QPushButton* m_playAll;
  QPushButton* m_exportList;
  QPushButton* m_exportCsv;
  QTimer m_wait;       ///< polls while a range's clip is being shown (a saved map's loads)
  int m_playing = -1;  ///< index into m_ranges
  bool m_sequence = false;
  bool m_started = false;    ///< the range's playback has begun
  bool m_loopBefore = true;  ///< Loop as it was before the selection played
};

}  // namespace motionmap::studio
