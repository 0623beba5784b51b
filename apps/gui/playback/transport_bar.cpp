#include "playback/transport_bar.h"

#include <algorithm>
#include <cmath>

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QLabel>
#include <QPainter>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QStyleOptionSlider>

#include "playback/playback.h"

namespace motionmap::studio {

namespace {
constexpr double kSpeeds[] = {0.25, 0.5, 1.0, 2.0, 4.0};
/// Height of the range band under the groove (px).
constexpr int kBandHeight = 4;
}  // namespace

RangeSlider::RangeSlider(QWidget* parent) : QSlider(Qt::Horizontal, parent) {
  // Room under the groove for the band, whatever the style's slider height.
  setMinimumHeight(sizeHint().height() + kBandHeight);
}

QColor RangeSlider::bandColor() {
  return QColor(255, 140, 0);  // orange: apart from the style's blue and the map's red → blue
}

void RangeSlider::setRangeMarks(int first, int last) {
  m_first = first;
  m_last = last;
  update();
}

void RangeSlider::clearRangeMarks() {
  setRangeMarks(-1, -1);
}

int RangeSlider::xOfValue(int value) const {
  QStyleOptionSlider option;
  initStyleOption(&option);
  const QRect groove =
      style()->subControlRect(QStyle::CC_Slider, &option, QStyle::SC_SliderGroove, this);
  const QRect handle =
      style()->subControlRect(QStyle::CC_Slider, &option, QStyle::SC_SliderHandle, this);
  // The handle's centre travels from half a handle inside the groove's left end to its right.
  const int span = groove.width() - handle.width();
  return groove.x() + handle.width() / 2 +
         QStyle::sliderPositionFromValue(minimum(), maximum(), value, span, option.upsideDown);
}

QRect RangeSlider::bandRect() const {
  if (m_first < 0 || m_last < m_first || maximum() <= minimum()) return {};
  const int left = xOfValue(m_first);
  const int right = xOfValue(m_last);
  return QRect(left - 1, height() - kBandHeight, right - left + 3, kBandHeight);
}

void RangeSlider::paintEvent(QPaintEvent* event) {
  QSlider::paintEvent(event);
  const QRect band = bandRect();
  if (band.isEmpty()) return;
  QPainter painter(this);
  painter.fillRect(band, bandColor());
  // A mark at each end, up through the groove, so a one-frame range still shows.
  painter.fillRect(QRect(band.left(), 0, 2, height()), bandColor());
  painter.fillRect(QRect(band.right() - 1, 0, 2, height()), bandColor());
}

TransportBar::TransportBar(Playback* playback, QWidget* parent)
    : QWidget(parent), m_playback(playback) {
  m_playButton = new QPushButton(playback->isPlaying() ? tr("Pause") : tr("Play"));
  m_playButton->setFocusPolicy(Qt::NoFocus);
  m_playButton->setToolTip(tr("Play or pause the motion (Space)"));
  m_slider = new RangeSlider;
  m_slider->setEnabled(false);
  m_slider->setFocusPolicy(Qt::NoFocus);
  m_slider->setToolTip(
      tr("The frame shown: drag to scrub (← / →: one frame, Shift+← / Shift+→: ten, Home / End: "
         "first / last). The orange band is the in/out range that playback stays within (I / O "
         "set it at the current frame, Alt+I / Alt+O clear it)"));
  m_frameBox = new QSpinBox;
  m_frameBox->setKeyboardTracking(false);  // a typed number counts on Enter, not per digit
  m_frameBox->setFocusPolicy(Qt::ClickFocus);
  m_frameBox->setPrefix(tr("Frame "));
  m_frameBox->setToolTip(
      tr("The current frame (0 is the first): type a frame and press Enter to go there; Esc "
         "leaves the field"));
  m_timeBox = new QDoubleSpinBox;
  m_timeBox->setKeyboardTracking(false);
  m_timeBox->setFocusPolicy(Qt::ClickFocus);
  m_timeBox->setDecimals(3);
  m_timeBox->setSuffix(tr(" s"));
  m_timeBox->setToolTip(
      tr("The current time in seconds (frame × frame time): type a time and press Enter to go to "
         "the frame nearest it; Esc leaves the field"));
  m_lengthLabel = new QLabel;
  m_lengthLabel->setToolTip(
      tr("The length of the motion playing (frames, and frames × frame time in seconds), and "
         "the in/out range when one is set"));
  m_speedBox = new QComboBox;
  m_speedBox->setFocusPolicy(Qt::NoFocus);
  m_speedBox->setToolTip(tr("Playback speed: 1× is the motion's own frame rate"));
  for (double s : kSpeeds) m_speedBox->addItem(QString("%1×").arg(s), s);
  m_speedBox->setCurrentIndex(2);
  showSpeed(playback->speed());
  m_loopBox = new QCheckBox(tr("Loop"));
  m_loopBox->setFocusPolicy(Qt::NoFocus);
  m_loopBox->setChecked(playback->loop());
  m_loopBox->setToolTip(
      tr("On: playback starts over at the end of the in/out range (the motion's end without one). "
         "Off: it stops on the range's last frame"));
  for (QAbstractSpinBox* box :
       {static_cast<QAbstractSpinBox*>(m_frameBox), static_cast<QAbstractSpinBox*>(m_timeBox)}) {
    box->installEventFilter(this);
    // Focus by a click only, not by Tab or the wheel: a wheel turn over the field would
    // otherwise take the playback keys away from the window.
    for (QWidget* child : box->findChildren<QWidget*>()) child->setFocusPolicy(Qt::ClickFocus);
  }
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(m_playButton);
  layout->addWidget(m_slider, 1);
  layout->addWidget(m_frameBox);
  layout->addWidget(m_timeBox);
  layout->addWidget(m_lengthLabel);
  layout->addWidget(m_speedBox);
  layout->addWidget(m_loopBox);

  // Controls → clock.
  connect(m_playButton, &QPushButton::clicked, this,
          [this] { m_playback->isPlaying() ? m_playback->pause() : m_playback->play(); });
  connect(m_slider, &QSlider::valueChanged, this, [this](int v) {
    if (v != m_playback->frame()) m_playback->setFrame(v);
  });
  connect(m_frameBox, &QSpinBox::valueChanged, this, [this](int v) {
    if (v != m_playback->frame()) m_playback->setFrame(v);
  });
  connect(m_timeBox, &QDoubleSpinBox::valueChanged, this, [this](double seconds) {
    if (m_playback->frameTime() <= 0.0) return;
    const int frame = int(std::lround(seconds / m_playback->frameTime()));
    if (frame != m_playback->frame()) m_playback->setFrame(frame);
    showFrame(m_playback->frame());  // the time of that frame, not the one typed
  });
  // Enter (or leaving the field) commits; the keys go back to the window's shortcuts.
  for (QAbstractSpinBox* box :
       {static_cast<QAbstractSpinBox*>(m_frameBox), static_cast<QAbstractSpinBox*>(m_timeBox)}) {
    connect(box, &QAbstractSpinBox::editingFinished, box, [box] {
      if (box->hasFocus()) box->clearFocus();
    });
  }
  connect(m_speedBox, &QComboBox::currentIndexChanged, this,
          [this](int i) { m_playback->setSpeed(m_speedBox->itemData(i).toDouble()); });
  connect(m_loopBox, &QCheckBox::toggled, m_playback, &Playback::setLoop);

  // Clock → controls.
  connect(playback, &Playback::playingChanged, this,
          [this](bool playing) { m_playButton->setText(playing ? tr("Pause") : tr("Play")); });
  connect(playback, &Playback::frameCountChanged, this, &TransportBar::showMotion);
  connect(playback, &Playback::rangeChanged, this, &TransportBar::showMotion);
  connect(playback, &Playback::frameChanged, this, &TransportBar::showFrame);
  connect(playback, &Playback::speedChanged, this, &TransportBar::showSpeed);
  connect(playback, &Playback::loopChanged, this, [this](bool loop) {
    if (m_loopBox->isChecked() == loop) return;
    const QSignalBlocker block(m_loopBox);
    m_loopBox->setChecked(loop);
  });
  showMotion();
}

void TransportBar::showMotion() {
  const int frames = m_playback->frameCount();
  const double frameTime = m_playback->frameTime();
  const int last = std::max(0, frames - 1);
  {
    const QSignalBlocker b1(m_slider), b2(m_frameBox), b3(m_timeBox);
    m_slider->setRange(0, last);
    m_frameBox->setRange(0, last);
    m_timeBox->setRange(0.0, last * frameTime);
    m_timeBox->setSingleStep(frameTime);  // ↑ / ↓ in the field: one frame
  }
  for (QWidget* w : {static_cast<QWidget*>(m_slider), static_cast<QWidget*>(m_frameBox),
                     static_cast<QWidget*>(m_timeBox)})
    w->setEnabled(frames > 0);
  QString text = frames > 0
                     ? tr("%n frames · %1 s", nullptr, frames).arg(frames * frameTime, 0, 'f', 3)
                     : tr("no motion");
  const bool range = m_playback->inPoint() || m_playback->outPoint();
  if (range && frames > 0) {
    text += tr(" · range %1–%2").arg(m_playback->rangeStart()).arg(m_playback->rangeEnd());
    m_slider->setRangeMarks(m_playback->rangeStart(), m_playback->rangeEnd());
  } else {
    m_slider->clearRangeMarks();
  }
  m_lengthLabel->setText(text);
  showFrame(m_playback->frame());
}

void TransportBar::showFrame(int frame) {
  const QSignalBlocker b1(m_slider), b2(m_frameBox), b3(m_timeBox);
  m_slider->setValue(frame);
  m_frameBox->setValue(frame);
  m_timeBox->setValue(frame * m_playback->frameTime());
}

bool TransportBar::eventFilter(QObject* watched, QEvent* event) {
  if (event->type() == QEvent::FocusIn) {
    m_playback->pause();
  } else if (event->type() == QEvent::KeyPress &&
             static_cast<QKeyEvent*>(event)->key() == Qt::Key_Escape) {
    showFrame(m_playback->frame());  // drops what was typed
    static_cast<QWidget*>(watched)->clearFocus();
    return true;
  }
  return QWidget::eventFilter(watched, event);
}

void TransportBar::showSpeed(double speed) {
  // A speed that is not in the list (a call, not the box) leaves the box as it was.
  const int i = m_speedBox->findData(speed);
  if (i < 0 || i == m_speedBox->currentIndex()) return;
  const QSignalBlocker block(m_speedBox);
  m_speedBox->setCurrentIndex(i);
}

}  // namespace motionmap::studio
