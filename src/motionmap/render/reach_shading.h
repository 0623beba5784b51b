#pragma once
// Where a map point lies within a distance r of some sample of a map — the one rule of where a
// drag or sketch blends real frames (synth::reach_radius(); Studio's "Shade trustworthy blends")
// — drawn per pixel of a view at any zoom, on maps of millions of samples. Plain data and QtGui
// images: no painter, no QGuiApplication.
//
// A ReachField is built once per map and reach: the samples rasterized into a grid over the map
// (at most `cells` a side) and an exact Euclidean distance transform of it (Felzenszwalb and
// Huttenlocher's lower envelope of parabolas, O(cells)). Snapping a sample to its cell's centre,
// and a point to its cell's, moves a distance by at most one cell diagonal h·√2, so a cell whose
// distance is more than that below r is wholly within reach, one more than that above r wholly
// outside, and only the thin band between is unsure. reach_image() decides every pixel of a view
// from the field and asks `within` — an exact test, e.g. a k-d tree's nearest distance — only for
// the pixels in that band: the result is exactly "the map point at the pixel's centre is within r
// of a sample", whatever the zoom, at O(pixels) plus a few exact queries along the edge.
//
//   motionmap::render::ReachField field(points, r);
//   QImage shade = motionmap::render::reach_image(field, pixel_to_map, size, green,
//                                                 [&](const Eigen::Vector2d& p) {
//                                                   return index.nearest(p).distance <= r; });
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <QColor>
#include <QImage>
#include <QRect>
#include <QSize>
#include <QTransform>

namespace motionmap::render {

class ReachField {
 public:
  /// Where a point lies for certain, or that the exact test must say.
  enum class Side : std::uint8_t { Outside = 0, Inside = 1, Unsure = 2 };

  /// An empty field: every point Outside.
  ReachField() = default;
  /// The first two columns of `points` (non-finite rows left out) and the reach `reach` (map
  /// units): a grid over the samples' box grown by the reach, at most `cells` cells along its
  /// longer side. No sample, reach ≤ 0 (or not finite), or a box too wide for a double: an
  /// empty field.
  /// @throws ParameterError if points has fewer than 2 columns or cells < 16.
  ReachField(const Eigen::MatrixXd& points, double reach, int cells = 2048);

  /// Where a smooth function `value` of the map point is at most `threshold` (a GP-LVM map's
  /// predictive variance and its rule, embed::GplvmMap::inside): a grid over the box `lo`–`hi`
  /// (points off it are Outside: the caller's box must hold every point where value ≤
  /// threshold), at most `cells` cells along its longer side, `value` taken at every cell
  /// corner (in parallel); a cell is Inside when its four corners are below threshold ×
  /// (1 − `margin`), Outside when above threshold × (1 + `margin`), else Unsure; level()
  /// interpolates the corners' values bilinearly, for the Unsure cells' pixels. Unlike the
  /// distance field this is exact only at the corners: it trusts `value` to be nearly bilinear
  /// within a cell (true when cells are well below the function's lengthscale). reach() is
  /// `threshold`.
  /// @throws ParameterError if cells < 16, margin is not in [0, 1) or the box is not finite.
  static ReachField level_set(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int cells,
                              const std::function<double(const Eigen::Vector2d&)>& value,
                              double threshold, double margin);

  double reach() const { return m_reach; }
  /// A level_set field's value at map point (x, y): its corners' values interpolated
  /// bilinearly; +∞ off the grid or for a distance field.
  double level(double x, double y) const;
  bool empty() const { return m_nx == 0; }
  /// The side of a cell (map units).
  double cell() const { return m_cell; }
  int nx() const { return m_nx; }
  int ny() const { return m_ny; }

  /// Where map point (x, y) lies: Inside (within reach() of a sample for certain), Outside
  /// (farther from every sample for certain), or Unsure (within a cell's diagonal of the edge).
  Side side(double x, double y) const {
    const double gx = (x - m_origin.x()) * m_inv_cell, gy = (y - m_origin.y()) * m_inv_cell;
    if (!(gx >= 0.0 && gy >= 0.0 && gx < m_nx && gy < m_ny)) return Side::Outside;
    return Side(m_side[std::size_t(int(gy)) * std::size_t(m_nx) + std::size_t(int(gx))]);
  }

 private:
  friend QImage reach_image(const ReachField&, const QTransform&, const QSize&, const QColor&,
                            const std::function<bool(const Eigen::Vector2d&)>&, const QRect&);
  double m_reach = 0.0;
  double m_cell = 0.0, m_inv_cell = 0.0;
  Eigen::Vector2d m_origin = Eigen::Vector2d::Zero();  ///< corner of cell (0, 0)
  int m_nx = 0, m_ny = 0;
  std::vector<std::uint8_t> m_side;  ///< per cell (index y·nx + x): a Side
  std::vector<double> m_level;       ///< level_set: per corner (index y·(nx + 1) + x)
};

/// An image of `size` (Format_ARGB32_Premultiplied): `color` (opaque) at every pixel (i, j) of
/// `clip` (the whole image when empty; clipped to it) whose centre's map point,
/// pixel_to_map.map((i + 0.5, j + 0.5)), lies within the field's reach of a sample, transparent
/// elsewhere. The field decides most pixels; `within(map point)` is asked for the rest (the
/// field's Unsure band) and must be the exact rule (distance to the nearest sample ≤ reach). An
/// empty field or a non-invertible map: all transparent.
QImage reach_image(const ReachField& field, const QTransform& pixel_to_map, const QSize& size,
                   const QColor& color, const std::function<bool(const Eigen::Vector2d&)>& within,
                   const QRect& clip = QRect());

}  // namespace motionmap::render
