#include "transport_bar.h"

#include <algorithm>

#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSlider>

#include "playback.h"

namespace motionmap::studio {

namespace {
constexpr double kSpeeds[] = {0.25, 0.5, 1.0, 2.0, 4.0};
}  // namespace

TransportBar::TransportBar(Playback* playback, QWidget* parent)
    : QWidget(parent), m_playback(playback) {
  m_playButton = new QPushButton(playback->isPlaying() ? tr("Pause") : tr("Play"));
  m_playButton->setFocusPolicy(Qt::NoFocus);
  m_slider = new QSlider(Qt::Horizontal);
  m_slider->setEnabled(false);
  m_slider->setFocusPolicy(Qt::NoFocus);
  m_speedBox = new QComboBox;
  m_speedBox->setFocusPolicy(Qt::NoFocus);
  m_speedBox->setToolTip(tr("Playback speed"));
  for (double s : kSpeeds) m_speedBox->addItem(QString("%1×").arg(s), s);
  m_speedBox->setCurrentIndex(2);
  showSpeed(playback->speed());
  m_loopBox = new QCheckBox(tr("Loop"));
  m_loopBox->setFocusPolicy(Qt::NoFocus);
  m_loopBox->setChecked(playback->loop());
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(m_playButton);
  layout->addWidget(m_slider, 1);
  layout->addWidget(m_speedBox);
  layout->addWidget(m_loopBox);

  // Controls → clock.
  connect(m_playButton, &QPushButton::clicked, this,
          [this] { m_playback->isPlaying() ? m_playback->pause() : m_playback->play(); });
  connect(m_slider, &QSlider::valueChanged, this, [this](int v) {
    if (v != m_playback->frame()) m_playback->setFrame(v);
  });
  connect(m_speedBox, &QComboBox::currentIndexChanged, this,
          [this](int i) { m_playback->setSpeed(m_speedBox->itemData(i).toDouble()); });
  connect(m_loopBox, &QCheckBox::toggled, m_playback, &Playback::setLoop);

  // Clock → controls.
  connect(playback, &Playback::playingChanged, this,
          [this](bool playing) { m_playButton->setText(playing ? tr("Pause") : tr("Play")); });
  connect(playback, &Playback::frameCountChanged, this, [this](int frames) {
    m_slider->setRange(0, std::max(0, frames - 1));
    m_slider->setEnabled(frames > 0);
  });
  connect(playback, &Playback::frameChanged, this, [this](int frame) {
    if (m_slider->value() == frame) return;
    const QSignalBlocker block(m_slider);
    m_slider->setValue(frame);
  });
  connect(playback, &Playback::speedChanged, this, &TransportBar::showSpeed);
  connect(playback, &Playback::loopChanged, this, [this](bool loop) {
    if (m_loopBox->isChecked() == loop) return;
    const QSignalBlocker block(m_loopBox);
    m_loopBox->setChecked(loop);
  });
}

void TransportBar::showSpeed(double speed) {
  // A speed that is not in the list (a call, not the box) leaves the box as it was.
  const int i = m_speedBox->findData(speed);
  if (i < 0 || i == m_speedBox->currentIndex()) return;
  const QSignalBlocker block(m_speedBox);
  m_speedBox->setCurrentIndex(i);
}

}  // namespace motionmap::studio
