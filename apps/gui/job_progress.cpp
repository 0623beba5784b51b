#include "job_progress.h"

#include <QProgressBar>
#include <QPushButton>
#include <QStatusBar>

namespace motionmap::studio {

namespace {
constexpr int kSteps = 1000;
}  // namespace

JobProgress::JobProgress(QStatusBar* bar, const QString& cancelText, const QString& format)
    : QObject(bar), m_bar(new QProgressBar), m_cancel(new QPushButton(cancelText)) {
  m_bar->setRange(0, kSteps);
  m_bar->setMaximumWidth(200);
  if (!format.isEmpty()) m_bar->setFormat(format);
  m_bar->hide();
  m_cancel->hide();
  connect(m_cancel, &QPushButton::clicked, this, &JobProgress::cancelClicked);
  bar->addPermanentWidget(m_bar);
  bar->addPermanentWidget(m_cancel);
}

void JobProgress::start() {
  m_bar->setValue(0);
  m_bar->show();
  m_cancel->show();
}

void JobProgress::setProgress(double fraction, const QString& format) {
  m_bar->setValue(int(fraction * kSteps));
  if (!format.isEmpty()) m_bar->setFormat(format);
}

void JobProgress::stop() {
  m_bar->hide();
  m_cancel->hide();
}

}  // namespace motionmap::studio
