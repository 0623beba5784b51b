#include "app/status_line.h"

#include <exception>

#include <QMessageBox>

namespace motionmap::studio {

StatusLine::StatusLine(QWidget* window) : QLabel(QObject::tr("No clip")), m_window(window) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
}

void StatusLine::showParts(const QStringList& parts) {
  if (!parts.isEmpty()) setText(parts.join(QStringLiteral(" · ")));
}

void StatusLine::showError(const QString& message) {
  m_lastError = message;
  setText(tr("Error: %1").arg(message));
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
