#pragma once
// The playback controls under the views: Play/Pause, the frame slider (the in/out range drawn on
// it), the current frame and time (both editable), the motion's length, the speed and Loop, all
// bound to a Playback both ways (a control changes the clock; the clock, whoever moved it,
// updates the controls). Only the two number fields take the keyboard focus (by a click, to type
// in them); Enter or Esc hands the keys back to the window, so Space and the arrows stay its
// playback shortcuts everywhere else.
#include <QSlider>
#include <QWidget>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSpinBox;

namespace motionmap::studio {

class Playback;

/// A frame slider that draws the in/out range: a band under the groove from the in point to the
/// out point, with a mark at each end.
class RangeSlider : public QSlider {
  Q_OBJECT
 public:
  explicit RangeSlider(QWidget* parent = nullptr);
  /// The range drawn (frames, inclusive); none: nothing drawn.
  void setRangeMarks(int first, int last);
  void clearRangeMarks();
  /// Where the band is drawn (widget coordinates); empty without a range.
  QRect bandRect() const;
  /// The x of frame `value`'s handle centre.
  int xOfValue(int value) const;
  /// The band's colour.
  static QColor bandColor();

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  int m_first = -1;
  int m_last = -1;
};

class TransportBar : public QWidget {
  Q_OBJECT
 public:
  /// Controls for `playback`, which must outlive the bar.
  explicit TransportBar(Playback* playback, QWidget* parent = nullptr);

  QPushButton* playButton() const { return m_playButton; }
  RangeSlider* slider() const { return m_slider; }
  /// The current frame (0 = the first, as the slider and `--frame`).
  QSpinBox* frameBox() const { return m_frameBox; }
  /// The current time in seconds (frame × frame time); a time typed goes to the nearest frame.
  QDoubleSpinBox* timeBox() const { return m_timeBox; }
  /// The length (frames and seconds) and the in/out range when one is set.
  QLabel* lengthLabel() const { return m_lengthLabel; }
  QComboBox* speedBox() const { return m_speedBox; }
  QCheckBox* loopBox() const { return m_loopBox; }

 protected:
  /// The number fields: focus pauses playback (typing while the frame runs would be lost), Esc
  /// puts the current frame back and leaves the field.
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void showSpeed(double speed);
  /// The frame count or the range changed: ranges of the fields, the length text, the band.
  void showMotion();
  /// The current frame in the slider and both fields, without signalling back.
  void showFrame(int frame);

  Playback* m_playback;
  QPushButton* m_playButton = nullptr;
  RangeSlider* m_slider = nullptr;
  QSpinBox* m_frameBox = nullptr;
  QDoubleSpinBox* m_timeBox = nullptr;
  QLabel* m_lengthLabel = nullptr;
  QComboBox* m_speedBox = nullptr;
  QCheckBox* m_loopBox = nullptr;
};

}  // namespace motionmap::studio
