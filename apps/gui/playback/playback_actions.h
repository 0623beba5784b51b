#pragma once
// The Playback menu: the window's playback keys as actions (Space play/pause, ← / → one frame,
// Shift+← / Shift+→ ten, Home / End the range's first and last frame, I / O the in and out
// points, Alt+I / Alt+O clear them, and Loop). They are window shortcuts (Qt::WindowShortcut,
// also added to the window itself, so they work with the menu bar hidden): they work as soon as
// the window is active, whichever of its widgets has the focus — no click into a view first. A
// text or number field being typed in keeps the keys it edits with (Qt's ShortcutOverride), and
// the 3-D view keeps Home for its camera the same way.
#include <QObject>

class QAction;
class QMainWindow;
class QMenu;

namespace motionmap::studio {

class Playback;

class PlaybackActions : public QObject {
  Q_OBJECT
 public:
  /// Adds the Playback menu to `window`'s menu bar, its entries driving `playback` (which must
  /// outlive the window's actions).
  PlaybackActions(QMainWindow* window, Playback* playback);

  QMenu* menu() const { return m_menu; }
  QAction* playPause() const { return m_playPause; }
  QAction* previousFrame() const { return m_previous; }
  QAction* nextFrame() const { return m_next; }
  QAction* backTen() const { return m_backTen; }
  QAction* forwardTen() const { return m_forwardTen; }
  QAction* firstFrame() const { return m_first; }
  QAction* lastFrame() const { return m_last; }
  QAction* setIn() const { return m_setIn; }
  QAction* setOut() const { return m_setOut; }
  QAction* clearIn() const { return m_clearIn; }
  QAction* clearOut() const { return m_clearOut; }
  QAction* loop() const { return m_loop; }

  /// Frames Shift+← / Shift+→ move.
  static constexpr int kBigStep = 10;

 private:
  QMenu* m_menu;
  QAction* m_playPause;
  QAction* m_previous;
  QAction* m_next;
  QAction* m_backTen;
  QAction* m_forwardTen;
  QAction* m_first;
  QAction* m_last;
  QAction* m_setIn;
  QAction* m_setOut;
  QAction* m_clearIn;
  QAction* m_clearOut;
  QAction* m_loop;
};

}  // namespace motionmap::studio
