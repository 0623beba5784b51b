#pragma once
// Draws a map: every frame of a clip is a 2-D point, a clip is a trajectory coloured by time
// (red → yellow → green → cyan → blue from its first to its last frame). One painter serves the
// app (a widget's QPainter), the CLI (PNG/SVG/PDF files, no display needed) and figures (a grid
// of panels, e.g. one per embedding method). QtGui only, no QtWidgets.
//
// A library, not an application: it draws into the QPainter/QPaintDevice or the file it is given
// and leaves the process alone. Drawing (paint_map, save_map_plot, save_figure) needs a
// QGuiApplication (or QApplication), which the caller creates on the main thread before it draws
// (the CLI with the offscreen platform, Studio its QApplication); render never creates one, sets
// no environment variable and installs no message handler. The plain-data functions (colours,
// segments, transforms, layout) need none.
//
//   motionmap::render::MapPlotOptions options;
//   options.title = "Isomap";
//   options.notes = {"trustworthiness 0.93"};
//   motionmap::render::save_map_plot("map.png", coords, {}, options);
//
// Coordinates are "#samples by ≥ 2" matrices; only columns 0 (x, to the right) and 1 (y, up)
// are drawn. Rows with a non-finite x or y are gaps: no segment touches them.
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <QColor>
#include <QImage>
#include <QPainter>
#include <QPointF>
#include <QRectF>
#include <QString>
#include <QStringList>
#include <QTransform>

namespace motionmap::render {

/// Colour of time t ∈ [0, 1], the reference system's red → yellow → green → cyan → blue: the
/// "jet" ramp backwards, piecewise linear through dark red (0), red (1/8), yellow (3/8), cyan
/// (5/8), blue (7/8) and dark blue (1); green at 1/2. t outside [0, 1] is clamped; NaN gives gray.
QColor time_color(double t);

/// A distinct colour for clip `clip` of a map of several clips (Tableau 10, cycling; gray for a
/// negative index).
QColor clip_color(int clip);

/// The qualitative palette of categories (labels): kCategoryColors distinct colours, told apart
/// at a glance (Tableau 10 without its grey, navy, gold and near-black); category_color(c) for
/// c ≥ kCategoryColors cycles, and a negative c is the light grey of "other".
constexpr int kCategoryColors = 12;
QColor category_color(int category);
/// Which values of a label get a colour, given each value's number of samples (`counts[v]` for
/// value v): the values by count (most first, ties in value order), the first kCategoryColors
/// coloured — or kCategoryColors − 1 and the rest grey ("other") when there are more — and the
/// coloured ones numbered in value order, so colours follow the names, not the counts. Returns
/// each value's category for category_color() (0 … kCategoryColors − 1), or −1 for "other".
/// The one rule of `motionmap map --color-by` and Studio's Colour by.
std::vector<int> category_slots(std::span<const int> counts);
/// Clip `clip`'s colour (clip_color) shaded by time t ∈ [0, 1] within the clip: light (half-way to
/// white) at its first frame, the colour itself half-way, dark (40 % of the way to black) at its
/// last; t is clamped; NaN gives the colour itself. Each trajectory of a map of several clips
/// then shows which way its time runs.
QColor clip_time_color(int clip, double t);

/// How paint_map() draws a panel. Sizes are in the painter's units (pixels for images).
struct MapPlotOptions {
  QString title;             ///< printed above the panel (nothing when empty)
  QStringList notes;         ///< lines printed under the panel, e.g. quality metrics
  bool start_marker = true;  ///< black-outlined white circle on each clip's first frame
  bool draw_points = false;  ///< a dot on every sample, in its time colour
  bool time_legend = false;  ///< a red → blue "start … end" bar under the panel
  /// Non-empty: colour by clip — clip c's trajectory and dots in clip_color(c), and the legend
  /// (when time_legend is set) names the clips with their colours instead of the time bar.
  QStringList clip_names;
  /// Non-empty (one entry per sample): colour by category — each sample's dot, and the segment
  /// from it, in category_color(point_category[i]) (−1: grey, "other"), instead of time or
  /// clip; the legend (when time_legend is set) lists `categories` (entry c for category c, e.g.
  /// "walk (512)") with their colours, in rows as the panel's width allows.
  std::vector<int> point_category;
  QStringList categories;
  /// With categories: the legend's entry for −1 (e.g. "other (40)"); empty: none.
  QString other_category;
  /// With clip_names: each clip's trajectory and dots run light → dark in its colour over its
  /// time (clip_time_color) instead of one flat colour.
  bool clip_time_ramp = false;
  /// With clip_names, optional (one entry per clip, or fewer): a colour that clip c is drawn in
  /// flat — its trajectory, its dots and its legend swatch — in place of its own (e.g. a clip
  /// compared with another); an invalid entry keeps its own. See drawn_clip_color().
  std::vector<QColor> clip_colors;
  /// The legend's clip names, when too long, are cut at their end ("clip 2: …happy_0…") instead
  /// of in the middle: for names whose distinguishing part comes first (their common prefix
  /// removed, a number in front).
  bool legend_elide_right = false;
  double line_width = 2.0;        ///< trajectory pen width, clamped to [0, 100]; 0 is a hairline
  QColor background = Qt::white;  ///< fills the whole rect; an invalid colour leaves it as is
  /// Points drawn as dots under the trajectory ("#points by ≥ 2", columns 0 and 1), e.g. the
  /// samples of a saved map under new frames placed on it; the panel's extent covers them too.
  /// Non-finite rows are skipped.
  Eigen::MatrixXd backdrop;
  QColor backdrop_color = QColor(190, 190, 190);
  /// When valid (width and height ≥ 0, both finite): the data extent the panel frames — a box in
  /// map coordinates, x from left() to right(), y from top() to bottom() — in place of the
  /// extent of the coordinates and backdrop. For a trajectory drawn over a density_image() of a
  /// whole map, framed as the whole map.
  QRectF extent = QRectF(0, 0, -1, -1);
  /// The backdrop, trajectory, dots and start markers clipped to the panel's frame: for a zoomed
  /// view (an `extent` smaller than the data), so nothing is drawn over the title, legend or notes.
  bool clip_to_frame = false;
};

/// The colour paint_map() draws clip `clip` in at time t ∈ [0, 1] within it, with clip_names set:
/// options.clip_colors[clip] when given and valid, else clip_time_color(clip, t) with
/// clip_time_ramp, else clip_color(clip). The one rule of a clip's trajectory, dots and legend
/// swatch.
QColor drawn_clip_color(const MapPlotOptions& options, int clip, double t);

/// One piece of a trajectory, from sample `sample` to sample `sample + 1` of the same clip, in
/// unit-square coordinates (see data_to_unit()).
struct ColoredSegment {
  QPointF from;
  QPointF to;
  int sample = 0;     ///< row of `from` in the coordinate matrix
  int clip = 0;       ///< index of its clip (of segment_starts)
  double time = 0.0;  ///< the segment's midpoint time within its clip, in [0, 1]
  QColor color;       ///< time_color(time)
};

/// The similarity mapping from data (columns 0, 1 of `coords`) to the unit square [0,1]², y up:
/// equal scale on both axes, the bounding box of the finite samples centred, its longer side
/// spanning [0, 1]. With no finite sample or zero extent the scale is 1 (points land at 0.5).
QTransform data_to_unit(const Eigen::MatrixXd& coords);

/// `coords` with its first two columns scaled (about their centres) to the same extent, so a plot
/// fills its square panel on both axes, as the reference system draws its maps. Distances are no
/// longer to scale, but a map whose second axis is much shorter than its first (SVD, whose first
/// axis is the mean pose) shows its shape. Columns of zero extent are left as they are.
Eigen::MatrixXd fill_axes(const Eigen::MatrixXd& coords);

/// The coloured polyline of `coords` (#samples by ≥ 2) as plain data, in unit-square
/// coordinates: one segment per pair of consecutive finite samples of the same clip.
/// `segment_starts` lists the row where each clip starts, strictly increasing, in
/// [0, #samples); row 0 always starts a clip; empty means one clip. Linear in #samples.
/// @throws ParameterError if coords has < 2 columns or segment_starts is invalid.
std::vector<ColoredSegment> trajectory_segments(const Eigen::MatrixXd& coords,
                                                const std::vector<int>& segment_starts);

/// The square data area paint_map() uses inside `rect`: what is left after the title, notes and
/// legend, centred, with a margin; the frame box surrounds it.
QRectF data_area(const QRectF& rect, const MapPlotOptions& options = {});

/// Unit square (y up) → painter coordinates for a panel drawn in `rect`: maps [0,1]² onto
/// data_area(rect, options), flipping y. Use it to place cached trajectory_segments().
QTransform unit_transform(const QRectF& rect, const MapPlotOptions& options = {});

/// Data → painter coordinates exactly as paint_map(painter, rect, coords, …, options) draws:
/// data_to_unit(coords) * unit_transform(rect, options), with the extent of options.backdrop
/// included in data_to_unit's when there is one. `map_transform(...).inverted().map(mouse)`
/// gives the map coordinates under a mouse position (invertible as long as the data's extent is
/// below 10⁶ × the data area's side in pixels: Qt's fuzzy determinant test).
QTransform map_transform(const Eigen::MatrixXd& coords, const QRectF& rect,
                         const MapPlotOptions& options = {});

/// A 2-D histogram of `points` (#points by ≥ 2, columns 0 and 1) as an image of `size` pixels:
/// each point falls in the pixel `data_to_pixel` maps it to (points outside the image and
/// non-finite rows are skipped); a pixel holding c > 0 points is `ink` at opacity
/// 0.12 + 0.88 · log(1 + c) / log(1 + max c), others transparent (so it lies over any
/// background). A map of millions of points drawn in one pass: O(#points + #pixels).
/// Format_ARGB32_Premultiplied; a null image for an empty size.
/// @throws ParameterError if points has < 2 columns.
QImage density_image(const Eigen::MatrixXd& points, const QTransform& data_to_pixel,
                     const QSize& size, const QColor& ink = QColor(40, 50, 90));

/// The same histogram coloured by category: `categories` (one per point) gives each point's
/// colour (category_color(); −1: "other", grey), and a pixel is the mean colour of its points at
/// density_image()'s opacity for their count; a category below −1 leaves its point out (hidden).
/// For a map of a library coloured by a label (Studio's saved maps).
/// @throws ParameterError if points has < 2 columns or categories is not one per point.
QImage category_density_image(const Eigen::MatrixXd& points, const std::vector<int>& categories,
                              const QTransform& data_to_pixel, const QSize& size);

/// Draws one panel into `rect`: background, title on top, a square data area with a thin frame,
/// the backdrop's dots, the trajectory coloured by each clip's own time, start markers, notes at
/// the bottom.
/// Degenerate input (no/one sample, identical samples, NaN rows) draws what remains.
/// Needs a QGuiApplication (text does). Linear in #samples.
/// @throws ParameterError if coords (or a non-empty backdrop) has < 2 columns or segment_starts
///   is invalid.
/// @throws Error if no QGuiApplication exists (nothing is drawn).
void paint_map(QPainter& painter, const QRectF& rect, const Eigen::MatrixXd& coords,
               const std::vector<int>& segment_starts, const MapPlotOptions& options);

/// Writes one panel to `path`, size_px × size_px, format from the extension (case-insensitive):
/// .png (antialiased), .svg, .pdf (one square page, size_px at 96 dpi). Needs a
/// QGuiApplication.
/// @throws ParameterError if size_px is outside [16, 16384] or coords/segment_starts are invalid.
/// @throws Error naming the path and the reason on an unknown extension or a write failure.
/// @throws Error if no QGuiApplication exists (nothing is written).
void save_map_plot(const std::string& path, const Eigen::MatrixXd& coords,
                   const std::vector<int>& segment_starts, const MapPlotOptions& options,
                   int size_px = 800);

/// One panel of a figure: the arguments of paint_map().
struct FigurePanel {
  Eigen::MatrixXd coords;
  std::vector<int> segment_starts;
  MapPlotOptions options;
};

/// Writes panels in a grid of `columns` columns (row by row), each panel_px wide with its title
/// and notes, under a figure title and a time legend (or, when the first panel has categories or
/// clip names, their legend). Formats as save_map_plot(). Needs a
/// QGuiApplication.
/// @throws ParameterError if panels is empty, columns is outside [1, 64], panel_px outside
///         [64, 4096], the figure would exceed 10⁸ pixels, or a panel's data is invalid.
/// @throws Error naming the path and the reason on an unknown extension or a write failure.
/// @throws Error if no QGuiApplication exists (nothing is written).
void save_figure(const std::string& path, const std::vector<FigurePanel>& panels, int columns = 3,
                 int panel_px = 500, const QString& title = {});

}  // namespace motionmap::render
