#pragma once
// View → Key poses: a dock under the views with the key poses of the clip playing (KeyPoses) as
// a strip of stick figures in time order (render::paint_sheet_poses, the drawing of `motionmap
// keyposes`' contact sheet), each numbered and captioned with its frame and time. A click on one
// asks the window to play the clip from that frame; the one playback is on is highlighted. The
// count is a spin box beside the strip. Whether the strip is shown and the count are remembered
// (QSettings "keyPoses/shown", "keyPoses/count"). Computed only while shown.
#include <functional>

#include <QDockWidget>

class QMainWindow;
class QSpinBox;

namespace motionmap::studio {

class KeyPoses;
class MapSource;

/// The figures: one cell per key pose, at least kMinCell pixels wide (the strip scrolls beyond).
class KeyPoseThumbnails : public QWidget {
  Q_OBJECT
 public:
  static constexpr int kMinCell = 96;
  explicit KeyPoseThumbnails(const KeyPoses* keys, QWidget* parent = nullptr);
  /// Key pose i's cell (widget coordinates; empty out of range).
  QRect cellRect(int i) const;
  /// The key pose under `pos` (−1: none).
  int indexAt(const QPoint& pos) const;
  /// The key pose drawn highlighted (−1: none).
  int highlighted() const { return m_highlighted; }
  void setHighlighted(int index);
  QSize sizeHint() const override;

 signals:
  void clicked(int index);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;

 private:
  int cellWidth() const;

  const KeyPoses* m_keys;
  int m_highlighted = -1;
};

class KeyPoseStrip : public QDockWidget {
  Q_OBJECT
 public:
  /// Docks itself under `window`'s views, shown as last time (hidden the first time). `source`
  /// gives the map source shown; `clipPlays` whether its clip plays (not a take).
  KeyPoseStrip(QMainWindow* window, std::function<const MapSource*()> source,
               std::function<bool()> clipPlays);
  KeyPoses* keyPoses() const { return m_keys; }
  KeyPoseThumbnails* thumbnails() const { return m_thumbnails; }
  QSpinBox* countBox() const { return m_count; }

  /// Frame `frame` of the motion playing is shown: the key poses follow a change of clip or
  /// map, and the one on `frame` is highlighted.
  void showFrame(int frame);

 signals:
  /// A key pose was clicked: play clip `clip` from `frame`.
  void clipRequested(int clip, int frame);

 private:
  void updateView();

  KeyPoses* m_keys;
  KeyPoseThumbnails* m_thumbnails;
  QSpinBox* m_count;
  std::function<bool()> m_clipPlays;
  int m_frame = -1;
};

}  // namespace motionmap::studio
