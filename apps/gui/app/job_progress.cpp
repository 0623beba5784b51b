#include "app/job_progress.h"

#include <algorithm>
#include <cmath>

#include <QProgressBar>
#include <QPushButton>
#include <QStatusBar>

namespace motionmap::studio {

namespace {
constexpr int kSteps = 1000;
}  // namespace

ElidedLabel::ElidedLabel(QWidget* parent) : QLabel(parent) {
  setTextFormat(Qt::PlainText);
}

void ElidedLabel::setFullText(const QString& text) {
  if (text == m_full) return;
  m_full = text;
  setToolTip(text);
  updateGeometry();
  elide();
}

QSize ElidedLabel::sizeHint() const {
  const int width = fontMetrics().horizontalAdvance(m_full) + 2 * margin() + 4;
  return {std::min(width, kMaxWidth), QLabel::sizeHint().height()};
}

QSize ElidedLabel::minimumSizeHint() const {
  // Narrow enough to give way to the status line; "…" still says there is more.
  return {std::min(sizeHint().width(), 60), QLabel::minimumSizeHint().height()};
}

void ElidedLabel::resizeEvent(QResizeEvent* event) {
  QLabel::resizeEvent(event);
  elide();
}

void ElidedLabel::elide() {
  QLabel::setText(fontMetrics().elidedText(m_full, Qt::ElideRight, contentsRect().width()));
}

JobProgress::JobProgress(QStatusBar* bar, const QString& cancelText, const QString& format)
    : QObject(bar),
      m_label(new ElidedLabel),
      m_bar(new QProgressBar),
      m_cancel(new QPushButton(cancelText)),
      m_startFormat(format.isEmpty() ? QStringLiteral("%p%") : format),
      m_format(m_startFormat) {
  m_label->setMaximumWidth(ElidedLabel::kMaxWidth);
  m_bar->setRange(0, kSteps);
  m_bar->setMaximumWidth(120);
  m_bar->setTextVisible(false);  // the label says it, in full on hover
  m_label->hide();
  m_bar->hide();
  m_cancel->hide();
  m_cancel->setToolTip(tr("Stops the work at once; what was shown before stays"));
  // A click is enough: with the focus (given it when the window activates while a map computes)
  // it would take Space and the arrows from the window, and Space would cancel.
  m_cancel->setFocusPolicy(Qt::NoFocus);
  connect(m_cancel, &QPushButton::clicked, this, &JobProgress::cancelClicked);
  bar->addPermanentWidget(m_label);
  bar->addPermanentWidget(m_bar);
  bar->addPermanentWidget(m_cancel);
}

void JobProgress::start() {
  m_bar->setValue(0);
  m_format = m_startFormat;  // not the last stage of the job before
  showText();
  m_label->show();
  m_bar->show();
  m_cancel->show();
}

void JobProgress::setProgress(double fraction, const QString& format) {
  m_bar->setValue(int(std::clamp(fraction, 0.0, 1.0) * kSteps));
  if (!format.isEmpty()) m_format = format;
  showText();
}

void JobProgress::showText() {
  const int percent = int(std::lround(100.0 * m_bar->value() / kSteps));
  QString text = m_format;
  text.replace(QLatin1String("%p"), QString::number(percent));
  m_label->setFullText(text);
  m_bar->setToolTip(text);
}

void JobProgress::stop() {
  m_label->hide();
  m_bar->hide();
  m_cancel->hide();
}

}  // namespace motionmap::studio
