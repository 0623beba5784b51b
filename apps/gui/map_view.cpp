#include "map_view.h"

#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>

namespace motionmap::studio {

MapView::MapView(QWidget* parent) : QWidget(parent) {
  setMouseTracking(true);
  setMinimumSize(200, 200);
  m_hint = tr("Open a clip (File → Open, or drop a .bvh/.amc here)");
}

void MapView::setMap(const Eigen::MatrixXd& coords, const std::vector<int>& segmentStarts,
                     const render::MapPlotOptions& options) {
  m_coords = coords.leftCols(std::min<Eigen::Index>(2, coords.cols()));
  m_segmentStarts = segmentStarts;
  m_options = options;
  m_cache = QPixmap();
  update();
}

void MapView::clearMap(const QString& hint) {
  m_coords.resize(0, 2);
  m_segmentStarts.clear();
  m_pointer.reset();
  if (!hint.isEmpty()) m_hint = hint;
  m_cache = QPixmap();
  update();
}

void MapView::setPointer(const std::optional<Eigen::Vector2d>& point) {
  m_pointer = point;
  update();
}

void MapView::setHoverText(const QString& text) {
  if (text == m_hoverText) return;
  m_hoverText = text;
  update();
}

QPointF MapView::toWidget(const Eigen::Vector2d& point) const {
  return render::map_transform(m_coords, QRectF(rect()), m_options).map(QPointF(point.x(), point.y()));
}

Eigen::Vector2d MapView::toMap(const QPointF& pixel) const {
  bool invertible = false;
  const QTransform inverse = render::map_transform(m_coords, QRectF(rect()), m_options).inverted(&invertible);
  const QPointF p = invertible ? inverse.map(pixel) : QPointF();
  return {p.x(), p.y()};
}

void MapView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  if (!hasMap()) {
    painter.fillRect(rect(), Qt::white);
    painter.drawText(rect(), Qt::AlignCenter | Qt::TextWordWrap, m_hint);
    return;
  }
  // The trajectory is painted once per size/map; a frame only blits it and draws the pointer.
  const qreal dpr = devicePixelRatioF();
  if (m_cache.isNull() || m_cache.size() != size() * dpr) {
    m_cache = QPixmap(size() * dpr);
    m_cache.setDevicePixelRatio(dpr);
    QPainter cachePainter(&m_cache);
    cachePainter.setRenderHint(QPainter::Antialiasing);
    render::paint_map(cachePainter, QRectF(rect()), m_coords, m_segmentStarts, m_options);
  }
  painter.drawPixmap(0, 0, m_cache);
  painter.setRenderHint(QPainter::Antialiasing);
  if (m_sketch.points.size() >= 2) {
    QPainterPath path(toWidget(m_sketch.points.front()));
    for (const auto& p : m_sketch.points) path.lineTo(toWidget(p));
    painter.setPen(QPen(Qt::black, 2, Qt::DashLine));
    painter.drawPath(path);
  }
  if (m_pointer) {
    painter.setPen(QPen(Qt::black, 2));
    painter.setBrush(Qt::white);
    painter.drawEllipse(toWidget(*m_pointer), 7, 7);
  }
  if (!m_hoverText.isEmpty()) {
    painter.setPen(Qt::black);
    painter.drawText(QRectF(rect()).adjusted(8, 4, -8, -4), Qt::AlignTop | Qt::AlignRight, m_hoverText);
  }
}

void MapView::resizeEvent(QResizeEvent*) { m_cache = QPixmap(); }

void MapView::addSketchPoint(const QPointF& pixel) {
  // Times must increase strictly: events within one clock tick are merged into the last point.
  const double t = double(m_sketchClock.nsecsElapsed()) * 1e-9;
  if (!m_sketch.times.empty() && t <= m_sketch.times.back()) {
    m_sketch.points.back() = toMap(pixel);
    return;
  }
  m_sketch.points.push_back(toMap(pixel));
  m_sketch.times.push_back(t);
}

void MapView::mousePressEvent(QMouseEvent* event) {
  if (!hasMap() || event->button() != Qt::LeftButton) return;
  m_pressPixel = event->position();
  if (event->modifiers() & Qt::ShiftModifier) {
    m_gesture = Gesture::Sketch;
    m_sketch = {};
    m_sketchClock.start();
    addSketchPoint(event->position());
  } else {
    m_gesture = Gesture::Press;
  }
}

void MapView::mouseMoveEvent(QMouseEvent* event) {
  if (!hasMap()) return;
  const QPointF pixel = event->position();
  switch (m_gesture) {
    case Gesture::Sketch:
      addSketchPoint(pixel);
      update();
      break;
    case Gesture::Press:
      if ((pixel - m_pressPixel).manhattanLength() < 3) break;
      m_gesture = Gesture::Drag;
      [[fallthrough]];
    case Gesture::Drag:
      emit dragged(toMap(pixel));
      break;
    case Gesture::None:
      emit hovered(toMap(pixel), pixel);
      break;
  }
}

void MapView::mouseReleaseEvent(QMouseEvent* event) {
  if (event->button() != Qt::LeftButton) return;
  const Gesture gesture = m_gesture;
  m_gesture = Gesture::None;
  if (gesture == Gesture::Sketch) {
    addSketchPoint(event->position());
    const synth::MapPath path = m_sketch;
    m_sketch = {};
    update();
    emit sketchFinished(path);
  } else if (gesture == Gesture::Press) {
    emit clicked(toMap(event->position()), event->position());
  } else if (gesture == Gesture::Drag) {
    emit dragFinished();
  }
}

void MapView::leaveEvent(QEvent*) { setHoverText({}); }

}  // namespace motionmap::studio
