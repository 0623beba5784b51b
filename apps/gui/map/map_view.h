#pragma once
// The map view: the trajectory drawn by render::paint_map (cached as a pixmap at the widget's
// size, with the data → pixel transform, so a frame's repaint costs one blit plus the pointer,
// whatever the trajectory's length), a white pointer at the current frame, a hover text, a
// magnifying lens, and the mouse gestures the main window turns into library calls:
//  - left click                          → clicked(map point)
//  - left drag                           → dragged(map point) while the mouse moves
//  - Shift + left drag, or any left drag
//    in sketch mode                      → a sketch path, sketchFinished(path) on release
//                                          (times in seconds, from the gesture's own clock)
//  - left drag on a control point of the
//    current take (setTakePaths)         → it follows the mouse, controlPointMoved on release
//  - Ctrl + left click                   → keyClicked(map point): a key pose added or removed
//  - right drag                          → a box, Shift + right drag → a lasso:
//                                          selectionDrawn(polygon in map coordinates) on release;
//                                          a right click without a drag → selectionDrawn({})
// A sketch or a control point dragged outside the plot (plotRect) stays on its edge, where the
// stroke is drawn: nothing is sketched where the map is not shown.
// The takes' paths stay drawn over the map (orange; the current one solid with its control points,
// the others thinner and translucent, each named at its end).
// The magnifier is a fisheye lens (Sarkar & Brown's g(x) = (d + 1)·x / (d·x + 1) on the distance
// to its centre, within its radius) that follows the mouse while no button is down and stays put
// during a press, so frames that overlap at the map's scale can be told apart and dragged over
// slowly; the wheel changes its power d. Every map ↔ pixel conversion (toWidget, toMap) goes
// through the lens, so hover, click, drag and sketch work inside it.
// Zoom and pan: the wheel zooms around the cursor (with the magnifier on, the wheel sets its power
// instead), a middle-button drag or a left drag with Space held pans, Home (while the map has the
// keyboard focus and is zoomed) or a double-click resets. The view is a square of the map
// (viewExtent) drawn through render::paint_map's extent, clipped to the plot's frame, and the
// density image is binned again at the zoomed transform, so it stays sharp. Every conversion
// (toWidget, toMap) includes the view, so every gesture lands where the mouse is.
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <QElapsedTimer>
#include <QPixmap>
#include <QPolygonF>
#include <QTransform>
#include <QWidget>

#include "motionmap/embed/gplvm.h"
#include "motionmap/render/map_plot.h"
#include "motionmap/render/reach_shading.h"
#include "motionmap/synth/path.h"
#include "motionmap/synth/point_index.h"
#include "takes/takes.h"

namespace motionmap::studio {

class MapView : public QWidget {
  Q_OBJECT
 public:
  explicit MapView(QWidget* parent = nullptr);

  /// A take's path as drawn (map coordinates).
  struct TakePath {
    QString name;
    std::vector<Eigen::Vector2d> points;
    std::vector<int> controls;  ///< indices into points: drawn and draggable (current take only)
    bool current = false;
    bool keyed = false;  ///< an in-between take: its controls are its keys, drawn numbered
  };
  /// How close (pixels) a press must be to a control point to drag it.
  static constexpr double kControlPickPixels = 9.0;
  /// The colour of the current take's path (the others are drawn in it, translucent): violet, in
  /// neither the time ramp (red → blue) nor the clips' palette (render::clip_color).
  static QColor takeColor() { return QColor(120, 0, 170); }
  /// The colour of highlighted points (setHighlight): magenta, in neither either.
  static QColor highlightColor() { return QColor(255, 0, 170); }
  /// Points drawn highlighted (#points by ≥ 2, map coordinates; e.g. the clips a search matches):
  /// each a 3 × 3 px mark, over the density image and under a saved map's trajectory (over a
  /// computed map's), within the plot. An empty matrix: none. setMap, setDensityMap and clearMap
  /// remove them (mapReplaced() says so).
  void setHighlight(const Eigen::MatrixXd& points);
  const Eigen::MatrixXd& highlight() const { return m_highlight; }
  /// The colour of selected points (setSelection): spring green.
  static QColor selectionColor() { return QColor(0, 215, 110); }
  /// The selected points (#points by ≥ 2) drawn as highlighted ones are, in selectionColor(), and
  /// the outline they were selected with (map coordinates; empty: none), dashed. Removed with
  /// the map, as the highlight.
  void setSelection(const Eigen::MatrixXd& points, const QPolygonF& outline);
  const Eigen::MatrixXd& selection() const { return m_selection; }
  const QPolygonF& selectionOutline() const { return m_selectionOutline; }
  /// The colour of a compared clip (setComparison): teal, in neither the time ramp's ends nor the
  /// takes', highlight's or selection's colours.
  static QColor comparisonColor() { return QColor(0, 140, 150); }
  /// A clip compared with the one playing: its trajectory (#frames by ≥ 2, map coordinates)
  /// drawn over the map in comparisonColor(), and its frame's point as a ring in that colour
  /// (nothing: none). An empty trajectory: no comparison. setMap, setDensityMap and clearMap
  /// remove it.
  /// `clip`: the compared clip's index in the map's clip legend (−1: not one of them); that clip
  /// is drawn in comparisonColor() under the ring, its trajectory and its legend swatch alike
  /// (see clipColor).
  void setComparison(const Eigen::MatrixXd& trajectory, const std::optional<Eigen::Vector2d>& point,
                     int clip = -1);
  /// The clip being compared (setComparison), or −1.
  int comparisonClip() const { return m_comparisonClip; }
  /// The colour clip `clip` of a map of several clips is drawn in at time t ∈ [0, 1] within it —
  /// its trajectory, under the magnifier too, and its legend swatch: render::drawn_clip_color of
  /// the options shown (comparisonColor() for the compared clip).
  QColor clipColor(int clip, double t) const;
  const Eigen::MatrixXd& comparisonTrajectory() const { return m_comparison; }
  std::optional<Eigen::Vector2d> comparisonPoint() const { return m_comparisonPoint; }
  /// The takes drawn over the map (replacing those before).
  void setTakePaths(std::vector<TakePath> paths);
  const std::vector<TakePath>& takePaths() const { return m_takes; }
  /// Keys placed before there are two to in-between (drawn numbered, in order); empty: none.
  void setPendingKeys(std::vector<Eigen::Vector2d> keys);
  const std::vector<Eigen::Vector2d>& pendingKeys() const { return m_pendingKeys; }
  /// The index of the current take's control point within kControlPickPixels of `pixel`, or −1.
  int controlPointAt(const QPointF& pixel) const;
  /// The control point being dragged (−1: none).
  int draggedControlPoint() const { return m_gesture == Gesture::Control ? m_control : -1; }

  /// Shows `coords` (#samples by ≥ 2, copied) with the clip starts and plot options.
  void setMap(const Eigen::MatrixXd& coords, const std::vector<int>& segmentStarts,
              const render::MapPlotOptions& options);
  /// A saved map of many points: `points` (#points by ≥ 2, shared, not copied) drawn as a density
  /// image (render::density_image: a log-scaled 2-D histogram binned once per size into an image),
  /// framed as a whole, with `trajectory` — the current clip's rows — drawn over it red → blue
  /// (and the pointer on top). setMap() afterwards replaces both.
  void setDensityMap(std::shared_ptr<const Eigen::MatrixXd> points,
                     const Eigen::MatrixXd& trajectory, const render::MapPlotOptions& options);
  /// The category of a sample that is hidden (setSampleCategories): not drawn, not picked.
  static constexpr int kHiddenCategory = -2;
  /// Colours the map's samples by category — one entry per sample: a computed map's rows
  /// (setMap), a saved map's density points (setDensityMap) — each in render::category_color(c)
  /// (the CLI's palette; −1: the grey of "other"), or kHiddenCategory: left out of the drawing
  /// (and of hover, click, nearest and selection, which ask sampleShown). A computed map's
  /// trajectory is drawn in its samples' colours, framed as the whole map; a saved map's density
  /// image mixes the colours of each pixel's samples (render::category_density_image). Empty, or a
  /// count that is not the map's: the map's own colours. setMap, setDensityMap and clearMap remove
  /// them.
  void setSampleCategories(std::vector<int> categories);
  const std::vector<int>& sampleCategories() const { return m_categories; }
  /// Whether the samples are coloured by category (setSampleCategories, of the map shown).
  bool categoriesShown() const;
  /// Whether sample `sample` is drawn: false for a hidden one (and out of range).
  bool sampleShown(int sample) const;
  /// Whether some sample is hidden.
  bool hidesSamples() const { return m_hidden > 0; }
  /// Replaces the trajectory over the density image (another clip of the saved map).
  void setTrajectory(const Eigen::MatrixXd& trajectory);
  bool hasDensity() const { return m_density != nullptr; }
  /// The density image at the widget's size (binned when stale); null without a density map.
  const QImage& densityImage() const;
  /// Removes the map (shows a hint text instead).
  void clearMap(const QString& hint = {});
  bool hasMap() const { return m_coords.rows() > 0 || m_density != nullptr; }
  /// The map's points drawn (the trajectory: #samples by 2; empty without a map).
  const Eigen::MatrixXd& coordinates() const { return m_coords; }
  /// The pointer's map position (nothing hides it).
  void setPointer(const std::optional<Eigen::Vector2d>& point);
  std::optional<Eigen::Vector2d> pointer() const { return m_pointer; }
  /// A line drawn over the map shown, which is greyed behind it (e.g. "Computing the Isomap
  /// map…" while the map before stays on screen until a new one replaces it); empty: none.
  /// setMap and clearMap remove it.
  void setBusyText(const QString& text);
  QString busyText() const { return m_busyText; }
  /// Text drawn in the top-right corner (e.g. "frame 120" under the mouse).
  void setHoverText(const QString& text);
  QString hoverText() const { return m_hoverText; }

  /// Map coordinates → widget pixels, exactly as the map is painted (render::map_transform, then
  /// the lens when it is shown).
  QPointF toWidget(const Eigen::Vector2d& point) const;
  /// Widget pixels → map coordinates (the inverse of toWidget).
  Eigen::Vector2d toMap(const QPointF& pixel) const;
  /// The sketch being drawn (empty when none).
  const synth::MapPath& sketch() const { return m_sketch; }
  const render::MapPlotOptions& plotOptions() const { return m_options; }

  /// Sketch mode: a plain left drag sketches (as Shift-drag always does).
  void setSketchMode(bool on);
  bool sketchMode() const { return m_sketchMode; }

  /// Trustworthy-blend shading: a translucent green over every map point within `reach` (map
  /// units) of a sample — a computed map's points (setMap), a saved map's density points
  /// (setDensityMap): the blender's reach_distance(), synth::reach_radius()'s one rule of where
  /// a blend is inside the data (beyond it, a drag is moved to its edge and a sketch plays the
  /// clips' own frames: synth/detail/outside_route.h). One way for both kinds of map, exact at
  /// each pixel's centre at any zoom: render::ReachField (built
  /// once per map and reach) decides most pixels of the view, `index`'s nearest distance the
  /// thin band along the edge (render::reach_image); without an index the view builds one over
  /// the samples when the shading is first drawn. Drawn into the cached picture, clipped to
  /// plotRect(), and under the magnifier at its magnification, with a key in the plot's
  /// lower-left corner. 0: no shading (no blender). With `gplvm` (a GP-LVM map's GP, its
  /// blender's synth::BlendOptions::gplvm) the shading is the GP's rule instead
  /// (embed::GplvmMap::inside): render::ReachField::level_set of its variance over the GP's
  /// basis decides most pixels, the exact variance the band along the edge.
  void setShadingReach(double reach, std::shared_ptr<const synth::PointIndex> index = {},
                       std::shared_ptr<const MapGp> gplvm = {});
  double shadingReach() const { return m_shadingReach; }
  void setShadingVisible(bool on);
  bool shadingVisible() const { return m_shadingVisible; }
  /// Whether there is a shading to show (a map and a reach).
  bool shadingAvailable() const { return hasMap() && m_shadingReach > 0.0; }
  /// The shading of the current view, as drawn under the magnifier-free picture: an image of the
  /// widget's size in device pixels, opaque green at every pixel of plotRect() whose centre's
  /// map point lies within the reach of a sample, transparent elsewhere (drawn at 30 %). Null
  /// when !shadingAvailable().
  QImage shadingLayer() const;
  /// The shading's radius in pixels (0 without a map).
  double shadingRadius() const;
  /// The plot's frame in widget pixels (render::data_area with its margin): the trajectory,
  /// shading and key lie inside it; the title above, the colour bar and notes below.
  QRectF plotRect() const;
  /// The text of the tooltip at `pixel`: every note of the plot in full (render::paint_map elides
  /// a note wider than the panel) when the pixel is below the plot (colour bar and notes); empty
  /// elsewhere or without notes.
  QString noteToolTip(const QPointF& pixel) const;

  /// The magnifier: on/off, its centre (widget pixels; the mouse moves it), power d ∈ [0.5, 30]
  /// (magnification d + 1 at the centre) and radius in pixels.
  void setLensEnabled(bool on);
  bool lensEnabled() const { return m_lensEnabled; }
  void setLensCenter(const QPointF& center);
  QPointF lensCenter() const { return m_lensCenter; }
  void setLensPower(double power);
  double lensPower() const { return m_lensPower; }
  double lensRadius() const;
  /// Whether the lens is drawn (enabled, over the widget, with a map).
  bool lensShown() const { return m_lensEnabled && m_lensVisible && hasMap(); }

  /// The most the view zooms in (times the whole map's scale).
  static constexpr double kMaxZoom = 10000.0;
  /// The zoom: 1 shows the whole map as the plot options frame it; more is closer.
  double zoom() const { return m_zoom; }
  /// Whether the view was zoomed or panned (resetView() undoes it).
  bool isZoomed() const { return m_viewCenter.has_value(); }
  /// The map square the plot shows (map coordinates, x from left() to right(), y from top() to
  /// bottom()); the whole map's when not zoomed.
  QRectF viewExtent() const;
  /// Zooms by `factor` (clamped to [1, kMaxZoom] overall), the map point under `pixel` staying
  /// under it.
  void zoomAt(const QPointF& pixel, double factor);
  /// Moves the map by `delta` pixels (as a pan drag does).
  void panBy(const QPointF& delta);
  /// Shows the whole map again.
  void resetView();

 signals:
  void hovered(const Eigen::Vector2d& point, const QPointF& pixel);
  void clicked(const Eigen::Vector2d& point, const QPointF& pixel);
  void dragged(const Eigen::Vector2d& point);
  void dragFinished();
  void sketchFinished(const motionmap::synth::MapPath& path);
  /// A control point of the current take was dragged to `point` (map coordinates).
  void controlPointMoved(int control, const Eigen::Vector2d& point);
  /// Ctrl + left click at `point` (map coordinates; `pixel` in the widget).
  void keyClicked(const Eigen::Vector2d& point, const QPointF& pixel);
  /// The view was zoomed, panned or reset.
  void viewChanged();
  /// The mouse left the view.
  void left();
  /// Another map (or none) is shown: setMap, setDensityMap or clearMap.
  void mapReplaced();
  /// A box (4 corners) or lasso drawn with the right button, in map coordinates; empty for a
  /// right click without a drag (clear the selection).
  void selectionDrawn(const QPolygonF& polygon);
  /// Space was pressed and released over the map without panning: the window's play/pause key,
  /// which the map holds back while Space is down (Space + drag pans).
  void spaceTapped();

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void leaveEvent(QEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  bool event(QEvent* event) override;
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  enum class Gesture { None, Press, Drag, Sketch, Control, Key, Pan, Select };
  /// m_options as shown: without the clip or time legend while coloured by category.
  render::MapPlotOptions shownOptions() const;
  /// shownOptions() with the zoomed view's extent (clipped to the frame); as they are when not
  /// zoomed.
  render::MapPlotOptions viewOptions() const;
  /// The whole map's square: its centre and half side (map units), as m_options frame it.
  std::pair<Eigen::Vector2d, double> homeView() const;
  /// The view changed: transforms, the cached picture and the density image are redone.
  void viewMoved();
  /// Whether Space pressed now belongs to the map (the mouse over it, no text field focused).
  bool wantsSpace() const;
  void paintTakes(QPainter& painter) const;
  /// The compared clip's trajectory and ring (setComparison).
  void paintComparison(QPainter& painter) const;
  /// A key marker: a numbered disc at `pixel`.
  static void paintKey(QPainter& painter, const QPointF& pixel, int number, bool pending);
  void addSketchPoint(const QPointF& pixel);
  /// `pixel` moved onto plotRect() (unchanged inside it).
  QPointF clampToPlot(const QPointF& pixel) const;
  /// Recomputes the data ↔ pixel transforms (and the trajectory in pixels) when stale.
  void ensureTransform() const;
  void invalidate();
  QPointF lens(const QPointF& pixel) const;    ///< undistorted → shown
  QPointF unlens(const QPointF& pixel) const;  ///< shown → undistorted
  void paintLens(QPainter& painter) const;
  /// The shading (shadingLayer) at its opacity, into the cached picture.
  void paintShading(QPainter& painter) const;
  /// The shading's key, inside the plot's lower-left corner.
  void paintShadingKey(QPainter& painter) const;
  /// The shading under the lens: each pixel of the lens's disc decided at the map point it
  /// shows (`bounds`: the lens's box).
  void paintLensShading(QPainter& painter, const QRectF& bounds) const;
  /// The reach field and the nearest-sample index of the shading's samples, built when stale.
  void ensureReachField() const;
  /// The exact rule: the nearest sample of map point `p` lies within the reach (on a GP-LVM map:
  /// the GP's variance at p is within its threshold).
  bool withinReach(const Eigen::Vector2d& p) const;
  /// `points` as 3 × 3 px marks in `color`, into the cached picture (clipped to the plot).
  void paintMarks(QPainter& painter, const Eigen::MatrixXd& points, const QColor& color) const;
  /// The selection's outline (or the one being drawn) in widget pixels.
  QPolygonF selectionPixels() const;
  /// The computed map's trajectory (paint_map), coloured by category when categoriesShown():
  /// hidden samples left out as gaps, framed as the whole map.
  void paintTrajectory(QPainter& painter, const render::MapPlotOptions& options) const;
  /// The density image of `points` at `toPixel` and `size`: by category when categoriesShown().
  QImage density(const QTransform& toPixel, const QSize& size) const;
  /// The busy text over the greyed map (see setBusyText).
  void paintBusy(QPainter& painter) const;

  Eigen::MatrixXd m_coords;
  std::vector<int> m_segmentStarts;
  std::shared_ptr<const Eigen::MatrixXd> m_density;  ///< a saved map's points, or none
  std::vector<int> m_categories;                     ///< per sample (setSampleCategories)
  Eigen::Index m_hidden = 0;                         ///< samples of kHiddenCategory
  mutable QImage m_densityImage;                     ///< binned at m_densitySize; null when stale
  mutable QSize m_densitySize;
  render::MapPlotOptions m_options;
  QString m_hint;
  QPixmap m_cache;  ///< the painted trajectory at the current size; null when stale
  /// A density map's marks and trajectory over its density image (transparent elsewhere), at
  /// m_cache's size; null when stale. A legend click composes the picture again from it.
  QImage m_overLayer;
  // Cached with the size they were computed for (mutable: filled lazily by const conversions).
  mutable QSize m_transformSize;
  mutable bool m_transformValid = false;
  mutable QTransform m_toWidget, m_toMap;
  mutable std::vector<render::ColoredSegment> m_pixelSegments;  ///< the trajectory in pixels
  std::optional<Eigen::Vector2d> m_pointer;
  QString m_hoverText;
  Gesture m_gesture = Gesture::None;
  QPointF m_pressPixel;
  synth::MapPath m_sketch;
  std::vector<TakePath> m_takes;
  int m_control = -1;               ///< the control point being dragged
  synth::MapPath m_controlPreview;  ///< the current take's path as it follows the drag
  QElapsedTimer m_sketchClock;
  bool m_sketchMode = false;
  std::vector<Eigen::Vector2d> m_pendingKeys;
  double m_shadingReach = 0.0;  ///< map units (setShadingReach)
  /// The shading's exact nearest-sample index (given, or built over the samples) and its field.
  mutable std::shared_ptr<const synth::PointIndex> m_shadingIndex;
  mutable std::shared_ptr<const render::ReachField> m_reachField;
  std::shared_ptr<const MapGp> m_shadingGplvm;  ///< a GP-LVM map's rule (setShadingReach)
  QString m_busyText;
  bool m_shadingVisible = false;
  bool m_lensEnabled = false;
  bool m_lensVisible = false;
  QPointF m_lensCenter;
  double m_lensPower = 3.0;
  Eigen::MatrixXd m_comparison;  ///< setComparison's trajectory (#frames by 2)
  std::optional<Eigen::Vector2d> m_comparisonPoint;
  int m_comparisonClip = -1;     ///< setComparison's clip
  Eigen::MatrixXd m_highlight;   ///< setHighlight's points (#points by 2)
  Eigen::MatrixXd m_selection;   ///< setSelection's points
  QPolygonF m_selectionOutline;  ///< map coordinates
  QPolygonF m_selectDrawn;       ///< the box's corners or the lasso being drawn, in pixels
  bool m_selectLasso = false;
  double m_zoom = 1.0;
  std::optional<Eigen::Vector2d> m_viewCenter;  ///< the zoomed view's centre; none: the whole map
  QPointF m_panLast;                            ///< the last mouse position of a pan
  bool m_spaceHeld = false;                     ///< Space is down over the map
  bool m_spacePanned = false;                   ///< a pan happened while Space was down
};

}  // namespace motionmap::studio
