#pragma once
// The window's status line: what the map, the clip and the take say (joined by " · "), messages,
// and errors — shown as "Error: …", and in a message box too when the window is interactive (not
// in tests, nor with MOTIONMAP_STUDIO_NO_CONFIRM=1).
#include <functional>

#include <QLabel>
#include <QStringList>

namespace motionmap::studio {

class StatusLine : public QLabel {
  Q_OBJECT
 public:
  /// Message boxes are parented to `window`.
  explicit StatusLine(QWidget* window);

  /// Whether errors also open a message box (and the window asks questions).
  void setInteractive(bool interactive) { m_interactive = interactive; }
  bool interactive() const { return m_interactive; }
  /// The parts joined by " · " (cut at the window's edge; the tooltip shows each whole on its
  /// own line); nothing changes for none (no clip yet).
  void showParts(const QStringList& parts);
  /// Shows `message` as an error (a message box too when interactive); lastError() keeps it.
  void showError(const QString& message);
  QString lastError() const { return m_lastError; }
  /// Runs `work`; false, with the error it threw shown, when it throws.
  bool attempt(const std::function<void()>& work);

 private:
  QWidget* m_window;
  bool m_interactive = true;
  QString m_lastError;
};

}  // namespace motionmap::studio
