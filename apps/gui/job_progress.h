#pragma once
// A worker's progress in the status bar: a bar and a Cancel button, shown while the worker runs
// (the map, a synthesis), hidden when it stops.
#include <QObject>
#include <QString>

class QProgressBar;
class QPushButton;
class QStatusBar;

namespace motionmap::studio {

class JobProgress : public QObject {
  Q_OBJECT
 public:
  /// Adds the bar and a button labelled `cancelText` to `bar` as permanent widgets, hidden.
  /// `format` is the bar's text (%p: the percentage); empty: Qt's default.
  JobProgress(QStatusBar* bar, const QString& cancelText, const QString& format = {});

  /// Shows both at 0 %.
  void start();
  /// The fraction done (0…1), and the bar's text when `format` is not empty.
  void setProgress(double fraction, const QString& format = {});
  /// Hides both.
  void stop();

 signals:
  void cancelClicked();

 private:
  QProgressBar* m_bar;
  QPushButton* m_cancel;
};

}  // namespace motionmap::studio
