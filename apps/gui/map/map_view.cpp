#include "map/map_view.h"

#include <algorithm>
#include <cmath>

#include <QAbstractSpinBox>
#include <QApplication>
#include <QCursor>
#include <QHelpEvent>
#include <QKeyEvent>
#include <QLineEdit>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QToolTip>
#include <QWheelEvent>

namespace motionmap::studio {

namespace {
/// Longest straight piece (pixels) of a trajectory segment bent by the lens.
constexpr double kLensStepPixels = 3.0;
}  // namespace

MapView::MapView(QWidget* parent) : QWidget(parent) {
  setMouseTracking(true);
  setMinimumSize(200, 200);
  m_hint = tr("Open a clip (File → Open, or drop a .bvh/.amc here)");
  setFocusPolicy(Qt::ClickFocus);  // Home resets a zoomed view while the map has the focus
  setContextMenuPolicy(Qt::PreventContextMenu);  // the right button selects
  qApp->installEventFilter(this);  // Space + drag pans: Space is held back from the window
}

void MapView::setSampleCategories(std::vector<int> categories) {
  m_categories = std::move(categories);
  m_hidden = std::count(m_categories.begin(), m_categories.end(), kHiddenCategory);
  if (m_density) {
    // Only the density's colours change: the picture is composed again from the points binned
    // again and the trajectory layer as it was (a legend click does not stroke it again).
    m_cache = QPixmap();
    m_densityImage = QImage();
  } else {
    invalidate();
  }
  update();
}

bool MapView::categoriesShown() const {
  const Eigen::Index samples = m_density ? m_density->rows() : m_coords.rows();
  return !m_categories.empty() && Eigen::Index(m_categories.size()) == samples;
}

bool MapView::sampleShown(int sample) const {
  if (!categoriesShown()) return sample >= 0;
  return sample >= 0 && std::size_t(sample) < m_categories.size() &&
         m_categories[std::size_t(sample)] != kHiddenCategory;
}

QImage MapView::density(const QTransform& toPixel, const QSize& size) const {
  if (categoriesShown())
    return render::category_density_image(*m_density, m_categories, toPixel, size);
  return render::density_image(*m_density, toPixel, size);
}

void MapView::paintTrajectory(QPainter& painter, const render::MapPlotOptions& options) const {
  if (!categoriesShown()) {
    render::paint_map(painter, QRectF(rect()), m_coords, m_segmentStarts, options);
    return;
  }
  Eigen::MatrixXd drawn = m_coords;
  render::MapPlotOptions by = options;
  if (!(by.extent.width() >= 0.0 && by.extent.height() >= 0.0)) {
    // Framed as the whole map, whichever samples are hidden.
    const QRectF box = render::data_to_unit(m_coords).inverted().mapRect(QRectF(0, 0, 1, 1));
    by.extent = box;
  }
  by.point_category = m_categories;
  for (Eigen::Index i = 0; i < drawn.rows(); ++i) {
    if (m_categories[std::size_t(i)] == kHiddenCategory) {
      drawn.row(i).setConstant(std::nan(""));
      by.point_category[std::size_t(i)] = -1;
    }
  }
  render::paint_map(painter, QRectF(rect()), drawn, m_segmentStarts, by);
}

void MapView::invalidate() {
  m_cache = QPixmap();
  m_overLayer = QImage();
  m_densityImage = QImage();
  m_transformValid = false;
}

void MapView::setDensityMap(std::shared_ptr<const Eigen::MatrixXd> points,
                            const Eigen::MatrixXd& trajectory,
                            const render::MapPlotOptions& options) {
  m_density = std::move(points);
  m_categories.clear();
  m_hidden = 0;
  m_options = options;
  // Framed as the whole map, whichever clip is drawn over it.
  const Eigen::MatrixXd& xy = *m_density;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (Eigen::Index i = 0; i < xy.rows(); ++i) {
    const double x = xy(i, 0), y = xy(i, 1);
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  if (x0 <= x1) m_options.extent = QRectF(QPointF(x0, y0), QPointF(x1, y1));
  m_segmentStarts.clear();
  m_coords = trajectory.leftCols(std::min<Eigen::Index>(2, trajectory.cols()));
  m_zoom = 1.0;
  m_viewCenter.reset();
  m_highlight.resize(0, 2);
  m_comparison.resize(0, 2);
  m_comparisonPoint.reset();
  m_comparisonClip = -1;
  m_selection.resize(0, 2);
  m_selectionOutline.clear();
  m_shadingIndex.reset();  // another map's samples
  m_reachField.reset();
  invalidate();
  update();
  emit mapReplaced();
}

void MapView::setTrajectory(const Eigen::MatrixXd& trajectory) {
  m_coords = trajectory.leftCols(std::min<Eigen::Index>(2, trajectory.cols()));
  m_segmentStarts.clear();
  m_cache = QPixmap();  // the density image and the transform stay
  m_overLayer = QImage();
  m_transformValid = false;
  update();
}

const QImage& MapView::densityImage() const {
  if (!m_density) {
    m_densityImage = QImage();
    return m_densityImage;
  }
  const qreal dpr = devicePixelRatioF();
  const QSize pixels = size() * dpr;
  if (m_densityImage.isNull() || m_densitySize != pixels) {
    ensureTransform();
    m_densityImage = density(m_toWidget * QTransform::fromScale(dpr, dpr), pixels);
    m_densityImage.setDevicePixelRatio(dpr);
    m_densitySize = pixels;
  }
  return m_densityImage;
}

void MapView::setMap(const Eigen::MatrixXd& coords, const std::vector<int>& segmentStarts,
                     const render::MapPlotOptions& options) {
  m_density.reset();
  m_categories.clear();
  m_hidden = 0;
  m_coords = coords.leftCols(std::min<Eigen::Index>(2, coords.cols()));
  m_segmentStarts = segmentStarts;
  m_options = options;
  m_busyText.clear();
  m_zoom = 1.0;  // another map: shown whole
  m_viewCenter.reset();
  m_highlight.resize(0, 2);
  m_comparison.resize(0, 2);
  m_comparisonPoint.reset();
  m_comparisonClip = -1;
  m_selection.resize(0, 2);
  m_selectionOutline.clear();
  m_shadingIndex.reset();  // another map's samples
  m_reachField.reset();
  invalidate();
  update();
  emit mapReplaced();
}

void MapView::clearMap(const QString& hint) {
  m_density.reset();
  m_categories.clear();
  m_hidden = 0;
  m_coords.resize(0, 2);
  m_segmentStarts.clear();
  m_pointer.reset();
  m_busyText.clear();
  m_zoom = 1.0;
  m_viewCenter.reset();
  m_highlight.resize(0, 2);
  m_comparison.resize(0, 2);
  m_comparisonPoint.reset();
  m_comparisonClip = -1;
  m_selection.resize(0, 2);
  m_selectionOutline.clear();
  m_shadingIndex.reset();  // another map's samples
  m_reachField.reset();
  if (!hint.isEmpty()) m_hint = hint;
  invalidate();
  update();
  emit mapReplaced();
}

void MapView::setHighlight(const Eigen::MatrixXd& points) {
  m_highlight = points.leftCols(std::min<Eigen::Index>(2, points.cols()));
  m_cache = QPixmap();
  m_overLayer = QImage();
  update();
}

void MapView::setComparison(const Eigen::MatrixXd& trajectory,
                            const std::optional<Eigen::Vector2d>& point, int clip) {
  m_comparison = trajectory.leftCols(std::min<Eigen::Index>(2, trajectory.cols()));
  m_comparisonPoint = m_comparison.rows() > 0 ? point : std::nullopt;
  const int compared = m_comparison.rows() > 0 ? std::max(clip, -1) : -1;
  if (compared != m_comparisonClip) {
    // Its trajectory and legend swatch change colour: the cached picture is painted again (a
    // frame of the comparison only moves the ring).
    m_comparisonClip = compared;
    m_cache = QPixmap();
    m_overLayer = QImage();
  }
  update();
}

QColor MapView::clipColor(int clip, double t) const {
  return render::drawn_clip_color(shownOptions(), clip, t);
}

void MapView::paintComparison(QPainter& painter) const {
  QPolygonF line;
  for (Eigen::Index i = 0; i < m_comparison.rows(); ++i) {
    const Eigen::Vector2d p(m_comparison(i, 0), m_comparison(i, 1));
    if (p.allFinite()) line << toWidget(p);
  }
  painter.setPen(QPen(comparisonColor(), 2.5, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
  painter.setBrush(Qt::NoBrush);
  painter.drawPolyline(line);
  if (m_comparisonPoint) {
    painter.setPen(QPen(comparisonColor(), 3));
    painter.setBrush(Qt::white);
    painter.drawEllipse(toWidget(*m_comparisonPoint), 7, 7);
  }
}

void MapView::setSelection(const Eigen::MatrixXd& points, const QPolygonF& outline) {
  m_selection = points.leftCols(std::min<Eigen::Index>(2, points.cols()));
  m_selectionOutline = outline;
  m_cache = QPixmap();
  m_overLayer = QImage();
  update();
}

QPolygonF MapView::selectionPixels() const {
  if (m_gesture == Gesture::Select) return m_selectDrawn;
  QPolygonF pixels;
  for (const QPointF& p : m_selectionOutline) pixels << toWidget(Eigen::Vector2d(p.x(), p.y()));
  return pixels;
}

void MapView::paintMarks(QPainter& painter, const Eigen::MatrixXd& points,
                         const QColor& color) const {
  if (points.rows() == 0) return;
  ensureTransform();
  const qreal dpr = devicePixelRatioF();
  const QSize pixels = size() * dpr;
  QImage marks(pixels, QImage::Format_ARGB32_Premultiplied);
  marks.fill(Qt::transparent);
  const QTransform toPixel = m_toWidget * QTransform::fromScale(dpr, dpr);
  const QRgb ink = color.rgba();
  const int w = pixels.width(), h = pixels.height();
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const QPointF p = toPixel.map(QPointF(points(i, 0), points(i, 1)));
    if (!(p.x() >= 0.0 && p.x() < w && p.y() >= 0.0 && p.y() < h)) continue;  // or NaN
    const int x = int(p.x()), y = int(p.y());
    for (int yy = std::max(0, y - 1); yy <= std::min(h - 1, y + 1); ++yy) {
      auto* line = reinterpret_cast<QRgb*>(marks.scanLine(yy));
      for (int xx = std::max(0, x - 1); xx <= std::min(w - 1, x + 1); ++xx) line[xx] = ink;
    }
  }
  marks.setDevicePixelRatio(dpr);
  painter.save();
  painter.setClipRect(plotRect());
  painter.drawImage(QPointF(0, 0), marks);
  painter.restore();
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

void MapView::setTakePaths(std::vector<TakePath> paths) {
  m_takes = std::move(paths);
  if (m_gesture == Gesture::Control) m_gesture = Gesture::None;  // its take changed under it
  update();
}

int MapView::controlPointAt(const QPointF& pixel) const {
  for (const TakePath& take : m_takes) {
    if (!take.current) continue;
    int best = -1;
    double bestDistance = kControlPickPixels;
    for (std::size_t c = 0; c < take.controls.size(); ++c) {
      const double d = QLineF(toWidget(take.points[std::size_t(take.controls[c])]), pixel).length();
      if (d <= bestDistance) {
        bestDistance = d;
        best = int(c);
      }
    }
    return best;
  }
  return -1;
}

void MapView::paintTakes(QPainter& painter) const {
  const QColor color = takeColor();
  for (const TakePath& take : m_takes) {
    const bool dragging = take.current && m_gesture == Gesture::Control;
    const std::vector<Eigen::Vector2d>& points = dragging ? m_controlPreview.points : take.points;
    if (points.size() < 2) continue;
    QPainterPath path(toWidget(points.front()));
    for (const auto& p : points) path.lineTo(toWidget(p));
    QColor line = color;
    if (!take.current) line.setAlpha(110);  // the other takes of this map, behind
    painter.setPen(
        QPen(line, take.current ? 2.5 : 1.5, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    painter.setBrush(Qt::NoBrush);
    painter.drawPath(path);
    const QPointF end = toWidget(points.back());
    painter.setPen(take.current ? QColor(120, 60, 0) : QColor(120, 60, 0, 140));
    painter.drawText(end + QPointF(6, -6), take.name);
    for (std::size_t c = 0; c < take.controls.size(); ++c) {
      const int i = take.controls[c];
      if (std::size_t(i) >= points.size()) continue;
      if (take.keyed) {
        paintKey(painter, toWidget(points[std::size_t(i)]), int(c) + 1, false);
        continue;
      }
      painter.setPen(QPen(QColor(120, 60, 0), 1.5));
      painter.setBrush(Qt::white);
      painter.drawRect(QRectF(toWidget(points[std::size_t(i)]) - QPointF(4, 4), QSizeF(8, 8)));
    }
  }
  for (std::size_t k = 0; k < m_pendingKeys.size(); ++k)
    paintKey(painter, toWidget(m_pendingKeys[k]), int(k) + 1, true);
}

void MapView::paintKey(QPainter& painter, const QPointF& pixel, int number, bool pending) {
  painter.save();
  QFont font = painter.font();
  font.setPixelSize(11);
  font.setBold(true);
  painter.setFont(font);
  painter.setPen(QPen(QColor(120, 60, 0), 1.5, pending ? Qt::DashLine : Qt::SolidLine));
  painter.setBrush(pending ? QColor(255, 255, 255, 220) : takeColor().lighter(150));
  const QRectF disc(pixel - QPointF(8, 8), QSizeF(16, 16));
  painter.drawEllipse(disc);
  painter.setPen(QColor(60, 30, 0));
  painter.drawText(disc, Qt::AlignCenter, QString::number(number));
  painter.restore();
}

void MapView::setPendingKeys(std::vector<Eigen::Vector2d> keys) {
  m_pendingKeys = std::move(keys);
  update();
}

void MapView::setSketchMode(bool on) {
  m_sketchMode = on;
}

void MapView::setShadingReach(double reach, std::shared_ptr<const synth::PointIndex> index,
                              std::shared_ptr<const MapGp> gplvm) {
  m_shadingReach = std::isfinite(reach) && reach > 0.0 ? reach : 0.0;
  m_shadingIndex = std::move(index);
  m_shadingGplvm = std::move(gplvm);
  m_reachField.reset();
  m_cache = QPixmap();
  m_overLayer = QImage();
  update();
}

void MapView::setShadingVisible(bool on) {
  m_shadingVisible = on;
  m_cache = QPixmap();
  m_overLayer = QImage();
  update();
}

void MapView::setLensEnabled(bool on) {
  m_lensEnabled = on;
  if (on && !m_lensVisible) {
    // Until the mouse moves: where it is if over the view, else the middle.
    const QPoint mouse = mapFromGlobal(QCursor::pos());
    m_lensCenter = rect().contains(mouse) ? QPointF(mouse) : QRectF(rect()).center();
    m_lensVisible = true;
  }
  update();
}

void MapView::setLensCenter(const QPointF& center) {
  m_lensCenter = center;
  m_lensVisible = true;
  update();
}

void MapView::setLensPower(double power) {
  m_lensPower = std::clamp(std::isfinite(power) ? power : 3.0, 0.5, 30.0);
  update();
}

double MapView::lensRadius() const {
  return std::max(40.0, 0.2 * std::min(width(), height()));
}

QPointF MapView::lens(const QPointF& pixel) const {
  if (!lensShown()) return pixel;
  const QPointF v = pixel - m_lensCenter;
  const double R = lensRadius(), r = std::hypot(v.x(), v.y());
  if (r >= R || r == 0.0) return pixel;
  const double x = r / R, d = m_lensPower;
  const double g = (d + 1.0) * x / (d * x + 1.0);
  return m_lensCenter + v * (g / x);
}

QPointF MapView::unlens(const QPointF& pixel) const {
  if (!lensShown()) return pixel;
  const QPointF v = pixel - m_lensCenter;
  const double R = lensRadius(), r = std::hypot(v.x(), v.y());
  if (r >= R || r == 0.0) return pixel;
  const double y = r / R, d = m_lensPower;
  const double x = y / (d + 1.0 - d * y);
  return m_lensCenter + v * (x / y);
}

void MapView::ensureTransform() const {
  if (m_transformValid && m_transformSize == size()) return;
  const QRectF area(rect());
  m_toWidget = render::map_transform(m_coords, area, viewOptions());
  bool invertible = false;
  m_toMap = m_toWidget.inverted(&invertible);
  if (!invertible) m_toMap = QTransform(0, 0, 0, 0, 0, 0);  // every pixel → (0, 0)
  m_pixelSegments.clear();
  if (m_coords.rows() > 0) {
    // The segments' unit coordinates (of the trajectory's own extent) go back to data, then
    // through the panel's transform: the whole map's (a density map, a backdrop) or the zoomed
    // view's.
    const QTransform unit = render::data_to_unit(m_coords).inverted() * m_toWidget;
    m_pixelSegments = render::trajectory_segments(m_coords, m_segmentStarts);
    for (auto& s : m_pixelSegments) {
      s.from = unit.map(s.from);
      s.to = unit.map(s.to);
    }
  }
  m_transformSize = size();
  m_transformValid = true;
}

QPointF MapView::toWidget(const Eigen::Vector2d& point) const {
  ensureTransform();
  return lens(m_toWidget.map(QPointF(point.x(), point.y())));
}

Eigen::Vector2d MapView::toMap(const QPointF& pixel) const {
  ensureTransform();
  const QPointF p = m_toMap.map(unlens(pixel));
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
    const render::MapPlotOptions options = viewOptions();
    const bool shading = m_shadingVisible && shadingAvailable();
    if (m_density) {
      // Background, the saved map's density (inside the frame), the shading, then the current
      // clip's trajectory over it.
      cachePainter.fillRect(
          rect(), m_options.background.isValid() ? m_options.background : QColor(Qt::white));
      cachePainter.save();
      cachePainter.setClipRect(plotRect());
      cachePainter.drawImage(QPointF(0, 0), densityImage());
      cachePainter.restore();
      if (shading) paintShading(cachePainter);
      // The marks and the trajectory over it, a layer of their own: kept while only the
      // density's colours change.
      if (m_overLayer.isNull() || m_overLayer.size() != m_cache.size()) {
        m_overLayer = QImage(m_cache.size(), QImage::Format_ARGB32_Premultiplied);
        m_overLayer.setDevicePixelRatio(dpr);
        m_overLayer.fill(Qt::transparent);
        QPainter layer(&m_overLayer);
        layer.setRenderHint(QPainter::Antialiasing);
        paintMarks(layer, m_highlight, highlightColor());
        paintMarks(layer, m_selection, selectionColor());
        render::MapPlotOptions over = options;
        over.background = QColor();
        if (m_coords.rows() > 0)
          render::paint_map(layer, QRectF(rect()), m_coords, m_segmentStarts, over);
      }
      cachePainter.drawImage(QPointF(0, 0), m_overLayer);
    } else {
      paintTrajectory(cachePainter, options);
      paintMarks(cachePainter, m_highlight, highlightColor());
      paintMarks(cachePainter, m_selection, selectionColor());
      if (shading) {
        paintShading(cachePainter);
        // The trajectory stays on top, in its own colours (clipped: the title, colour bar and
        // notes are not drawn twice).
        cachePainter.save();
        cachePainter.setClipRect(plotRect());
        render::MapPlotOptions over = options;
        over.background = QColor();
        paintTrajectory(cachePainter, over);
        cachePainter.restore();
      }
    }
    if (shading) paintShadingKey(cachePainter);
  }
  painter.drawPixmap(0, 0, m_cache);
  painter.setRenderHint(QPainter::Antialiasing);
  if (!m_busyText.isEmpty()) paintBusy(painter);
  painter.save();
  if (isZoomed()) painter.setClipRect(plotRect());  // what lies outside the view stays out
  if (lensShown()) paintLens(painter);
  paintTakes(painter);
  if (const QPolygonF outline = selectionPixels(); outline.size() >= 2) {
    painter.setPen(QPen(QColor(0, 120, 60), 1.5, Qt::DashLine));
    painter.setBrush(QColor(0, 215, 110, 30));
    painter.drawPolygon(outline);
  }
  if (m_sketch.points.size() >= 2) {
    QPainterPath path(toWidget(m_sketch.points.front()));
    for (const auto& p : m_sketch.points) path.lineTo(toWidget(p));
    painter.setPen(QPen(Qt::black, 2, Qt::DashLine));
    painter.setBrush(Qt::NoBrush);
    painter.drawPath(path);
  }
  if (m_comparison.rows() > 0) paintComparison(painter);
  if (m_pointer) {
    painter.setPen(QPen(Qt::black, 2));
    painter.setBrush(Qt::white);
    painter.drawEllipse(toWidget(*m_pointer), 7, 7);
  }
  painter.restore();
  if (!m_hoverText.isEmpty()) {
    painter.setPen(Qt::black);
    painter.drawText(QRectF(rect()).adjusted(8, 4, -8, -4), Qt::AlignTop | Qt::AlignRight,
                     m_hoverText);
  }
}

QRectF MapView::plotRect() const {
  // render::layout_panel's frame: the data square plus a margin of 5 % of the frame's side on
  // each side, i.e. 1/18 of the data square's.
  const QRectF data = render::data_area(QRectF(rect()), shownOptions());
  const double margin = data.width() / 18.0;
  return data.adjusted(-margin, -margin, margin, margin);
}

double MapView::shadingRadius() const {
  if (!shadingAvailable()) return 0.0;
  ensureTransform();
  return QLineF(m_toWidget.map(QPointF(0.0, 0.0)), m_toWidget.map(QPointF(m_shadingReach, 0.0)))
      .length();
}

namespace {
/// The shading's colour, drawn at kShadingOpacity.
const QColor kShadingGreen(30, 170, 70);
/// Most cells along the longer side of a GP-LVM map's shading grid.
constexpr int kGplvmShadingCells = 256;
constexpr double kShadingOpacity = 0.3;
}  // namespace

void MapView::ensureReachField() const {
  if (m_reachField) return;
  const Eigen::MatrixXd& samples = m_density ? *m_density : m_coords;
  if (m_shadingGplvm) {
    // The GP's variance on a grid over the samples grown by the cutoff (beyond it the variance
    // is the prior's, outside): cells at most ℓ/8 and kGplvmShadingCells a side, sure more than
    // 25 % from the threshold, the others' pixels decided by the grid's bilinear interpolation.
    const MapGp& gp = *m_shadingGplvm;
    const double pad = embed::kGplvmCutoff * gp.lengthscale();
    const Eigen::Vector2d lo = samples.leftCols(2).colwise().minCoeff().transpose().array() - pad;
    const Eigen::Vector2d hi = samples.leftCols(2).colwise().maxCoeff().transpose().array() + pad;
    const int cells = int(std::clamp((hi - lo).maxCoeff() / (0.125 * gp.lengthscale()), 16.0,
                                     double(kGplvmShadingCells)));
    m_reachField = std::make_shared<const render::ReachField>(render::ReachField::level_set(
        lo, hi, cells, [&gp](const Eigen::Vector2d& p) { return gp.variance(p); }, gp.threshold(),
        0.25));
    return;
  }
  if (!m_shadingIndex) m_shadingIndex = std::make_shared<const synth::PointIndex>(samples);
  m_reachField = std::make_shared<const render::ReachField>(samples, m_shadingReach);
}

bool MapView::withinReach(const Eigen::Vector2d& p) const {
  // A GP-LVM map: the field's grid of the GP's variance, interpolated (exact variances per
  // pixel would cost a zoomed view seconds).
  if (m_shadingGplvm) return m_reachField->level(p.x(), p.y()) <= m_shadingGplvm->threshold();
  const synth::Neighbor nearest = m_shadingIndex->nearest(p);
  return nearest.sample >= 0 && nearest.distance <= m_shadingReach;
}

QImage MapView::shadingLayer() const {
  if (!shadingAvailable()) return {};
  ensureTransform();
  ensureReachField();
  const qreal dpr = devicePixelRatioF();
  const QSize pixels = size() * dpr;
  const QTransform toMap =
      dpr == 1.0 ? m_toMap : QTransform::fromScale(1.0 / dpr, 1.0 / dpr) * m_toMap;
  // The pixels whose centres lie inside the plot's frame: never over the title, the colour bar
  // or the notes.
  const QRectF plot(plotRect().topLeft() * dpr, plotRect().size() * dpr);
  const QRect clip(
      QPoint(int(std::ceil(plot.left() - 0.5)), int(std::ceil(plot.top() - 0.5))),
      QPoint(int(std::floor(plot.right() - 0.5)), int(std::floor(plot.bottom() - 0.5))));
  QImage layer = render::reach_image(
      *m_reachField, toMap, pixels, kShadingGreen,
      [this](const Eigen::Vector2d& p) { return withinReach(p); }, clip);
  layer.setDevicePixelRatio(dpr);
  return layer;
}

void MapView::paintShading(QPainter& painter) const {
  const QImage layer = shadingLayer();
  if (layer.isNull()) return;
  painter.save();
  painter.setOpacity(kShadingOpacity);
  painter.drawImage(QPointF(0, 0), layer);
  painter.restore();
}

void MapView::paintLensShading(QPainter& painter, const QRectF& bounds) const {
  ensureReachField();
  const QRectF plot = plotRect();
  const QPointF centre = m_lensCenter;
  const double R = lensRadius();
  // On whole pixels (the lens's centre follows the mouse to fractions of one), each decided at
  // its centre.
  const QRect box = bounds.toAlignedRect();
  QImage lensed(box.size(), QImage::Format_ARGB32_Premultiplied);
  lensed.fill(Qt::transparent);
  const QRgb ink = kShadingGreen.rgba();
  for (int y = 0; y < lensed.height(); ++y) {
    auto* line = reinterpret_cast<QRgb*>(lensed.scanLine(y));
    for (int x = 0; x < lensed.width(); ++x) {
      const QPointF shown = QPointF(box.topLeft()) + QPointF(x + 0.5, y + 0.5);
      if (!plot.contains(shown) || QLineF(shown, centre).length() > R) continue;
      const QPointF at = m_toMap.map(unlens(shown));
      const auto side = m_reachField->side(at.x(), at.y());
      if (side == render::ReachField::Side::Inside ||
          (side == render::ReachField::Side::Unsure && withinReach({at.x(), at.y()})))
        line[x] = ink;
    }
  }
  painter.save();
  painter.setOpacity(kShadingOpacity);
  painter.drawImage(box.topLeft(), lensed);
  painter.restore();
}

void MapView::paintShadingKey(QPainter& painter) const {
  const QRectF plot = plotRect();
  painter.save();
  QFont font = painter.font();
  font.setPixelSize(int(std::clamp(plot.height() / 34.0, 8.0, 12.0)));
  painter.setFont(font);
  const QFontMetricsF fm(font);
  const QString text = m_shadingGplvm ? tr("the GP's pose is sure (outside: moved to the edge)")
                                      : tr("a blend of nearby frames (outside: moved to the edge)");
  const double pad = 4.0, swatch = fm.height();
  const double textWidth = std::min(fm.horizontalAdvance(text), plot.width() - swatch - 5 * pad);
  const QRectF key(plot.left() + pad, plot.bottom() - pad - swatch - 2 * pad,
                   swatch + 3 * pad + textWidth, swatch + 2 * pad);
  painter.setPen(QPen(QColor(150, 150, 150), 1));
  painter.setBrush(QColor(255, 255, 255, 220));
  painter.drawRect(key);
  QColor fill = kShadingGreen;
  fill.setAlphaF(kShadingOpacity);
  painter.setPen(Qt::NoPen);
  painter.setBrush(fill);
  painter.drawRect(QRectF(key.left() + pad, key.top() + pad, swatch, swatch));
  painter.setPen(QColor(40, 40, 40));
  painter.drawText(QRectF(key.left() + 2 * pad + swatch, key.top() + pad, textWidth, swatch),
                   Qt::AlignVCenter | Qt::AlignLeft,
                   fm.elidedText(text, Qt::ElideRight, textWidth));
  painter.restore();
}

void MapView::setBusyText(const QString& text) {
  if (text == m_busyText) return;
  m_busyText = text;
  update();
}

void MapView::paintBusy(QPainter& painter) const {
  painter.save();
  painter.fillRect(rect(), QColor(255, 255, 255, 150));  // the map before, greyed
  const QRectF plot = plotRect();
  const QFontMetricsF fm(painter.font());
  const double width = std::min(fm.horizontalAdvance(m_busyText) + 24.0, plot.width() - 8.0);
  const QRectF box(plot.center().x() - width / 2, plot.top() + 8, width, fm.height() + 12);
  painter.setPen(QPen(QColor(150, 150, 150), 1));
  painter.setBrush(QColor(255, 255, 255, 235));
  painter.drawRoundedRect(box, 4, 4);
  painter.setPen(QColor(40, 40, 40));
  painter.drawText(box, Qt::AlignCenter,
                   fm.elidedText(m_busyText, Qt::ElideRight, box.width() - 12));
  painter.restore();
}

QString MapView::noteToolTip(const QPointF& pixel) const {
  if (!hasMap() || m_options.notes.isEmpty()) return {};
  if (pixel.y() <= plotRect().bottom()) return {};
  return m_options.notes.join(QLatin1Char('\n'));
}

bool MapView::event(QEvent* event) {
  if (event->type() == QEvent::ShortcutOverride) {
    // Home here resets a zoomed view; the window's Home action (first frame) must not take it.
    auto* key = static_cast<QKeyEvent*>(event);
    if (key->key() == Qt::Key_Home && key->modifiers() == Qt::NoModifier && isZoomed()) {
      event->accept();
      return true;
    }
  }
  if (event->type() == QEvent::ToolTip) {
    // The notes under the plot are elided to the panel's width: hovering them shows them whole.
    auto* help = static_cast<QHelpEvent*>(event);
    const QString text = noteToolTip(help->pos());
    if (text.isEmpty()) {
      QToolTip::hideText();
      event->ignore();
    } else {
      QToolTip::showText(help->globalPos(), text, this);
    }
    return true;
  }
  return QWidget::event(event);
}

void MapView::paintLens(QPainter& painter) const {
  ensureTransform();
  const double R = lensRadius();
  const QRectF bounds(m_lensCenter - QPointF(R, R), QSizeF(2 * R, 2 * R));
  painter.save();
  QPainterPath circle;
  circle.addEllipse(bounds);
  painter.setClipPath(circle);
  painter.fillPath(circle,
                   m_options.background.isValid() ? m_options.background : QColor(Qt::white));
  if (m_density) {
    // The density under the lens: binned at the lens's magnification over its box (so the centre
    // is as sharp as the plot), each pixel of the disc read where the lens takes it from.
    // (at most 2048 px a side: a strong lens stays cheap, a little softer at its very centre)
    const double magnification =
        std::min(m_lensPower + 1.0, 2048.0 / std::max(1.0, bounds.width()));
    const QSize sharp = (bounds.size() * magnification).toSize();
    const QTransform toSharp = m_toWidget *
                               QTransform::fromTranslate(-bounds.left(), -bounds.top()) *
                               QTransform::fromScale(magnification, magnification);
    const QImage source = density(toSharp, sharp);
    QImage lensed(bounds.size().toSize(), QImage::Format_ARGB32_Premultiplied);
    lensed.fill(Qt::transparent);
    for (int y = 0; y < lensed.height(); ++y) {
      auto* line = reinterpret_cast<QRgb*>(lensed.scanLine(y));
      for (int x = 0; x < lensed.width(); ++x) {
        const QPointF shown = bounds.topLeft() + QPointF(x + 0.5, y + 0.5);
        const QPointF from = (unlens(shown) - bounds.topLeft()) * magnification;
        const int sx = int(from.x()), sy = int(from.y());
        if (sx >= 0 && sy >= 0 && sx < source.width() && sy < source.height())
          line[x] = source.pixel(sx, sy);
      }
    }
    painter.drawImage(bounds.topLeft(), lensed);
  }
  if (m_shadingVisible && shadingAvailable()) paintLensShading(painter, bounds);
  // The segments near the lens, bent: only those whose box meets the lens's box are looked at.
  const double width = m_options.line_width * std::sqrt(m_lensPower + 1.0);
  const render::MapPlotOptions shown = shownOptions();  // the clips' colours, as drawn
  for (const auto& s : m_pixelSegments) {
    if (std::max(s.from.x(), s.to.x()) < bounds.left() ||
        std::min(s.from.x(), s.to.x()) > bounds.right() ||
        std::max(s.from.y(), s.to.y()) < bounds.top() ||
        std::min(s.from.y(), s.to.y()) > bounds.bottom()) {
      continue;
    }
    const bool byCategory = categoriesShown();
    if (byCategory && (!sampleShown(s.sample) || !sampleShown(s.sample + 1))) continue;
    const int pieces =
        std::clamp(int(std::ceil(QLineF(s.from, s.to).length() / kLensStepPixels)), 1, 200);
    QPainterPath path(lens(s.from));
    for (int i = 1; i <= pieces; ++i)
      path.lineTo(lens(s.from + (s.to - s.from) * (double(i) / pieces)));
    const QColor color = byCategory ? render::category_color(m_categories[std::size_t(s.sample)])
                         : m_options.clip_names.isEmpty()
                             ? s.color
                             : render::drawn_clip_color(shown, s.clip, s.time);
    painter.setPen(QPen(color, width, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    painter.drawPath(path);
  }
  painter.restore();
  painter.setPen(QPen(QColor(90, 90, 90), 1.5));
  painter.setBrush(Qt::NoBrush);
  painter.drawEllipse(bounds);
}

void MapView::resizeEvent(QResizeEvent*) {
  invalidate();
}

QPointF MapView::clampToPlot(const QPointF& pixel) const {
  const QRectF plot = plotRect();
  return {std::clamp(pixel.x(), plot.left(), plot.right()),
          std::clamp(pixel.y(), plot.top(), plot.bottom())};
}

void MapView::addSketchPoint(const QPointF& pixel) {
  const Eigen::Vector2d point = toMap(clampToPlot(pixel));  // the stroke drawn follows the edge
  // Times must increase strictly: events within one clock tick are merged into the last point.
  const double t = double(m_sketchClock.nsecsElapsed()) * 1e-9;
  if (!m_sketch.times.empty() && t <= m_sketch.times.back()) {
    m_sketch.points.back() = point;
    return;
  }
  m_sketch.points.push_back(point);
  m_sketch.times.push_back(t);
}

void MapView::mousePressEvent(QMouseEvent* event) {
  if (!hasMap()) return;
  if (m_gesture == Gesture::None &&
      (event->button() == Qt::MiddleButton || (event->button() == Qt::LeftButton && m_spaceHeld))) {
    m_gesture = Gesture::Pan;
    m_panLast = event->position();
    setCursor(Qt::ClosedHandCursor);
    return;
  }
  if (event->button() == Qt::RightButton && m_gesture == Gesture::None) {
    m_gesture = Gesture::Select;  // a box; with Shift a lasso
    m_selectLasso = event->modifiers() & Qt::ShiftModifier;
    m_pressPixel = event->position();
    m_selectDrawn = QPolygonF() << event->position();
    return;
  }
  if (event->button() != Qt::LeftButton) return;
  m_pressPixel = event->position();
  if (event->modifiers() & Qt::ControlModifier) {
    m_gesture = Gesture::Key;  // a key added or removed on release
    return;
  }
  // A control point of the current take is dragged even in sketch mode (Shift always sketches).
  const int control =
      (event->modifiers() & Qt::ShiftModifier) ? -1 : controlPointAt(event->position());
  if (control >= 0) {
    const TakePath* current = nullptr;
    for (const TakePath& take : m_takes)
      if (take.current) current = &take;
    m_gesture = Gesture::Control;
    m_control = control;
    m_controlPreview = {};
    m_controlPreview.points = current->points;
  } else if ((event->modifiers() & Qt::ShiftModifier) || m_sketchMode) {
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
    case Gesture::Control:
      for (const TakePath& take : m_takes) {
        if (!take.current) continue;
        synth::MapPath original;
        original.points = take.points;
        m_controlPreview =
            deformPath(original, take.controls, m_control, toMap(clampToPlot(pixel)));
      }
      update();
      break;
    case Gesture::Key:
      break;
    case Gesture::Select:
      if (m_selectLasso) {
        m_selectDrawn << pixel;
      } else {
        m_selectDrawn = QPolygonF(QRectF(m_pressPixel, pixel).normalized());
      }
      update();
      break;
    case Gesture::Pan:
      panBy(pixel - m_panLast);
      m_panLast = pixel;
      if (m_spaceHeld) m_spacePanned = true;
      break;
    case Gesture::Press:
      if ((pixel - m_pressPixel).manhattanLength() < 3) break;
      m_gesture = Gesture::Drag;
      [[fallthrough]];
    case Gesture::Drag:
      emit dragged(toMap(pixel));
      break;
    case Gesture::None:
      if (m_lensEnabled) setLensCenter(pixel);  // the lens follows the mouse until a press
      emit hovered(toMap(pixel), pixel);
      break;
  }
}

void MapView::mouseReleaseEvent(QMouseEvent* event) {
  if (m_gesture == Gesture::Pan) {
    if (event->button() == Qt::MiddleButton || event->button() == Qt::LeftButton) {
      m_gesture = Gesture::None;
      if (m_spaceHeld) {
        setCursor(Qt::OpenHandCursor);
      } else {
        unsetCursor();
      }
    }
    return;
  }
  if (m_gesture == Gesture::Select) {
    if (event->button() != Qt::RightButton) return;
    m_gesture = Gesture::None;
    QPolygonF polygon;
    if ((event->position() - m_pressPixel).manhattanLength() >= 3) {
      if (m_selectLasso) {
        m_selectDrawn << event->position();
      } else {
        m_selectDrawn = QPolygonF(QRectF(m_pressPixel, event->position()).normalized());
      }
      for (const QPointF& p : m_selectDrawn) {
        const Eigen::Vector2d m = toMap(p);
        polygon << QPointF(m.x(), m.y());
      }
    }
    m_selectDrawn.clear();
    update();
    emit selectionDrawn(polygon);
    return;
  }
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
  } else if (gesture == Gesture::Key) {
    emit keyClicked(toMap(event->position()), event->position());
  } else if (gesture == Gesture::Drag) {
    emit dragFinished();
  } else if (gesture == Gesture::Control) {
    const int control = m_control;
    m_control = -1;
    update();
    // A click without a move is no edit.
    if ((event->position() - m_pressPixel).manhattanLength() >= 2)
      emit controlPointMoved(control, toMap(clampToPlot(event->position())));
  }
}

void MapView::wheelEvent(QWheelEvent* event) {
  const double steps = event->angleDelta().y() / 120.0;
  if (m_lensEnabled) {
    setLensPower(m_lensPower * std::pow(1.25, steps));
  } else if (hasMap() && steps != 0.0) {
    zoomAt(event->position(), std::pow(1.25, steps));
  } else {
    return event->ignore();
  }
  event->accept();
}

void MapView::mouseDoubleClickEvent(QMouseEvent* event) {
  // A plain double-click shows the whole map; with a modifier, in sketch mode or on a control
  // point it is the second press of what those do.
  if (hasMap() && event->button() == Qt::LeftButton && event->modifiers() == Qt::NoModifier &&
      !m_sketchMode && !m_spaceHeld && controlPointAt(event->position()) < 0) {
    m_gesture = Gesture::None;
    resetView();
    return;
  }
  mousePressEvent(event);
}

void MapView::keyPressEvent(QKeyEvent* event) {
  if (event->key() == Qt::Key_Home && event->modifiers() == Qt::NoModifier && isZoomed()) {
    resetView();
    return;
  }
  QWidget::keyPressEvent(event);
}

bool MapView::wantsSpace() const {
  if (!hasMap() || !isVisible() || !window()->isActiveWindow()) return false;
  const QWidget* focus = QApplication::focusWidget();
  // A text or number field keeps Space (the transport bar's frame and time fields).
  if (qobject_cast<const QLineEdit*>(focus) || qobject_cast<const QAbstractSpinBox*>(focus))
    return false;
  return rect().contains(mapFromGlobal(QCursor::pos()));
}

bool MapView::eventFilter(QObject* watched, QEvent* event) {
  const QEvent::Type type = event->type();
  if (type != QEvent::ShortcutOverride && type != QEvent::KeyPress && type != QEvent::KeyRelease) {
    return QWidget::eventFilter(watched, event);
  }
  auto* key = static_cast<QKeyEvent*>(event);
  if (key->key() != Qt::Key_Space || key->modifiers() != Qt::NoModifier)
    return QWidget::eventFilter(watched, event);
  if (type == QEvent::KeyRelease) {
    if (!m_spaceHeld) return false;
    if (key->isAutoRepeat()) return true;
    m_spaceHeld = false;
    if (m_gesture != Gesture::Pan) unsetCursor();
    if (!m_spacePanned) emit spaceTapped();
    return true;
  }
  // ShortcutOverride (accepted: the window's Space shortcut does not fire) or the key press.
  if (!m_spaceHeld) {
    if (type != QEvent::ShortcutOverride || key->isAutoRepeat() || !wantsSpace()) return false;
    m_spaceHeld = true;
    m_spacePanned = false;
    if (m_gesture == Gesture::None) setCursor(Qt::OpenHandCursor);
  }
  event->accept();
  return true;
}

std::pair<Eigen::Vector2d, double> MapView::homeView() const {
  const QRectF area(rect());
  const render::MapPlotOptions shown = shownOptions();
  const QTransform home = render::map_transform(m_coords, area, shown);
  const QRectF data = render::data_area(area, shown);
  bool invertible = false;
  const QTransform back = home.inverted(&invertible);
  if (!invertible || home.m11() == 0.0) return {Eigen::Vector2d::Zero(), 1.0};
  const QPointF centre = back.map(data.center());
  return {Eigen::Vector2d(centre.x(), centre.y()), 0.5 * data.width() / std::abs(home.m11())};
}

QRectF MapView::viewExtent() const {
  const auto [home, half] = homeView();
  const Eigen::Vector2d c = m_viewCenter.value_or(home);
  const double h = half / m_zoom;
  return {c.x() - h, c.y() - h, 2 * h, 2 * h};
}

render::MapPlotOptions MapView::shownOptions() const {
  render::MapPlotOptions options = m_options;
  if (categoriesShown() && !m_density) {
    // Coloured by category: no clip or time legend under the plot (the Legend dock names the
    // values), in the layout, the transform and the painting alike.
    options.clip_names.clear();
    options.clip_time_ramp = false;
    options.time_legend = false;
  } else if (m_comparisonClip >= 0 && m_comparisonClip < options.clip_names.size()) {
    // The compared clip in the comparison's colour: its trajectory and its legend swatch.
    options.clip_colors.resize(std::size_t(options.clip_names.size()));
    options.clip_colors[std::size_t(m_comparisonClip)] = comparisonColor();
  }
  return options;
}

render::MapPlotOptions MapView::viewOptions() const {
  render::MapPlotOptions options = shownOptions();
  if (!isZoomed()) return options;
  options.extent = viewExtent();
  options.clip_to_frame = true;
  return options;
}

void MapView::viewMoved() {
  invalidate();
  update();
  emit viewChanged();
}

void MapView::zoomAt(const QPointF& pixel, double factor) {
  if (!hasMap() || !(factor > 0.0) || !std::isfinite(factor)) return;
  const double zoom = std::clamp(m_zoom * factor, 1.0, kMaxZoom);
  if (zoom == m_zoom) return;
  ensureTransform();
  const QPointF under = m_toMap.map(pixel);  // stays under the cursor
  const Eigen::Vector2d p(under.x(), under.y());
  const Eigen::Vector2d centre = m_viewCenter.value_or(homeView().first);
  m_viewCenter = p + (centre - p) * (m_zoom / zoom);
  m_zoom = zoom;
  viewMoved();
}

void MapView::panBy(const QPointF& delta) {
  if (!hasMap() || delta.isNull()) return;
  ensureTransform();
  const QPointF a = m_toMap.map(QPointF(0, 0)), b = m_toMap.map(delta);
  const Eigen::Vector2d centre = m_viewCenter.value_or(homeView().first);
  m_viewCenter = centre - Eigen::Vector2d(b.x() - a.x(), b.y() - a.y());
  viewMoved();
}

void MapView::resetView() {
  if (!isZoomed()) return;
  m_zoom = 1.0;
  m_viewCenter.reset();
  viewMoved();
}

void MapView::leaveEvent(QEvent*) {
  setHoverText({});
  emit left();
  if (m_gesture == Gesture::None && m_lensVisible) {
    m_lensVisible = false;
    update();
  }
}

}  // namespace motionmap::studio
