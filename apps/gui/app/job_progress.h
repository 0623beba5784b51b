#pragma once
// A worker's progress in the status bar: what it is doing ("shortest paths 45%"), a bar and a
// Cancel button, shown while the worker runs (the map, a synthesis), hidden when it stops. The
// text is elided to the room the status bar leaves it, and its whole is the tooltip of the text
// and of the bar, so a long stage name can always be read.
#include <QLabel>
#include <QObject>
#include <QString>

class QProgressBar;
class QPushButton;
class QStatusBar;

namespace motionmap::studio {

/// A label showing as much of its text as fits, ending in "…" when cut, the whole text as its
/// tooltip.
class ElidedLabel : public QLabel {
  Q_OBJECT
 public:
  /// Never wider than this (px): the status line's own text keeps the rest.
  static constexpr int kMaxWidth = 360;

  explicit ElidedLabel(QWidget* parent = nullptr);
  void setFullText(const QString& text);
  QString fullText() const { return m_full; }
  QSize sizeHint() const override;
  QSize minimumSizeHint() const override;

 protected:
  void resizeEvent(QResizeEvent* event) override;

 private:
  void elide();
  QString m_full;
};

class JobProgress : public QObject {
  Q_OBJECT
 public:
  /// Adds the text, the bar and a button labelled `cancelText` to `bar` as permanent widgets,
  /// hidden. `format` is the text (%p: the percentage); empty: the percentage alone.
  JobProgress(QStatusBar* bar, const QString& cancelText, const QString& format = {});

  /// Shows them at 0 %.
  void start();
  /// The fraction done (0…1), and the text's format when `format` is not empty.
  void setProgress(double fraction, const QString& format = {});
  /// Hides them.
  void stop();

  ElidedLabel* label() const { return m_label; }
  QProgressBar* bar() const { return m_bar; }
  QPushButton* cancelButton() const { return m_cancel; }

 signals:
  void cancelClicked();

 private:
  void showText();

  ElidedLabel* m_label;
  QProgressBar* m_bar;
  QPushButton* m_cancel;
  QString m_startFormat;  ///< the text until the job says its stage
  QString m_format;
};

}  // namespace motionmap::studio
