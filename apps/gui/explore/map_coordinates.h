#pragma once
// The map coordinates under the mouse, in the status bar ("map x 1.234  y −0.567"), so a user can
// read the points of a path to write as a sketch CSV (`motionmap synth --path`). The digits
// follow the zoom: enough that neighbouring pixels read differently, no more.
#include <Eigen/Core>
#include <QLabel>

namespace motionmap::studio {

class MapView;

class MapCoordinates : public QLabel {
  Q_OBJECT
 public:
  /// Follows `view`'s mouse (hover and drags); `view` must outlive this.
  explicit MapCoordinates(MapView* view, QWidget* parent = nullptr);
  /// The text for map point `point` with `decimals` digits after the point.
  static QString format(const Eigen::Vector2d& point, int decimals);
  /// Digits that tell apart points `pixel` map units apart (0 to 9).
  static int decimalsFor(double pixel);

 private:
  void show(const Eigen::Vector2d& point);
  MapView* m_view;
};

}  // namespace motionmap::studio
