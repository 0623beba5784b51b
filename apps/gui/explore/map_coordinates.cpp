#include "explore/map_coordinates.h"

#include <algorithm>
#include <cmath>

#include "map/map_view.h"

namespace motionmap::studio {

MapCoordinates::MapCoordinates(MapView* view, QWidget* parent) : QLabel(parent), m_view(view) {
  setToolTip(
      tr("The map coordinates under the mouse (x, y), as `motionmap map` writes them and "
         "`motionmap synth --path` reads them"));
  setMinimumWidth(
      fontMetrics().horizontalAdvance(QStringLiteral("map x -000.00000  y -000.00000")));
  connect(view, &MapView::hovered, this,
          [this](const Eigen::Vector2d& point, const QPointF&) { show(point); });
  connect(view, &MapView::dragged, this, &MapCoordinates::show);
  connect(view, &MapView::left, this, &QLabel::clear);
}

int MapCoordinates::decimalsFor(double pixel) {
  if (!(pixel > 0.0) || !std::isfinite(pixel)) return 3;
  return std::clamp(int(std::ceil(-std::log10(pixel))), 0, 9);
}

QString MapCoordinates::format(const Eigen::Vector2d& point, int decimals) {
  // ASCII digits and minus: the text can be copied into a CSV as it is.
  auto number = [decimals](double v) { return QString::number(v, 'f', decimals); };
  return tr("map x %1  y %2").arg(number(point.x()), number(point.y()));
}

void MapCoordinates::show(const Eigen::Vector2d& point) {
  if (!m_view->hasMap()) return clear();
  const double pixel = m_view->viewExtent().width() / std::max(1.0, m_view->plotRect().width());
  setText(format(point, decimalsFor(pixel)));
}

}  // namespace motionmap::studio
