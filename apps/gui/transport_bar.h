#pragma once
// The playback controls under the views: Play/Pause, the frame slider, the speed and Loop, all
// bound to a Playback both ways (a control changes the clock; the clock, whoever moved it,
// updates the controls). None takes the keyboard focus, so Space and the arrows stay the
// window's.
#include <QWidget>

class QCheckBox;
class QComboBox;
class QPushButton;
class QSlider;

namespace motionmap::studio {

class Playback;

class TransportBar : public QWidget {
  Q_OBJECT
 public:
  /// Controls for `playback`, which must outlive the bar.
  explicit TransportBar(Playback* playback, QWidget* parent = nullptr);

  QPushButton* playButton() const { return m_playButton; }
  QSlider* slider() const { return m_slider; }
  QComboBox* speedBox() const { return m_speedBox; }
  QCheckBox* loopBox() const { return m_loopBox; }

 private:
  void showSpeed(double speed);

  Playback* m_playback;
  QPushButton* m_playButton = nullptr;
  QSlider* m_slider = nullptr;
  QComboBox* m_speedBox = nullptr;
  QCheckBox* m_loopBox = nullptr;
};

}  // namespace motionmap::studio
