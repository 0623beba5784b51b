#include "app/status_line.h"

#include <exception>

#include <QMessageBox>

namespace motionmap::studio {

StatusLine::StatusLine(QWidget* window) : QLabel(QObject::tr("No clip")), m_window(window) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
  // A long line (a take's notes, an error) is cut at the window's edge rather than widening it.
  setMinimumWidth(1);
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Preferred);
}

void StatusLine::showParts(const QStringList& parts) {
  if (parts.isEmpty()) return;
  setText(parts.join(QStringLiteral(" · ")));
  setToolTip(parts.join(QLatin1Char('\n')));  // each part whole, on its own line
}

void StatusLine::showError(const QString& message) {
  m_lastError = message;
  setText(tr("Error: %1").arg(message));
  setToolTip(message);
  if (m_interactive) QMessageBox::warning(m_window, tr("MotionMap Studio"), message);
}

bool StatusLine::attempt(const std::function<void()>& work) {
  try {
    work();
    return true;
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

}  // namespace motionmap::studio
