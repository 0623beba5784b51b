#pragma once
// The map view: the trajectory drawn by render::paint_map (cached as a pixmap, so a frame's
// repaint costs one blit plus the pointer), a white pointer at the current frame, a hover text,
// and the mouse gestures the main window turns into library calls:
//  - left click             → clicked(map point)
//  - left drag              → dragged(map point) while the mouse moves
//  - Shift + left drag      → a sketch path, sketchFinished(path) on release (times in seconds)
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <QElapsedTimer>
#include <QPixmap>
#include <QWidget>

#include "motionmap/render/map_plot.h"
#include "motionmap/synth/path.h"

namespace motionmap::studio {

class MapView : public QWidget {
  Q_OBJECT
 public:
  explicit MapView(QWidget* parent = nullptr);

  /// Shows `coords` (#samples by ≥ 2, copied) with the clip starts and plot options.
  void setMap(const Eigen::MatrixXd& coords, const std::vector<int>& segmentStarts,
              const render::MapPlotOptions& options);
  /// Removes the map (shows a hint text instead).
  void clearMap(const QString& hint = {});
  bool hasMap() const { return m_coords.rows() > 0; }
  /// The pointer's map position (nothing hides it).
  void setPointer(const std::optional<Eigen::Vector2d>& point);
  std::optional<Eigen::Vector2d> pointer() const { return m_pointer; }
  /// Text drawn in the top-left corner (e.g. "frame 120" under the mouse).
  void setHoverText(const QString& text);
  QString hoverText() const { return m_hoverText; }

  /// Map coordinates → widget pixels, exactly as the map is painted (render::map_transform).
  QPointF toWidget(const Eigen::Vector2d& point) const;
  /// Widget pixels → map coordinates.
  Eigen::Vector2d toMap(const QPointF& pixel) const;
  /// The sketch being drawn (empty when none).
  const synth::MapPath& sketch() const { return m_sketch; }

 signals:
  void hovered(const Eigen::Vector2d& point, const QPointF& pixel);
  void clicked(const Eigen::Vector2d& point, const QPointF& pixel);
  void dragged(const Eigen::Vector2d& point);
  void dragFinished();
  void sketchFinished(const motionmap::synth::MapPath& path);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void leaveEvent(QEvent* event) override;

 private:
  enum class Gesture { None, Press, Drag, Sketch };
  void addSketchPoint(const QPointF& pixel);

  Eigen::MatrixXd m_coords;
  std::vector<int> m_segmentStarts;
  render::MapPlotOptions m_options;
  QString m_hint;
  QPixmap m_cache;  ///< the painted trajectory at the current size; null when stale
  std::optional<Eigen::Vector2d> m_pointer;
  QString m_hoverText;
  Gesture m_gesture = Gesture::None;
  QPointF m_pressPixel;
  synth::MapPath m_sketch;
  QElapsedTimer m_sketchClock;
};

}  // namespace motionmap::studio
