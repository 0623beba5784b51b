#include "app/window_dialogs.h"

#include <QFileDialog>
#include <QInputDialog>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>

#include "takes/takes.h"

namespace motionmap::studio {

bool askDiscard(QWidget* parent, const QStringList& unexported,
                const std::function<bool(const QString& folder)>& exportTo) {
  if (unexported.isEmpty()) return true;
  const QString text = unexported.size() == 1
                           ? QObject::tr("%1 has not been exported.").arg(unexported.front())
                           : QObject::tr("%1 takes have not been exported (%2).")
                                 .arg(unexported.size())
                                 .arg(unexported.join(", "));
  QMessageBox box(QMessageBox::Question, QObject::tr("MotionMap Studio"), text,
                  QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, parent);
  box.button(QMessageBox::Save)
      ->setText(unexported.size() == 1 ? QObject::tr("Export…") : QObject::tr("Export All…"));
  box.setDefaultButton(QMessageBox::Save);
  switch (box.exec()) {
    case QMessageBox::Discard:
      return true;
    case QMessageBox::Save: {
      const QString folder =
          QFileDialog::getExistingDirectory(parent, QObject::tr("Export the takes as BVH into"));
      return !folder.isEmpty() && exportTo(folder);
    }
    default:
      return false;
  }
}

std::optional<std::vector<double>> askKeyTimes(QWidget* parent, const Take& take, QString& error) {
  // The keys' times now (seconds from the first key), as the dialog's starting text.
  QStringList now;
  const double dt = take.result->motion.frame_time;
  for (const int frame : take.controls)
    now << QString::number((frame - take.controls.front()) * dt, 'g', 4);
  bool ok = false;
  const QString text = QInputDialog::getText(
      parent, QObject::tr("Retime keys"),
      QObject::tr("Each key's time in seconds from the first, separated by commas (empty: the "
                  "frames' own speed along the route):"),
      QLineEdit::Normal, now.join(", "), &ok);
  if (!ok) return std::nullopt;
  std::vector<double> times;
  for (const QString& part : text.split(',', Qt::SkipEmptyParts)) {
    bool number = false;
    const double t = part.trimmed().toDouble(&number);
    if (!number) {
      error = QObject::tr("'%1' is not a number of seconds").arg(part.trimmed());
      return std::nullopt;
    }
    times.push_back(t);
  }
  return times;
}

}  // namespace motionmap::studio
